// bspline.h: partition of unity, clamped ends, periodic closure, and a fit
// that reproduces a curve the spline space holds.
#include "ideal_curve/bspline.h"

#include <gtest/gtest.h>

#include <random>

namespace developable {
namespace {

TEST(BSpline, BasisIsAPartitionOfUnity) {
  std::mt19937 random(1);
  std::uniform_real_distribution<double> t(-0.5, 1.5);
  for (int n : {4, 5, 9, 16})
    for (bool closed : {false, true})
      for (int i = 0; i < 200; ++i) {
        double b[4];
        const int first = bspline_basis(n, closed, t(random), b);
        EXPECT_GE(first, 0);
        EXPECT_LT(first, n);
        EXPECT_NEAR(b[0] + b[1] + b[2] + b[3], 1.0, 1e-14);
        for (double v : b) EXPECT_GE(v, -1e-15);
      }
}

TEST(BSpline, OpenSplineStartsAndEndsAtItsEndControlPoints) {
  BSpline s;
  for (int i = 0; i < 7; ++i) s.ctrl.emplace_back(i, (i * 37) % 5);
  EXPECT_LT((evaluate(s, 0.0) - s.ctrl.front()).norm(), 1e-14);
  EXPECT_LT((evaluate(s, 1.0) - s.ctrl.back()).norm(), 1e-14);
}

TEST(BSpline, ClosedSplineWraps) {
  BSpline s;
  s.closed = true;
  for (int i = 0; i < 8; ++i) s.ctrl.emplace_back(std::cos(i * M_PI / 4), std::sin(i * M_PI / 4));
  EXPECT_LT((evaluate(s, 0.0) - evaluate(s, 1.0)).norm(), 1e-14);
  EXPECT_LT((evaluate(s, 0.1) - evaluate(s, 1.1)).norm(), 1e-14);
  const ChartPolyline p = sample_bspline(s, 64);
  ASSERT_EQ(p.points.size(), 64u);
  EXPECT_TRUE(p.closed);
  EXPECT_EQ(p.params.back(), 63.0 / 64.0);  // the end is the start: not sampled twice
}

TEST(BSpline, FitReproducesASplineFromItsSamples) {
  // Data sampled from a spline with the same knots: the fit gives it back
  // up to the small smoothing penalty.
  for (bool closed : {false, true}) {
    BSpline truth;
    truth.closed = closed;
    for (int i = 0; i < 8; ++i) truth.ctrl.emplace_back(std::cos(0.7 * i), std::sin(1.3 * i));
    std::vector<Eigen::Vector2d> data;
    std::vector<double> params, weights;
    for (int i = 0; i < 400; ++i) {
      const double t = closed ? i / 400.0 : i / 399.0;
      data.push_back(evaluate(truth, t));
      params.push_back(t);
      weights.push_back(1.0);
    }
    const BSpline fit = fit_bspline(data, params, weights, 8, closed);
    double worst = 0.0;
    for (double t = 0.0; t <= 1.0; t += 0.01) worst = std::max(worst, (evaluate(fit, t) - evaluate(truth, t)).norm());
    EXPECT_LT(worst, 1e-2) << (closed ? "closed" : "open");
  }
}

}  // namespace
}  // namespace developable

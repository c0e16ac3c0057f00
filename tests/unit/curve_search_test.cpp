// curve_search.h: CurveSearch::nearest is "exact whatever the hints":
// compared with a brute-force search over every arc, on random curves,
// random normals and random (also wrong-sized or garbage) hints.
#include "ideal_curve/curve_search.h"

#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace developable {
namespace {

// A random walk on the sphere: `count` points, steps of about `step` rad.
SphereCurve random_curve(std::mt19937& random, int count, double step, bool closed) {
  SphereCurve c;
  c.closed = closed;
  Eigen::Vector3d p = test::random_unit(random);
  for (int i = 0; i < count; ++i) {
    c.points.push_back(p);
    p = (p + step * test::random_unit(random)).normalized();
  }
  return c;
}

// Largest cosine between q and a point of the great-circle arc a -> b,
// written independently of curve_search.cpp: the foot of q on the arc's
// plane counts when it lies between a and b (its angles to a and b add up
// to the arc's), else the nearer end. Points 90 degrees or more apart are
// joined by no arc (curve_search.h): only the ends count.
double best_cosine_on_arc(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& q) {
  double best = std::max(a.dot(q), b.dot(q));
  if (a.dot(b) <= 0.0) return best;
  const Eigen::Vector3d normal = a.cross(b);
  if (normal.norm() < 1e-15) return best;
  const Eigen::Vector3d m = normal.normalized();
  const Eigen::Vector3d foot = q - q.dot(m) * m;
  if (foot.norm() < 1e-15) return best;
  const Eigen::Vector3d f = foot.normalized();
  auto angle = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    return std::atan2(x.cross(y).norm(), x.dot(y));
  };
  if (std::abs(angle(a, f) + angle(f, b) - angle(a, b)) < 1e-12) best = std::max(best, f.dot(q));
  return best;
}

double brute_force_cosine(const std::vector<SphereCurve>& curves, const Eigen::Vector3d& q) {
  double best = -2.0;
  for (const auto& c : curves) {
    const size_t n = c.points.size();
    std::vector<Eigen::Vector3d> p;
    for (const auto& x : c.points) p.push_back(x.normalized());
    if (n == 1) best = std::max(best, p[0].dot(q));
    for (size_t i = 0; i + 1 < n; ++i) best = std::max(best, best_cosine_on_arc(p[i], p[i + 1], q));
    if (c.closed && n > 2) best = std::max(best, best_cosine_on_arc(p[n - 1], p[0], q));
  }
  return best;
}

TEST(CurveSearch, ExactWhateverTheHints) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<SphereCurve> curves;
    const int count = 1 + trial % 3;
    for (int k = 0; k < count; ++k) {
      const int points = k == 2 ? 1 : std::uniform_int_distribution<int>(2, 300)(random);
      curves.push_back(random_curve(random, points, 0.05 + 0.1 * (trial % 4), (trial + k) % 2 == 0));
    }
    const CurveSearch search(curves);
    const int rows = trial < 2 ? 20000 : 700;  // the first two split over threads
    Normals normals(rows, 3);
    for (int i = 0; i < rows; ++i) normals.row(i) = (test::random_unit(random) * (0.5 + i % 3)).transpose();
    const Normals plain = search.nearest(normals);
    // Hints: none, random arc numbers (some out of range or negative), the
    // last answers, and a vector of the wrong size.
    std::vector<int> hints(static_cast<size_t>(rows));
    std::uniform_int_distribution<int> any(-5, 2000);
    for (int& h : hints) h = any(random);
    const Normals hinted = search.nearest(normals, &hints);
    const Normals again = search.nearest(normals, &hints);
    std::vector<int> wrong(3, 7);
    const Normals resized = search.nearest(normals, &wrong);
    EXPECT_EQ(wrong.size(), static_cast<size_t>(rows));
    for (int i = 0; i < rows; ++i) {
      const Eigen::Vector3d q = normals.row(i).transpose().normalized();
      const double best = brute_force_cosine(curves, q);
      const char* names[] = {"no hints", "random hints", "last answers", "wrong-sized hints"};
      const Normals* results[] = {&plain, &hinted, &again, &resized};
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d t = results[k]->row(i).transpose();
        ASSERT_NEAR(t.norm(), 1.0, 1e-14);
        ASSERT_NEAR(t.dot(q), best, 1e-12) << "trial " << trial << " row " << i << " " << names[k];
      }
    }
  }
}

TEST(CurveSearch, ZeroRowGetsTheFirstPointAndBadInputThrows) {
  std::mt19937 random(12);
  const std::vector<SphereCurve> curves{random_curve(random, 10, 0.1, false)};
  const CurveSearch search(curves);
  Normals n = Normals::Zero(1, 3);
  EXPECT_LT((search.nearest(n).row(0).transpose() - curves[0].points[0].normalized()).norm(), 1e-15);
  n(0, 0) = NAN;
  EXPECT_THROW(search.nearest(n), EngineError);
  EXPECT_THROW(CurveSearch().nearest(Normals::Zero(1, 3)), EngineError);
  EXPECT_THROW(CurveSearch(std::vector<SphereCurve>{}), EngineError);
  EXPECT_THROW(CurveSearch(std::vector<SphereCurve>{SphereCurve{}}), EngineError);
  SphereCurve zero;
  zero.points.push_back(Eigen::Vector3d::Zero());
  EXPECT_THROW(CurveSearch(std::vector<SphereCurve>{zero}), EngineError);
}

}  // namespace
}  // namespace developable

// Stage 4, effect_field.h: the window, the sources, the automatic radius's
// bounds, and a field that peaks along the points (a ridge on the circle of
// a cone's Gauss image).
#include "ideal_curve/effect_field.h"

#include "gauss_image.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

struct ChartOfImage {
  test::GaussImage image;
  GaussChart chart;
  ChartPoints points;
};

ChartOfImage chart_of(unsigned seed, double angle, double sweep = 2 * M_PI) {
  test::GaussImage image = test::cone_gauss_image(seed, angle, sweep);
  const GaussChart chart(image.axis);
  ChartPoints points = project_to_chart(chart, image.normals);
  return {std::move(image), chart, std::move(points)};
}

TEST(EffectField, SourcesHoldEveryPointAndTheirWeight) {
  const auto c = chart_of(1, 1.0);
  const EffectField field = compute_effect_field(c.points, c.image.weights, {});
  EXPECT_EQ(field.resolution, 128);
  int count = 0;
  double weight = 0.0;
  for (const auto& s : field.sources) {
    count += s.count;
    weight += s.weight;
  }
  EXPECT_EQ(count, c.points.rows());
  EXPECT_NEAR(weight, c.image.weights.sum(), 1e-9);
  EXPECT_NEAR(field.total_weight, c.image.weights.sum(), 1e-9);
  // The window holds every point, 4 cells inside its rim.
  for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
    const Eigen::Vector2d local = (c.points.row(i).transpose() - field.origin) / field.cell_size;
    EXPECT_GE(local.minCoeff(), 4.0 - 1e-9);
    EXPECT_LE(local.maxCoeff(), field.resolution - 4.0 + 1e-9);
  }
}

TEST(EffectField, AutomaticRadiusStaysInItsBounds) {
  for (unsigned seed = 0; seed < 6; ++seed) {
    const auto c = chart_of(seed, 0.3 + 0.2 * seed, seed % 2 ? M_PI : 2 * M_PI);
    const EffectField field = compute_effect_field(c.points, c.image.weights, {});
    const double extent = (c.points.colwise().maxCoeff() - c.points.colwise().minCoeff()).maxCoeff();
    const double h = field.cell_size;
    EXPECT_GE(field.effect_radius, 3.0 * h - 1e-12) << "seed " << seed;
    EXPECT_LE(field.effect_radius, std::max(0.25 * extent, 3.0 * h) + 1e-12) << "seed " << seed;
    EXPECT_EQ(field.base_softening, std::max(field.effect_radius / 3.0, h));
  }
}

TEST(EffectField, GivenRadiusIsUsed) {
  const auto c = chart_of(2, 1.2);
  EffectFieldOptions options;
  options.effect_radius = 0.2;
  EXPECT_EQ(compute_effect_field(c.points, c.image.weights, options).effect_radius, 0.2);
}

TEST(EffectField, FieldPeaksOnTheCircleAndVanishesOutside) {
  for (double angle : {0.6, M_PI / 2}) {
    const auto c = chart_of(3, angle);
    const EffectField field = compute_effect_field(c.points, c.image.weights, {});
    const double r = 2.0 * std::sin(angle / 2.0);  // chart radius of the circle
    const double R = field.effect_radius;
    for (int k = 0; k < 16; ++k) {
      const Eigen::Vector2d dir(std::cos(k * M_PI / 8), std::sin(k * M_PI / 8));
      const double on = field.sample(r * dir);
      EXPECT_GT(on, 0.0);
      EXPECT_GT(on, field.sample((r - 0.7 * R) * dir)) << "angle " << angle << " k " << k;
      EXPECT_GT(on, field.sample((r + 0.7 * R) * dir)) << "angle " << angle << " k " << k;
    }
    EXPECT_EQ(field.sample(Eigen::Vector2d(10, 10)), 0.0);
    EXPECT_GE(field.values.minCoeff(), 0.0);
  }
}

TEST(EffectField, Refusals) {
  const auto c = chart_of(4, 1.0);
  EXPECT_THROW(compute_effect_field(c.points, Eigen::VectorXd::Ones(3), {}), EngineError);
  EXPECT_THROW(compute_effect_field(ChartPoints(0, 2), Eigen::VectorXd(0), {}), EngineError);
  EffectFieldOptions bad;
  bad.grid_resolution = 8;
  EXPECT_THROW(compute_effect_field(c.points, c.image.weights, bad), EngineError);
  bad = {};
  bad.effect_radius = -1.0;
  EXPECT_THROW(compute_effect_field(c.points, c.image.weights, bad), EngineError);
  Eigen::VectorXd negative = c.image.weights;
  negative[5] = -1.0;
  EXPECT_THROW(compute_effect_field(c.points, negative, {}), EngineError);
}

}  // namespace
}  // namespace developable

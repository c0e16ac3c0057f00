// Stage 5, skeleton.h: on the field of a cone's (or a cylinder's) Gauss
// image the skeleton is one curve along the circle, closed when the circle
// is whole; a point-like image has none; ordering on known point sets.
#include "ideal_curve/skeleton.h"

#include "gauss_image.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

std::pair<EffectField, double> field_of(const test::GaussImage& image) {
  const GaussChart chart(image.axis);
  return {compute_effect_field(project_to_chart(chart, image.normals), image.weights, {}),
          2.0 * std::sin(image.angle / 2.0)};
}

TEST(Skeleton, WholeCircleGivesOneClosedCurveOnIt) {
  for (unsigned seed = 0; seed < 6; ++seed) {
    const double angle = seed % 2 ? M_PI / 2 : 0.4 + 0.15 * seed;  // cylinders and cones
    const auto [field, radius] = field_of(test::cone_gauss_image(seed, angle));
    const auto curves = extract_skeleton(field, {});
    ASSERT_EQ(curves.size(), 1u) << "seed " << seed;
    EXPECT_TRUE(curves[0].closed) << "seed " << seed;
    for (const auto& p : curves[0].points) EXPECT_NEAR(p.norm(), radius, 1.5 * field.cell_size) << "seed " << seed;
  }
}

TEST(Skeleton, ArcGivesOneOpenCurveOnIt) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    const double angle = 0.5 + 0.3 * seed;
    const auto [field, radius] = field_of(test::cone_gauss_image(seed, angle, 2.0));
    const auto curves = extract_skeleton(field, {});
    ASSERT_EQ(curves.size(), 1u) << "seed " << seed;
    EXPECT_FALSE(curves[0].closed);
    // Within an effect radius of its ends the field is a cap, not a ridge
    // across the arc: only the points between are held to the circle.
    const auto& points = curves[0].points;
    for (const auto& p : points) {
      if ((p - points.front()).norm() < field.effect_radius || (p - points.back()).norm() < field.effect_radius)
        continue;
      EXPECT_NEAR(p.norm(), radius, 1.5 * field.cell_size) << "seed " << seed;
    }
  }
}

TEST(Skeleton, OrderingALineAndARing) {
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i < 20; ++i) line.emplace_back(0.1 * ((i * 7) % 20), 0.0);  // shuffled
  auto curves = order_ridge_points(line, 0.15, 0.0, 0.25, 0.0);
  ASSERT_EQ(curves.size(), 1u);
  EXPECT_FALSE(curves[0].closed);
  ASSERT_EQ(curves[0].points.size(), 20u);
  const double step = curves[0].points[1].x() - curves[0].points[0].x();
  for (size_t i = 1; i < 20; ++i) EXPECT_NEAR(curves[0].points[i].x() - curves[0].points[i - 1].x(), step, 1e-12);

  std::vector<Eigen::Vector2d> ring;
  for (int i = 0; i < 40; ++i) ring.emplace_back(std::cos(i * M_PI / 20), std::sin(i * M_PI / 20));
  curves = order_ridge_points(ring, 0.3, 0.0, 0.25, 0.0);
  ASSERT_EQ(curves.size(), 1u);
  EXPECT_TRUE(curves[0].closed);
  EXPECT_EQ(curves[0].points.size(), 40u);
  EXPECT_TRUE(order_ridge_points({Eigen::Vector2d(0, 0)}, 1.0, 0.0, 0.25, 0.0).empty());
}

TEST(Skeleton, RidgePointsAreDeterministicAndRefuseBadOptions) {
  const auto [field, radius] = field_of(test::cone_gauss_image(5, 1.0));
  EXPECT_EQ(find_ridge_points(field, 0.01), find_ridge_points(field, 0.01));
  EXPECT_THROW(find_ridge_points(field, 1.0), EngineError);
  SkeletonOptions bad;
  bad.min_branch_fraction = -1.0;
  EXPECT_THROW(extract_skeleton(field, bad), EngineError);
}

}  // namespace
}  // namespace developable

// Stage 6, ideal_curve.h: the fitted curve of a cone's or a cylinder's Gauss
// image lies on its circle (small circle / great circle), closed when the
// circle is whole; a plane gets its normal as a single point.
#include "ideal_curve/ideal_curve.h"

#include "gauss_image.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

// Largest angle (rad) from a curve point to the image's circle.
double largest_gap(const test::GaussImage& image, const SphereCurve& curve) {
  double gap = 0.0;
  for (const auto& p : curve.points) gap = std::max(gap, test::angle_to_circle(image, p));
  return gap;
}

TEST(IdealCurve, WholeCircleOfConesAndCylinders) {
  for (unsigned seed = 0; seed < 8; ++seed) {
    const double angle = seed % 2 ? M_PI / 2 : 0.3 + 0.15 * seed;
    const auto image = test::cone_gauss_image(seed, angle);
    const auto curves = fit_ideal_curves(image.normals, image.weights, {});
    ASSERT_EQ(curves.size(), 1u) << "seed " << seed;
    EXPECT_TRUE(curves[0].closed);
    EXPECT_EQ(curves[0].points.size(), 512u);
    EXPECT_LT(largest_gap(image, curves[0]), 2e-3) << "seed " << seed << " angle " << angle;
    for (const auto& p : curves[0].points) EXPECT_NEAR(p.norm(), 1.0, 1e-14);
  }
}

TEST(IdealCurve, ArcOfACone) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    const auto image = test::cone_gauss_image(seed, 0.5 + 0.25 * seed, 2.5);
    const auto curves = fit_ideal_curves(image.normals, image.weights, {});
    ASSERT_EQ(curves.size(), 1u) << "seed " << seed;
    EXPECT_FALSE(curves[0].closed);
    EXPECT_LT(largest_gap(image, curves[0]), 2e-3) << "seed " << seed;
  }
}

TEST(IdealCurve, PlaneGetsItsNormal) {
  Normals n(50, 3);
  const Eigen::RowVector3d normal = Eigen::RowVector3d(0.3, -0.4, 0.8).normalized();
  for (int i = 0; i < 50; ++i) n.row(i) = normal * (1.0 + i);  // any length
  const auto curves = fit_ideal_curves(n, Eigen::VectorXd::Ones(50), {});
  ASSERT_EQ(curves.size(), 1u);
  ASSERT_EQ(curves[0].points.size(), 1u);
  EXPECT_LT((curves[0].points[0] - normal.transpose()).norm(), 1e-12);
}

TEST(IdealCurve, NoisyPlaneGetsOnePoint) {
  // Gaussian noise on a plane's normal: the skeleton may keep a short ridge
  // through the blob (skeleton.h), the residual test makes it a point.
  for (unsigned seed = 0; seed < 8; ++seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> g(0.0, 0.02);
    const Eigen::Vector3d normal = test::random_unit(random);
    const Eigen::Vector3d e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
    Normals n(500, 3);
    for (int i = 0; i < 500; ++i) n.row(i) = (normal + g(random) * e1 + g(random) * e2).normalized().transpose();
    const auto curves = fit_ideal_curves(n, Eigen::VectorXd::Ones(500), {});
    ASSERT_EQ(curves.size(), 1u);
    ASSERT_EQ(curves[0].points.size(), 1u) << "seed " << seed;
    EXPECT_LT((curves[0].points[0] - normal).norm(), 0.01);
  }
}

TEST(IdealCurve, AutomaticGridResolution) {
  EXPECT_EQ(automatic_grid_resolution(0), 32);
  EXPECT_EQ(automatic_grid_resolution(1600), 80);
  EXPECT_EQ(automatic_grid_resolution(1000000), 128);
}

TEST(IdealCurve, Refusals) {
  const auto image = test::cone_gauss_image(1, 1.0);
  EXPECT_THROW(fit_ideal_curves(image.normals, Eigen::VectorXd::Ones(3), {}), EngineError);
  EXPECT_THROW(fit_ideal_curves(Normals(0, 3), Eigen::VectorXd(0), {}), EngineError);
  EXPECT_THROW(fit_ideal_curves(Normals::Zero(4, 3), Eigen::VectorXd::Ones(4), {}), EngineError);
  IdealCurveOptions bad;
  bad.grid_resolution = 8;
  EXPECT_THROW(fit_ideal_curves(image.normals, image.weights, bad), EngineError);
}

}  // namespace
}  // namespace developable

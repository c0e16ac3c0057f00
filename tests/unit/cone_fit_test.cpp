// cone_fit.h: exact cones are recovered exactly, planes get angle 0, and the
// moments are additive.
#include "core/cone_fit.h"

#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace developable {
namespace {

// `count` normals on the cone (axis, angle), at random azimuths, random weights.
NormalMoments cone_normals(const Eigen::Vector3d& axis, double angle, int count, std::mt19937& random) {
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  std::uniform_real_distribution<double> u(0.0, 2 * M_PI), w(0.5, 2.0);
  NormalMoments m;
  for (int i = 0; i < count; ++i) {
    const double t = u(random);
    m.add(std::cos(angle) * axis + std::sin(angle) * (std::cos(t) * e1 + std::sin(t) * e2), w(random));
  }
  return m;
}

TEST(ConeFit, RecoversExactCones) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d axis = test::random_unit(random);
    const double angle = std::uniform_real_distribution<double>(0.1, M_PI / 2)(random);
    const ConeFit fit = fit_cone(cone_normals(axis, angle, 40, random));
    EXPECT_NEAR(fit.cone.axis.dot(axis), 1.0, 1e-9) << "trial " << trial;
    EXPECT_NEAR(fit.cone.angle, angle, 1e-7) << "trial " << trial;
    EXPECT_NEAR(fit.residual, 0.0, 1e-10);
  }
}

TEST(ConeFit, AngleStaysAtMostHalfPi) {
  // The cone of -axis at pi - angle is the same circle.
  std::mt19937 random(6);
  const ConeFit fit = fit_cone(cone_normals(Eigen::Vector3d::UnitZ(), 2.5, 30, random));
  EXPECT_NEAR(fit.cone.axis.z(), -1.0, 1e-9);
  EXPECT_NEAR(fit.cone.angle, M_PI - 2.5, 1e-7);
}

TEST(ConeFit, PlaneGetsItsNormalAndAngleZero) {
  NormalMoments m;
  const Eigen::Vector3d n = Eigen::Vector3d(1, -2, 0.5).normalized();
  for (int i = 0; i < 10; ++i) m.add(n, 1.0 + i);
  const ConeFit fit = fit_cone(m);
  EXPECT_LT((fit.cone.axis - n).norm(), 1e-12);
  EXPECT_EQ(fit.cone.angle, 0.0);
  EXPECT_NEAR(fit.residual, 0.0, 1e-12);
}

TEST(ConeFit, EmptyMomentsGiveTheDefaultCone) {
  const ConeFit fit = fit_cone(NormalMoments());
  EXPECT_EQ(fit.cone.axis, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(fit.residual, 0.0);
}

TEST(ConeFit, MomentsAreAdditive) {
  std::mt19937 random(7);
  NormalMoments a = cone_normals(Eigen::Vector3d::UnitX(), 0.7, 20, random);
  const NormalMoments b = cone_normals(Eigen::Vector3d::UnitX(), 0.7, 20, random);
  NormalMoments both = a;
  both += b;
  EXPECT_DOUBLE_EQ(both.weight, a.weight + b.weight);
  EXPECT_NEAR(fit_cone(both).cone.angle, 0.7, 1e-7);
}

TEST(ConeFit, PlaneFitAxisOfAFullCylinderIsDeterministic) {
  // A great circle's mean is ~0: the axis gets its largest component positive.
  NormalMoments m;
  for (int i = 0; i < 64; ++i) {
    const double t = 2 * M_PI * i / 64;
    m.add(Eigen::Vector3d(std::cos(t), 0.0, std::sin(t)), 1.0);
  }
  const Eigen::Vector3d mean = m.sum / m.weight;
  const NormalPlaneFit fit = fit_normal_plane(mean, m.outer / m.weight - mean * mean.transpose());
  EXPECT_TRUE(fit.found);
  EXPECT_NEAR(fit.axis.y(), 1.0, 1e-12);
  EXPECT_NEAR(fit.eigenvalues(0), 0.0, 1e-15);
}

TEST(ConeFit, AngleToCone) {
  const Cone cone{Eigen::Vector3d::UnitZ(), 0.5};
  EXPECT_NEAR(angle_to_cone(cone, Eigen::Vector3d(std::sin(0.5), 0, std::cos(0.5))), 0.0, 1e-15);
  EXPECT_NEAR(angle_to_cone(cone, Eigen::Vector3d::UnitZ()), 0.5, 1e-15);
  EXPECT_NEAR(angle_to_cone(cone, Eigen::Vector3d::UnitX()), M_PI / 2 - 0.5, 1e-15);
}

}  // namespace
}  // namespace developable

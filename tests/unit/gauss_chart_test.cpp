// Stage 3, gauss_chart.h: the Lambert chart and its "exact inverse", the
// chart's disc, and the choice of pole.
#include "ideal_curve/gauss_chart.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace developable {
namespace {

TEST(GaussChart, ToSphereInvertsToChart) {
  std::mt19937 random(1);
  for (int trial = 0; trial < 20; ++trial) {
    const GaussChart chart(test::random_unit(random));
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector3d n = test::random_unit(random);
      if (n.dot(chart.pole()) < -0.999) continue;  // next to the antipode the chart squeezes
      const Eigen::Vector2d p = chart.to_chart(n);
      EXPECT_LE(p.norm(), 2.0);
      EXPECT_LT((chart.to_sphere(p) - n).norm(), 1e-13) << n.transpose();
    }
  }
}

TEST(GaussChart, ToChartInvertsToSphereInsideTheDisc) {
  std::mt19937 random(2);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    const GaussChart chart(test::random_unit(random));
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector2d p(u(random), u(random));
      if (p.norm() > 1.99) continue;
      EXPECT_LT((chart.to_chart(chart.to_sphere(p)) - p).norm(), 1e-12) << p.transpose();
      EXPECT_NEAR(chart.to_sphere(p).norm(), 1.0, 1e-15);
    }
  }
}

TEST(GaussChart, PoleGoesToTheOriginAndTheAntipodeToTheRim) {
  const GaussChart chart(Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(chart.pole().norm(), 1.0, 1e-15);
  EXPECT_LT(chart.to_chart(chart.pole()).norm(), 1e-15);
  EXPECT_NEAR(chart.to_chart(-chart.pole()).norm(), 2.0, 1e-15);
  EXPECT_LT((chart.to_sphere(Eigen::Vector2d(5, 0)) + chart.pole()).norm(), 1e-12);  // clamped
  EXPECT_EQ(chart.to_chart(Eigen::Vector3d::Zero()), Eigen::Vector2d::Zero());
}

TEST(GaussChart, EqualAreas) {
  // Lambert's map keeps areas: a cap of half-angle a (area 2 pi (1 - cos a))
  // maps to the disc of radius 2 sin(a / 2) (area 4 pi sin^2(a / 2)), the same.
  const GaussChart chart(Eigen::Vector3d::UnitZ());
  for (double a : {0.1, 0.7, 1.5, 2.5}) {
    const Eigen::Vector3d rim(std::sin(a), 0.0, std::cos(a));
    const double r = chart.to_chart(rim).norm();
    EXPECT_NEAR(M_PI * r * r, 2.0 * M_PI * (1.0 - std::cos(a)), 1e-12);
  }
}

TEST(GaussChart, RefusesABadPole) {
  EXPECT_THROW(GaussChart(Eigen::Vector3d::Zero()), EngineError);
  EXPECT_THROW(GaussChart(Eigen::Vector3d(NAN, 0, 0)), EngineError);
}

TEST(GaussChart, PoleOfACapIsItsMeanNormal) {
  std::mt19937 random(3);
  const Eigen::Vector3d centre = test::random_unit(random);
  Normals n(200, 3);
  for (int i = 0; i < 200; ++i) n.row(i) = (centre + 0.3 * test::random_unit(random)).normalized().transpose();
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(200);
  const Eigen::Vector3d mean = (n.transpose() * w).normalized();
  EXPECT_LT((choose_chart_pole(n, w) - mean).norm(), 1e-12);
}

TEST(GaussChart, PoleOfACylinderIsItsAxis) {
  // A cylinder's normals are a great circle: the pole is its axis, whichever
  // way the cylinder lies.
  std::mt19937 random(4);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d axis = test::random_unit(random);
    const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
    Normals n(64, 3);
    for (int i = 0; i < 64; ++i) {
      const double t = 2 * M_PI * i / 64;
      n.row(i) = (std::cos(t) * e1 + std::sin(t) * e2).transpose();
    }
    const Eigen::Vector3d pole = choose_chart_pole(n, Eigen::VectorXd::Ones(64));
    EXPECT_NEAR(std::abs(pole.dot(axis)), 1.0, 1e-12);
  }
}

TEST(GaussChart, PoleRefusals) {
  Normals n(2, 3);
  n << 0, 0, 1, 0, 1, 0;
  EXPECT_THROW(choose_chart_pole(n, Eigen::VectorXd::Ones(3)), EngineError);
  Eigen::VectorXd negative(2);
  negative << 1, -1;
  EXPECT_THROW(choose_chart_pole(n, negative), EngineError);
  EXPECT_THROW(choose_chart_pole(Normals::Zero(2, 3), Eigen::VectorXd::Ones(2)), EngineError);
  // All-zero weights count as uniform.
  EXPECT_NO_THROW(choose_chart_pole(n, Eigen::VectorXd::Zero(2)));
}

}  // namespace
}  // namespace developable

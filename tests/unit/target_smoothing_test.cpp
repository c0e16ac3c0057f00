// target_smoothing.h: what smoothing keeps (unit targets, constant fields,
// other patches' targets) and what it does (averages over the ring).
#include "ideal_curve/target_smoothing.h"

#include "core/measures.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>

#include <random>

namespace developable {
namespace {

Normals random_targets(Eigen::Index rows, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> g;
  Normals t(rows, 3);
  for (Eigen::Index f = 0; f < rows; ++f) t.row(f) = Eigen::RowVector3d(g(random), g(random), g(random)).normalized();
  return t;
}

TEST(TargetSmoothing, ZeroRoundsReturnTheTargets) {
  const auto m = test::cylinder();
  const Normals t = random_targets(m.triangles.rows(), 1);
  const TargetSmoother smoother(m.triangles, std::vector<int>(m.triangles.rows(), 0));
  const Normals out = smoother.smooth(t, face_areas(m.positions, m.triangles), 0);
  EXPECT_TRUE(out == t);
}

TEST(TargetSmoothing, ResultsAreUnitAndAConstantFieldStays) {
  const auto m = test::cone();
  const Eigen::VectorXd areas = face_areas(m.positions, m.triangles);
  const TargetSmoother smoother(m.triangles, std::vector<int>(m.triangles.rows(), 0));
  const Normals smoothed = smoother.smooth(random_targets(m.triangles.rows(), 2), areas, 3);
  for (Eigen::Index f = 0; f < smoothed.rows(); ++f) EXPECT_NEAR(smoothed.row(f).norm(), 1.0, 1e-14);
  const Normals constant = Normals::Constant(m.triangles.rows(), 3, 1.0 / std::sqrt(3.0));
  const Normals kept = smoother.smooth(constant, areas, 5);
  EXPECT_LT((kept - constant).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(TargetSmoothing, OtherPatchesAreLeftOut) {
  // Two patches, each with its own constant target: nothing leaks over the seam.
  const auto m = test::plane(6, 10);
  std::vector<int> patch(m.triangles.rows());
  Normals t(m.triangles.rows(), 3);
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const double x =
        (m.positions(m.triangles(f, 0), 0) + m.positions(m.triangles(f, 1), 0) + m.positions(m.triangles(f, 2), 0)) / 3;
    patch[f] = x < 0.5 ? 0 : 1;
    t.row(f) = patch[f] == 0 ? Eigen::RowVector3d(0, 0, 1) : Eigen::RowVector3d(1, 0, 0);
  }
  const TargetSmoother smoother(m.triangles, patch);
  EXPECT_TRUE(smoother.smooth(t, face_areas(m.positions, m.triangles), 4) == t);
}

TEST(TargetSmoothing, OneRoundIsTheAreaWeightedRingMean) {
  const auto m = test::cylinder(5, 12);
  const Eigen::VectorXd areas = face_areas(m.positions, m.triangles);
  const Normals t = random_targets(m.triangles.rows(), 3);
  const TargetSmoother smoother(m.triangles, std::vector<int>(m.triangles.rows(), 0));
  const Normals once = smoother.smooth(t, areas, 1);
  for (Eigen::Index f = 0; f < t.rows(); ++f) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (Eigen::Index g = 0; g < t.rows(); ++g) {
      bool shares = false;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) shares |= m.triangles(f, a) == m.triangles(g, b);
      if (shares) sum += areas[g] * t.row(g);
    }
    EXPECT_LT((once.row(f) - sum.normalized()).norm(), 1e-13) << "face " << f;
  }
}

TEST(TargetSmoothing, CancellingRingKeepsTheFaceTarget) {
  // Two triangles sharing an edge, opposite targets, equal areas.
  Triangles tri(2, 3);
  tri << 0, 1, 2, 0, 2, 3;
  Normals t(2, 3);
  t << 0, 0, 1, 0, 0, -1;
  const TargetSmoother smoother(tri, {0, 0});
  EXPECT_TRUE(smoother.smooth(t, Eigen::VectorXd::Ones(2), 1) == t);
}

}  // namespace
}  // namespace developable

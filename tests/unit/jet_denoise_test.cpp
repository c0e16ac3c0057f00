// jet_denoise.h: the smoothed start takes most of the noise off a smooth
// surface, leaves a noise-free one (almost) where it is, keeps pins
// bit-identical and does not round a crease.
#include "deformation/jet_denoise.h"

#include "core/mesh_connectivity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace developable {
namespace {

// Distance of each vertex from the axis-aligned cylinder of radius 1 around z.
Eigen::VectorXd off_cylinder(const Positions& p) {
  return (p.leftCols(2).rowwise().norm().array() - 1.0).abs().matrix();
}

Positions denoised(const test::Mesh& m, const std::vector<bool>& pinned = {}) {
  return jet_denoise(m.positions, m.triangles, vertex_faces(m.triangles, m.positions.rows()), pinned);
}

TEST(JetDenoise, TakesMostOfTheNoiseOffACylinder) {
  test::Mesh m = test::cylinder(12, 40);
  test::add_noise(m.positions, 0.01, 3);  // edges ~0.09-0.16: noise about 10 % of them
  const Eigen::VectorXd before = off_cylinder(m.positions);
  const Eigen::VectorXd after = off_cylinder(denoised(m));
  // The ring of a border vertex is one-sided but still a fair quadric.
  EXPECT_LT(after.mean(), 0.6 * before.mean());
  EXPECT_LT(after.maxCoeff(), before.maxCoeff());
}

TEST(JetDenoise, LeavesANoiseFreeSurfaceAlmostWhereItIs) {
  const test::Mesh m = test::cylinder(12, 40);
  const Positions s = denoised(m);
  // The quadric misses a circle by its third-order terms only.
  EXPECT_LT((s - m.positions).rowwise().norm().maxCoeff(), 1e-3);
  const test::Mesh flat = test::plane();
  EXPECT_LT((denoised(flat) - flat.positions).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(JetDenoise, KeepsPinsBitIdentical) {
  test::Mesh m = test::plane(10, 10);
  test::add_noise(m.positions, 0.01, 4);
  std::vector<bool> pinned(static_cast<size_t>(m.positions.rows()), false);
  for (size_t v = 0; v < pinned.size(); v += 3) pinned[v] = true;
  const Positions s = denoised(m, pinned);
  int moved = 0;
  for (Eigen::Index v = 0; v < s.rows(); ++v) {
    if (pinned[static_cast<size_t>(v)]) {
      EXPECT_EQ(s.row(v), m.positions.row(v));
    } else {
      moved += s.row(v) != m.positions.row(v) ? 1 : 0;
    }
  }
  EXPECT_GT(moved, 0);
}

TEST(JetDenoise, DoesNotRoundACrease) {
  // A sheet folded by 90 degrees along y = 0.5: z = max(0, y - 0.5).
  const test::Mesh m = test::grid(
      11, 11, false, [](double u, double v) { return Eigen::Vector3d(u, std::min(v, 0.5), std::max(0.0, v - 0.5)); });
  const Positions s = denoised(m);
  for (Eigen::Index v = 0; v < s.rows(); ++v) {
    if (std::abs(m.positions(v, 1) - 0.5) < 1e-12) {
      EXPECT_EQ(s.row(v), m.positions.row(v)) << v;
    }
  }
}

}  // namespace
}  // namespace developable

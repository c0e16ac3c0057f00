// jet_denoise.h: the smoothed start takes most of the noise off a smooth
// surface, leaves a noise-free one (almost) where it is, keeps pins
// bit-identical, does not round a crease, and with face groups smooths each
// piece on its own.
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

// A sheet folded by 90 degrees along y = 0.5 (z = max(0, y - 0.5)), its
// faces grouped by side of the fold.
struct FoldedSheet {
  test::Mesh mesh;
  std::vector<int> sides;
};

FoldedSheet folded_sheet() {
  FoldedSheet out{
      test::grid(21, 21, false,
                 [](double u, double v) { return Eigen::Vector3d(u, std::min(v, 0.5), std::max(0.0, v - 0.5)); }),
      {}};
  for (Eigen::Index f = 0; f < out.mesh.triangles.rows(); ++f) {
    double z = 0.0;
    for (int c = 0; c < 3; ++c) z += out.mesh.positions(out.mesh.triangles(f, c), 2);
    out.sides.push_back(z > 0.0 ? 1 : 0);
  }
  return out;
}

// Distance of each vertex off its side's plane (on the fold: 0).
Eigen::VectorXd off_sides(const Positions& p, const Positions& clean) {
  Eigen::VectorXd d(p.rows());
  for (Eigen::Index v = 0; v < p.rows(); ++v) d[v] = clean(v, 2) > 0.0 ? std::abs(p(v, 1) - 0.5) : std::abs(p(v, 2));
  return d;
}

TEST(JetDenoise, SmoothsEachGroupOnItsOwn) {
  const FoldedSheet sheet = folded_sheet();
  const test::Mesh& m = sheet.mesh;
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  JetDenoiseOptions unguarded;
  unguarded.feature_angle_deg = 90.0;
  // Without groups, unguarded: the rings across the fold round it.
  const Eigen::VectorXd rounded =
      off_sides(jet_denoise(m.positions, m.triangles, connectivity, {}, unguarded), m.positions);
  EXPECT_GT(rounded.maxCoeff(), 1e-3);
  // Each side on its own: the planes are fitted exactly, the fold stays.
  unguarded.face_groups = sheet.sides;
  EXPECT_LT(off_sides(jet_denoise(m.positions, m.triangles, connectivity, {}, unguarded), m.positions).maxCoeff(),
            1e-12);
  // With noise: most of it off each side, the vertices on the fold where they are.
  Positions noisy = m.positions;
  test::add_noise(noisy, 0.003, 5);
  const Positions s = jet_denoise(noisy, m.triangles, connectivity, {}, unguarded);
  std::vector<Eigen::Index> inside;
  for (Eigen::Index v = 0; v < s.rows(); ++v) {
    if (std::abs(m.positions(v, 1) - 0.5) < 1e-12 && m.positions(v, 2) == 0.0) {
      EXPECT_EQ(s.row(v), noisy.row(v)) << v;
    } else {
      inside.push_back(v);
    }
  }
  EXPECT_LT(off_sides(s, m.positions)(inside).mean(), 0.6 * off_sides(noisy, m.positions)(inside).mean());
}

TEST(JetDenoise, SeveralGuardsAtOnceAreEachAloneBitForBit) {
  const FoldedSheet sheet = folded_sheet();
  const test::Mesh& m = sheet.mesh;
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  Positions noisy = m.positions;
  test::add_noise(noisy, 0.003, 7);
  std::vector<bool> pinned(static_cast<size_t>(noisy.rows()), false);
  pinned[3] = true;
  for (const std::vector<int>& groups : {std::vector<int>{}, sheet.sides}) {
    const std::vector<double> angles{30.0, 90.0, 5.0};
    const std::vector<Positions> together = jet_denoise(noisy, m.triangles, connectivity, pinned, angles, groups);
    ASSERT_EQ(together.size(), angles.size());
    for (size_t k = 0; k < angles.size(); ++k) {
      JetDenoiseOptions alone;
      alone.feature_angle_deg = angles[k];
      alone.face_groups = groups;
      EXPECT_EQ(together[k], jet_denoise(noisy, m.triangles, connectivity, pinned, alone)) << angles[k];
    }
    // The guards differ where they should: without groups the 30-degree
    // guard keeps the fold, the unguarded smoothing rounds it.
    if (groups.empty()) {
      EXPECT_NE(together[0], together[1]);
    }
  }
  EXPECT_TRUE(jet_denoise(noisy, m.triangles, connectivity, {}, std::vector<double>{}, {}).empty());
}

TEST(JetDenoise, RejectsGroupsOfTheWrongSize) {
  const test::Mesh m = test::plane();
  JetDenoiseOptions options;
  options.face_groups = {0, 1};
  EXPECT_THROW(jet_denoise(m.positions, m.triangles, vertex_faces(m.triangles, m.positions.rows()), {}, options),
               EngineError);
}

}  // namespace
}  // namespace developable

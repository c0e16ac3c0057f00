// gauss_thinning.h: a ruled surface's targets are its normals (its Gauss
// image is a curve already); a sphere's are pulled off its normals onto
// great circles; the targets are the per-face definition bit for bit;
// neighbourhoods hold the face itself, are symmetric, stay within the
// radius and, with pieces, within a piece.
#include "ideal_curve/gauss_thinning.h"

#include "core/measures.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace developable {
namespace {

double largest_angle(const Normals& a, const Normals& b) {
  double largest = 0.0;
  for (Eigen::Index f = 0; f < a.rows(); ++f)
    largest = std::max(largest, std::acos(std::clamp(a.row(f).dot(b.row(f)), -1.0, 1.0)));
  return largest;
}

TEST(GaussThinning, RuledSurfacesKeepTheirNormals) {
  // A cylinder's and a plane's normals lie on great circles: exactly.
  for (const test::Mesh& m : {test::cylinder(8, 24), test::plane(6, 7)}) {
    const Normals normals = face_normals(m.positions, m.triangles);
    const GaussThinning thinning(m.positions, m.triangles, 0.5, {});
    const Normals targets = thinning.targets(normals, 25.0 * M_PI / 180.0, 1);
    EXPECT_LT(largest_angle(targets, normals), 1e-6);
  }
  // A cone's lie on a small circle, which a great circle fits within the
  // neighbourhood's share of it (0.009 rad here; the ruled threshold is 0.02).
  const test::Mesh m = test::cone(8, 24);
  const Normals normals = face_normals(m.positions, m.triangles);
  const GaussThinning thinning(m.positions, m.triangles, 0.5, {});
  EXPECT_LT(largest_angle(thinning.targets(normals, 25.0 * M_PI / 180.0, 1), normals), 0.02);
}

TEST(GaussThinning, ASpherePullsItsNormalsOntoCircles) {
  const test::Mesh m = test::sphere(3);  // 512 faces
  const Normals normals = face_normals(m.positions, m.triangles);
  const double edge = average_edge_length(m.positions, m.triangles);
  const GaussThinning thinning(m.positions, m.triangles, 3.0 * edge, {});
  const Normals targets = thinning.targets(normals, 25.0 * M_PI / 180.0, 1);
  EXPECT_GT(largest_angle(targets, normals), 0.01);
  for (Eigen::Index f = 0; f < targets.rows(); ++f) EXPECT_NEAR(targets.row(f).norm(), 1.0, 1e-12);
  // Each target is the normal projected: closer to it than 90 degrees.
  EXPECT_LT(largest_angle(targets, normals), M_PI / 2);
  // The same whatever the thread count.
  EXPECT_EQ(thinning.targets(normals, 0.4, 1), thinning.targets(normals, 0.4, 2));
}

TEST(GaussThinning, NeighbourhoodsAreSymmetricWithinTheRadiusAndThePieces) {
  const test::Mesh m = test::sphere(2);
  const Eigen::Index faces = m.triangles.rows();
  std::vector<int> pieces(static_cast<size_t>(faces));
  for (Eigen::Index f = 0; f < faces; ++f) pieces[static_cast<size_t>(f)] = m.positions(m.triangles(f, 0), 2) > 0.0;
  const double radius = 0.6;
  for (const std::vector<int>& ids : {std::vector<int>(), pieces}) {
    const GaussThinning thinning(m.positions, m.triangles, radius, ids);
    const auto centroid = [&](Eigen::Index f) {
      return Eigen::RowVector3d((m.positions.row(m.triangles(f, 0)) + m.positions.row(m.triangles(f, 1)) +
                                 m.positions.row(m.triangles(f, 2))) /
                                3.0);
    };
    for (Eigen::Index f = 0; f < faces; ++f) {
      EXPECT_TRUE(std::binary_search(thinning.begin(f), thinning.end(f), static_cast<int>(f)));
      for (const int* g = thinning.begin(f); g != thinning.end(f); ++g) {
        EXPECT_LE((centroid(*g) - centroid(f)).norm(), radius + 1e-12);
        EXPECT_TRUE(std::binary_search(thinning.begin(*g), thinning.end(*g), static_cast<int>(f)));
        if (!ids.empty()) {
          EXPECT_EQ(ids[static_cast<size_t>(*g)], ids[static_cast<size_t>(f)]);
        }
      }
    }
  }
}

// The targets as the header defines them, each face's sum over its own
// neighbours in ascending order (on up to two threads the class computes
// each pair's weight once).
Normals targets_by_definition(const GaussThinning& thinning, const Normals& normals, double cone) {
  Normals out(normals.rows(), 3);
  for (Eigen::Index f = 0; f < normals.rows(); ++f) {
    const Eigen::Vector3d n = normals.row(f).transpose();
    Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
    for (const int* g = thinning.begin(f); g != thinning.end(f); ++g) {
      const Eigen::Vector3d ng = normals.row(*g).transpose();
      const double c = std::clamp(n.dot(ng), -1.0, 1.0);
      if (c < std::cos(cone)) continue;
      const double angle = std::acos(c) / (2.0 * cone);
      moments.noalias() += std::exp(-angle * angle) * ng * ng.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(moments);
    const Eigen::Vector3d axis = solver.eigenvectors().col(0);
    const Eigen::Vector3d target = n - n.dot(axis) * axis;
    out.row(f) = target.norm() > 1e-12 ? Eigen::RowVector3d(target.normalized().transpose()) : normals.row(f);
  }
  return out;
}

TEST(GaussThinning, TargetsAreTheDefinitionsBitForBit) {
  // A noisy sphere split in two pieces: every face's neighbours and weights.
  test::Mesh m = test::sphere(3);
  std::srand(7);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    m.positions.row(v) *= 1.0 + 0.02 * (static_cast<double>(std::rand()) / RAND_MAX - 0.5);
  const Normals normals = face_normals(m.positions, m.triangles);
  std::vector<int> pieces(static_cast<size_t>(m.triangles.rows()));
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    pieces[static_cast<size_t>(f)] = m.positions(m.triangles(f, 0), 0) > 0.1;
  const double edge = average_edge_length(m.positions, m.triangles);
  for (const std::vector<int>& ids : {std::vector<int>(), pieces}) {
    const GaussThinning thinning(m.positions, m.triangles, 3.0 * edge, ids);
    // Each pair once (up to two threads) and each face's own list (more).
    for (const double cone : {0.1, 0.44})
      for (const int threads : {1, 2, 4})
        EXPECT_TRUE(thinning.targets(normals, cone, threads) == targets_by_definition(thinning, normals, cone));
  }
}

// On spare cores the pairs are weighed block by block beforehand: the same
// targets bit for bit, over several blocks, whatever the cores taken.
TEST(GaussThinning, OnSpareCoresTheSameTargets) {
  test::Mesh m = test::sphere(6);  // 32768 faces: four blocks
  std::srand(3);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    m.positions.row(v) *= 1.0 + 0.01 * (static_cast<double>(std::rand()) / RAND_MAX - 0.5);
  const Normals normals = face_normals(m.positions, m.triangles);
  const GaussThinning thinning(m.positions, m.triangles, 3.0 * average_edge_length(m.positions, m.triangles), {});
  for (const double cone : {0.1, 0.44}) {
    const Normals alone = thinning.targets(normals, cone, 1);
    for (const int cores : {2, 3}) {
      SpareCores spare(cores);
      EXPECT_TRUE(thinning.targets(normals, cone, 2, &spare) == alone) << cores;
      EXPECT_EQ(spare.take(8), static_cast<unsigned>(cores - 1)) << "every core given back";
    }
  }
}

TEST(GaussThinning, RefusesBadArguments) {
  const test::Mesh m = test::plane(4, 4);
  EXPECT_THROW(GaussThinning(m.positions, m.triangles, 0.0, {}), EngineError);
  EXPECT_THROW(GaussThinning(m.positions, m.triangles, 1.0, {0, 1}), EngineError);
  const GaussThinning thinning(m.positions, m.triangles, 1.0, {});
  EXPECT_THROW(thinning.targets(face_normals(m.positions, m.triangles), 0.0), EngineError);
}

}  // namespace
}  // namespace developable

// developable_pieces.h: a mitred pipe falls into its cylinders, also where a
// mitre's ring has a flat vertex at the sides; meshes whose curvature is not
// on separating cuts (flat, a bump, noise) have no such pieces.
#include "segmentation/developable_pieces.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "crease_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>
#include <set>

namespace developable {
namespace {

std::optional<std::vector<int>> pieces_of(const test::Mesh& m) {
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  return developable_pieces(m.triangles, vertex_faces(m.triangles, m.positions.rows()), interior,
                            angle_defects(m.positions, m.triangles, interior), 1e-3);
}

// Faces below the joint ring (their centroid's z under the mitre plane) in
// one piece, those above in the other.
void expect_two_cylinders(const test::Mesh& m, const std::vector<int>& ids, double turn) {
  std::set<int> below, above;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    (test::below_mitre(m, f, turn) ? below : above).insert(ids[static_cast<size_t>(f)]);
  EXPECT_EQ(below.size(), 1u);
  EXPECT_EQ(above.size(), 1u);
  EXPECT_NE(*below.begin(), *above.begin());
  EXPECT_EQ(ids[0], 0);  // numbered in face order
}

TEST(DevelopablePieces, AMitredPipeFallsIntoItsCylinders) {
  for (double degrees : {15.0, 30.0, 60.0}) {
    const double turn = degrees * M_PI / 180.0;
    for (int cols : {23, 24, 32}) {  // 24 and 32: a flat ring vertex at each side
      const test::Mesh m = test::mitred_pipe(9, cols, turn);
      const auto ids = pieces_of(m);
      ASSERT_TRUE(ids.has_value()) << degrees << " degrees, " << cols << " columns";
      expect_two_cylinders(m, *ids, turn);
    }
  }
}

TEST(DevelopablePieces, EveryPieceNeedsAnInsideVertex) {
  // Three rings: the joint and one ring each side, both on the boundary: the
  // pipe's two pieces have no inside vertex, so there are no pieces.
  EXPECT_FALSE(pieces_of(test::mitred_pipe(3, 24, 0.5)).has_value());
  // Five rings: one ring of inside vertices each side of the joint.
  const test::Mesh m = test::mitred_pipe(5, 24, 0.5);
  const auto ids = pieces_of(m);
  ASSERT_TRUE(ids.has_value());
  expect_two_cylinders(m, *ids, 0.5);
}

TEST(DevelopablePieces, NoPiecesWithoutCurvatureOnCuts) {
  // Flat everywhere: nothing to cut along.
  EXPECT_FALSE(pieces_of(test::cylinder()).has_value());
  EXPECT_FALSE(pieces_of(test::plane()).has_value());
  // A bump: its curved vertices are inside the one piece.
  test::Mesh bump = test::plane(9, 9);
  bump.positions(40, 2) = 0.2;
  EXPECT_FALSE(pieces_of(bump).has_value());
  // Noise: every vertex curved, every edge cut, no piece has an inside.
  test::Mesh noisy = test::plane(12, 12);
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (Eigen::Index v = 0; v < noisy.positions.rows(); ++v) noisy.positions(v, 2) += noise(random);
  EXPECT_FALSE(pieces_of(noisy).has_value());
}

}  // namespace
}  // namespace developable

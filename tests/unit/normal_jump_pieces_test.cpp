// normal_jump_pieces.h: a cube falls into its six sides, a smooth cylinder stays
// one piece, a folded sheet parts on its fold; small pieces merge into the
// neighbour with the smoothest border, never across a border the reference
// normals' guard would call creased unless they have no vertex of their own.
#include "segmentation/normal_jump_pieces.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace developable {
namespace {

int count_of(const std::vector<int>& pieces) { return 1 + *std::max_element(pieces.begin(), pieces.end()); }

std::vector<int> pieces_of(const test::Mesh& m, double crease, int min_faces, const Normals& reference = Normals(),
                           double growth = 0.0) {
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  return normal_jump_pieces(m.triangles, table, face_normals(m.positions, m.triangles), crease, min_faces, reference,
                            growth);
}

// The unit square folded along x = 0.5 by `angle` (rad) about the y axis.
test::Mesh folded(int rows, int cols, double angle) {
  return test::grid(rows, cols, false, [=](double u, double v) {
    if (v <= 0.5) return Eigen::Vector3d(v, u, 0.0);
    const double s = v - 0.5;
    return Eigen::Vector3d(0.5 + s * std::cos(angle), u, s * std::sin(angle));
  });
}

TEST(NormalJumpPieces, ACubeFallsIntoItsSides) {
  const test::Mesh m = test::cube();
  const std::vector<int> pieces = pieces_of(m, 25.0 * M_PI / 180.0, 1);
  EXPECT_EQ(count_of(pieces), 6);
  for (int side = 0; side < 6; ++side)
    EXPECT_EQ(pieces[static_cast<size_t>(2 * side)], pieces[static_cast<size_t>(2 * side + 1)]);
  EXPECT_EQ(pieces[0], 0);  // numbered by their lowest face
}

TEST(NormalJumpPieces, ASmoothCylinderIsOnePiece) {
  const std::vector<int> pieces = pieces_of(test::cylinder(8, 48), 20.0 * M_PI / 180.0, 1);
  EXPECT_EQ(count_of(pieces), 1);
}

TEST(NormalJumpPieces, AFoldPartsASheet) {
  const test::Mesh m = folded(6, 11, 60.0 * M_PI / 180.0);
  const std::vector<int> pieces = pieces_of(m, 20.0 * M_PI / 180.0, 1);
  ASSERT_EQ(count_of(pieces), 2);
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    double x = 0.0;
    for (int c = 0; c < 3; ++c) x += m.positions(m.triangles(f, c), 0) / 3.0;
    EXPECT_EQ(pieces[static_cast<size_t>(f)], x < 0.5 ? 0 : 1);
  }
  // A gentler fold than the crease angle does not part it.
  EXPECT_EQ(count_of(pieces_of(folded(6, 11, 10.0 * M_PI / 180.0), 20.0 * M_PI / 180.0, 1)), 1);
}

TEST(NormalJumpPieces, SmallPiecesMergeIntoTheSmoothestNeighbour) {
  // A cube: each side (2 faces) is small against min_faces 3; they merge
  // until one piece is left (every border is a right angle).
  EXPECT_EQ(count_of(pieces_of(test::cube(), 25.0 * M_PI / 180.0, 3)), 1);
  const test::Mesh m = test::cube();
  const Normals input = face_normals(m.positions, m.triangles);
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  EXPECT_EQ(count_of(normal_jump_pieces(m.triangles, table, input, 0.3, 3, input, 0.3)), 1);
}

// Held to reference normals, a small piece keeps a border that would crease
// beyond them, unless it has no vertex of its own (every corner also one of
// another piece): then it is no surface to make developable, and joins its
// smoothest neighbour whatever the border.
TEST(NormalJumpPieces, ASmallPieceMergesAcrossACreaseOnlyWithoutAVertexOfItsOwn) {
  const test::Mesh m = test::plane(7, 7);
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  const Normals flat = face_normals(m.positions, m.triangles);
  const Eigen::RowVector3d tilted = Eigen::RowVector3d(1.0, 0.0, 1.0).normalized();  // 45 degrees off

  // The star of an interior vertex tilted: a piece with a vertex of its own.
  const int centre = 3 * 7 + 3;
  Normals star = flat;
  for (const int* f = table.begin(centre); f != table.end(centre); ++f) star.row(*f) = tilted;
  const int star_faces = table.count(centre);
  EXPECT_EQ(count_of(normal_jump_pieces(m.triangles, table, star, 0.3, star_faces + 1, flat, 0.3)), 2);
  EXPECT_EQ(count_of(normal_jump_pieces(m.triangles, table, star, 0.3, star_faces + 1)), 1);  // no reference

  // One face tilted: a piece of three corners that are all another's too.
  Normals one = flat;
  one.row(40) = tilted;
  EXPECT_EQ(count_of(normal_jump_pieces(m.triangles, table, one, 0.3, 1, flat, 0.3)), 2);  // nothing is small
  EXPECT_EQ(count_of(normal_jump_pieces(m.triangles, table, one, 0.3, 2, flat, 0.3)), 1);
}

TEST(NormalJumpPieces, RefusesBadArguments) {
  const test::Mesh m = test::cube();
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  const Normals normals = face_normals(m.positions, m.triangles);
  EXPECT_THROW(normal_jump_pieces(m.triangles, table, normals, -0.1, 1), EngineError);
  EXPECT_THROW(normal_jump_pieces(m.triangles, table, normals, 0.1, 0), EngineError);
  EXPECT_THROW(normal_jump_pieces(m.triangles, table, normals.topRows(3), 0.1, 1), EngineError);
}

}  // namespace
}  // namespace developable

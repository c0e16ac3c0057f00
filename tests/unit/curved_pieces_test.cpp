// curved_pieces.h: a piece is split when too few of its inside vertices are
// developable and it has enough of them; a split parts a piece where its
// normals fit two cones (a sheet folded in the middle parts on its fold), in
// two edge-connected parts, leaving the other pieces as they were.
#include "segmentation/curved_pieces.h"

#include "core/mesh_connectivity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <queue>
#include <set>

namespace developable {
namespace {

// The unit square folded along x = 0.5 by `angle` (rad) about the y axis.
test::Mesh folded(int rows, int cols, double angle) {
  return test::grid(rows, cols, false, [=](double u, double v) {
    if (v <= 0.5) return Eigen::Vector3d(v, u, 0.0);
    const double s = v - 0.5;
    return Eigen::Vector3d(0.5 + s * std::cos(angle), u, s * std::sin(angle));
  });
}

double centroid_x(const test::Mesh& m, Eigen::Index f) {
  double x = 0.0;
  for (int c = 0; c < 3; ++c) x += m.positions(m.triangles(f, c), 0) / 3.0;
  return x;
}

// Whether the faces labelled `label` are edge-connected.
bool edge_connected(const test::Mesh& m, const std::vector<int>& labels, int label) {
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  std::vector<int> faces;
  for (size_t f = 0; f < labels.size(); ++f)
    if (labels[f] == label) faces.push_back(static_cast<int>(f));
  if (faces.empty()) return false;
  std::set<int> seen{faces[0]};
  std::queue<int> open;
  open.push(faces[0]);
  while (!open.empty()) {
    const int f = open.front();
    open.pop();
    for (int c = 0; c < 3; ++c) {
      const int g = face_across(table, m.triangles, f, m.triangles(f, c), m.triangles(f, (c + 1) % 3));
      if (g >= 0 && labels[static_cast<size_t>(g)] == label && seen.insert(g).second) open.push(g);
    }
  }
  return seen.size() == faces.size();
}

TEST(CurvedPieces, ChoosesThePiecesTooFewOfWhoseInsideVerticesAreDevelopable) {
  // A 9 x 9 grid: the faces left of x = 0.5 are piece 0, the others piece 1.
  const test::Mesh m = test::plane(9, 9);
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  std::vector<int> pieces(static_cast<size_t>(m.triangles.rows()));
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) pieces[static_cast<size_t>(f)] = centroid_x(m, f) < 0.5 ? 0 : 1;
  std::vector<bool> inside(static_cast<size_t>(m.positions.rows()), false);
  std::vector<bool> developable(inside.size(), true);
  int inside0 = 0, inside1 = 0;
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double x = m.positions(v, 0), y = m.positions(v, 1);
    const bool interior = x > 0.01 && x < 0.99 && y > 0.01 && y < 0.99 && std::abs(x - 0.5) > 0.01;
    inside[static_cast<size_t>(v)] = interior;
    if (interior) ++(x < 0.5 ? inside0 : inside1);
  }
  ASSERT_EQ(inside0, 21);
  ASSERT_EQ(inside1, 21);
  // Piece 1: 11 of its 21 developable (52 %); piece 0 all of them.
  int marked = 0;
  for (Eigen::Index v = 0; v < m.positions.rows() && marked < 10; ++v)
    if (inside[static_cast<size_t>(v)] && m.positions(v, 0) > 0.5) {
      developable[static_cast<size_t>(v)] = false;
      ++marked;
    }
  EXPECT_EQ(curved_pieces(pieces, 2, table, inside, developable, 0.9, 20), (std::vector<bool>{false, true}));
  EXPECT_EQ(curved_pieces(pieces, 2, table, inside, developable, 0.5, 20), (std::vector<bool>{false, false}));
  // Too few inside vertices to tell.
  EXPECT_EQ(curved_pieces(pieces, 2, table, inside, developable, 0.9, 22), (std::vector<bool>{false, false}));
}

TEST(CurvedPieces, AFoldedSheetPartsOnItsFold) {
  const test::Mesh m = folded(9, 17, 80.0 * M_PI / 180.0);
  const std::vector<int> one(static_cast<size_t>(m.triangles.rows()), 0);
  const std::vector<int> parts = split_in_two(m.positions, m.triangles, one, 1, {true}, Progress{});
  EXPECT_EQ(*std::max_element(parts.begin(), parts.end()), 1);
  EXPECT_EQ(parts[0], 0);  // the lowest face keeps the piece's id
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    EXPECT_EQ(parts[static_cast<size_t>(f)], centroid_x(m, f) < 0.5 ? 0 : 1) << f;
  EXPECT_TRUE(edge_connected(m, parts, 0));
  EXPECT_TRUE(edge_connected(m, parts, 1));
}

TEST(CurvedPieces, OnlyTheFlaggedPiecesSplit) {
  // Two folded sheets side by side in y as pieces 0 and 1; only piece 1 is flagged.
  const test::Mesh m = folded(17, 17, 80.0 * M_PI / 180.0);
  std::vector<int> pieces(static_cast<size_t>(m.triangles.rows()));
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    double y = 0.0;
    for (int c = 0; c < 3; ++c) y += m.positions(m.triangles(f, c), 1) / 3.0;
    pieces[static_cast<size_t>(f)] = y < 0.5 ? 0 : 1;
  }
  const std::vector<int> parts = split_in_two(m.positions, m.triangles, pieces, 2, {false, true}, Progress{});
  for (size_t f = 0; f < pieces.size(); ++f) {
    if (pieces[f] == 0)
      EXPECT_EQ(parts[f], 0);
    else
      EXPECT_EQ(parts[f], centroid_x(m, static_cast<Eigen::Index>(f)) < 0.5 ? 1 : 2) << f;
  }
  for (int label = 0; label < 3; ++label) EXPECT_TRUE(edge_connected(m, parts, label));
  // Nothing flagged: nothing changes.
  EXPECT_EQ(split_in_two(m.positions, m.triangles, pieces, 2, {false, false}, Progress{}), pieces);
}

}  // namespace
}  // namespace developable

// submesh.h: the submesh of a set of faces keeps the order of its faces and
// vertices, maps rows both ways, and faces_of_pieces buckets faces by piece.
#include "core/submesh.h"

#include "core/measures.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <set>

namespace developable {
namespace {

TEST(Submesh, KeepsTheOrderAndMapsBack) {
  const test::Mesh m = test::plane(5, 6);
  std::vector<Eigen::Index> faces;
  for (Eigen::Index f = 0; f < m.triangles.rows(); f += 3) faces.push_back(f);
  const Submesh sub = submesh(m.triangles, m.positions.rows(), faces);
  EXPECT_EQ(sub.faces, faces);
  ASSERT_EQ(sub.face_count(), static_cast<Eigen::Index>(faces.size()));
  // Its vertices: exactly the corners of its faces, ascending.
  std::set<Eigen::Index> corners;
  for (Eigen::Index f : faces)
    for (int c = 0; c < 3; ++c) corners.insert(m.triangles(f, c));
  EXPECT_EQ(sub.vertices, std::vector<Eigen::Index>(corners.begin(), corners.end()));
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const int local = sub.local_of[static_cast<size_t>(v)];
    if (corners.count(v)) {
      ASSERT_GE(local, 0);
      EXPECT_EQ(sub.vertices[static_cast<size_t>(local)], v);
    } else {
      EXPECT_EQ(local, -1);
    }
  }
  // Its triangles are the faces' own, renumbered.
  for (Eigen::Index i = 0; i < sub.face_count(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(sub.vertices[static_cast<size_t>(sub.triangles(i, c))], m.triangles(faces[static_cast<size_t>(i)], c));
  // Rows out and back.
  const Positions local = sub.vertex_rows(m.positions);
  for (Eigen::Index i = 0; i < sub.vertex_count(); ++i)
    EXPECT_EQ(local.row(i), m.positions.row(sub.vertices[static_cast<size_t>(i)]));
  Positions moved = m.positions;
  const Positions shifted = local.array() + 1.0;
  sub.scatter(shifted, moved);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const Eigen::RowVector3d expected = m.positions.row(v).array() + (corners.count(v) ? 1.0 : 0.0);
    EXPECT_EQ(moved.row(v), expected);
  }
  const Normals normals = face_normals(m.positions, m.triangles);
  const Normals local_normals = sub.face_rows(normals);
  for (Eigen::Index i = 0; i < sub.face_count(); ++i)
    EXPECT_EQ(local_normals.row(i), normals.row(faces[static_cast<size_t>(i)]));
}

TEST(Submesh, EmptyAndWhole) {
  const test::Mesh m = test::cube();
  const Submesh none = submesh(m.triangles, m.positions.rows(), {});
  EXPECT_EQ(none.vertex_count(), 0);
  EXPECT_EQ(none.face_count(), 0);
  std::vector<Eigen::Index> all(static_cast<size_t>(m.triangles.rows()));
  for (size_t f = 0; f < all.size(); ++f) all[f] = static_cast<Eigen::Index>(f);
  const Submesh whole = submesh(m.triangles, m.positions.rows(), all);
  EXPECT_EQ(whole.triangles, m.triangles);
  EXPECT_EQ(whole.vertex_rows(m.positions), m.positions);
}

TEST(Submesh, FacesOfPiecesAscending) {
  const std::vector<int> pieces{2, 0, 2, 1, 0, 2};
  const std::vector<std::vector<Eigen::Index>> faces = faces_of_pieces(pieces, 4);
  ASSERT_EQ(faces.size(), 4u);
  EXPECT_EQ(faces[0], (std::vector<Eigen::Index>{1, 4}));
  EXPECT_EQ(faces[1], (std::vector<Eigen::Index>{3}));
  EXPECT_EQ(faces[2], (std::vector<Eigen::Index>{0, 2, 5}));
  EXPECT_TRUE(faces[3].empty());
}

}  // namespace
}  // namespace developable

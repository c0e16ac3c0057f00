// mesh_connectivity.h: the faces around each vertex, ascending, and the face
// across each edge, on a closed and an open mesh; validate_mesh returns the
// same table.
#include "core/mesh_connectivity.h"

#include "core/mesh_input.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <map>

namespace developable {
namespace {

TEST(MeshConnectivity, FacesAroundEachVertex) {
  for (const auto& m : {test::cube(), test::plane(5, 6), test::cylinder(4, 9)}) {
    const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
    ASSERT_EQ(table.vertex_count(), m.positions.rows());
    EXPECT_EQ(table.faces.size(), static_cast<size_t>(3 * m.triangles.rows()));
    for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
      std::vector<int> expected;
      for (int f = 0; f < m.triangles.rows(); ++f)
        if ((m.triangles.row(f).array() == v).any()) expected.push_back(f);
      EXPECT_EQ(std::vector<int>(table.begin(v), table.end(v)), expected) << "vertex " << v;
    }
    const VertexFaces validated = validate_mesh(m.positions, m.triangles);
    EXPECT_EQ(validated.offsets, table.offsets);
    EXPECT_EQ(validated.faces, table.faces);
  }
}

TEST(MeshConnectivity, FaceAcrossEachEdge) {
  for (const auto& m : {test::cube(), test::plane(5, 6)}) {
    const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
    std::map<std::pair<int, int>, std::vector<int>> edge_faces;
    for (int f = 0; f < m.triangles.rows(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int a = m.triangles(f, c), b = m.triangles(f, (c + 1) % 3);
        edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
      }
    for (int f = 0; f < m.triangles.rows(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int a = m.triangles(f, c), b = m.triangles(f, (c + 1) % 3);
        const auto& faces = edge_faces[{std::min(a, b), std::max(a, b)}];
        const int other = faces.size() == 2 ? (faces[0] == f ? faces[1] : faces[0]) : -1;
        EXPECT_EQ(face_across(table, m.triangles, f, a, b), other);
      }
  }
}

}  // namespace
}  // namespace developable

#include "core/mesh_connectivity.h"

namespace developable {

VertexFaces vertex_faces(const Triangles& triangles, Eigen::Index vertex_count) {
  VertexFaces table;
  table.offsets.assign(static_cast<size_t>(vertex_count) + 1, 0);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) ++table.offsets[static_cast<size_t>(triangles(f, c)) + 1];
  for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) table.offsets[v + 1] += table.offsets[v];
  table.faces.resize(static_cast<size_t>(table.offsets.back()));
  std::vector<int> fill(table.offsets.begin(), table.offsets.end() - 1);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      table.faces[static_cast<size_t>(fill[static_cast<size_t>(triangles(f, c))]++)] = static_cast<int>(f);
  return table;
}

int face_across(const VertexFaces& table, const Triangles& triangles, int face, int a, int b) {
  for (const int* g = table.begin(a); g != table.end(a); ++g)
    if (*g != face && (triangles(*g, 0) == b || triangles(*g, 1) == b || triangles(*g, 2) == b)) return *g;
  return -1;
}

}  // namespace developable

// Mesh connectivity shared by the stages: the faces around each vertex, in
// compressed rows, built once per mesh (validate_mesh returns it; the
// pipeline hands it to segmentation and target smoothing).
//
// The engine's own table rather than OpenMesh's halfedge mesh: it is what the
// stages read (faces around a vertex, faces across an edge), it holds
// non-manifold input that the validation has yet to refuse, and it builds in
// a small fraction of OpenMesh's time (docs/architecture.md has the
// measurement, bench/connectivity.cpp).
#pragma once

#include "core/types.h"

#include <vector>

namespace developable {

struct VertexFaces {
  // Vertex v's faces are faces[offsets[v] .. offsets[v + 1]), ascending.
  std::vector<int> offsets;  // vertex count + 1 entries
  std::vector<int> faces;    // 3 entries per triangle

  Eigen::Index vertex_count() const { return static_cast<Eigen::Index>(offsets.size()) - 1; }
  const int* begin(Eigen::Index v) const { return faces.data() + offsets[static_cast<size_t>(v)]; }
  const int* end(Eigen::Index v) const { return faces.data() + offsets[static_cast<size_t>(v) + 1]; }
  int count(Eigen::Index v) const { return offsets[static_cast<size_t>(v) + 1] - offsets[static_cast<size_t>(v)]; }
};

// The faces around each of `vertex_count` vertices.
//   triangles: indices in 0 .. vertex_count-1 (checked by the caller; no
//   other requirement: works on non-manifold input). O(faces) time and memory.
VertexFaces vertex_faces(const Triangles& triangles, Eigen::Index vertex_count);

// The face across edge (a, b) from `face`: the other face around a that also
// holds b, or -1 on a boundary edge. On a manifold mesh there is at most one.
int face_across(const VertexFaces& table, const Triangles& triangles, int face, int a, int b);

}  // namespace developable

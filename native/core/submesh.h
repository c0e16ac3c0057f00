// The submesh of a set of faces: its triangles over vertices of its own and
// the maps back to the whole mesh. A stage that only needs a region (the
// angle-defect polish's active faces, one piece to split, the pieces a
// second round settles) runs on it and writes its rows back.
#pragma once

#include "core/types.h"

#include <vector>

namespace developable {

// Faces and vertices keep their order in the whole mesh, so that a stage run
// on the submesh numbers them as the whole mesh would (the angle-defect
// polish relies on this for bit-identical results).
struct Submesh {
  std::vector<Eigen::Index> faces;     // submesh face i is mesh face faces[i]
  std::vector<Eigen::Index> vertices;  // submesh vertex i is mesh vertex vertices[i], ascending
  std::vector<int> local_of;           // per mesh vertex: its submesh vertex, -1 outside
  Triangles triangles;                 // over the submesh's vertices

  Eigen::Index vertex_count() const { return static_cast<Eigen::Index>(vertices.size()); }
  Eigen::Index face_count() const { return static_cast<Eigen::Index>(faces.size()); }

  // The rows of `whole` (one per mesh vertex) at the submesh's vertices.
  Positions vertex_rows(const Positions& whole) const;
  // The rows of `whole` (one per mesh face: normals) at the submesh's faces.
  Positions face_rows(const Positions& whole) const;
  // `local` (one row per submesh vertex) written into `whole` at its vertices.
  void scatter(const Positions& local, Positions& whole) const;
};

// The submesh of `faces` (ascending ids of `triangles`, whose vertices are
// 0 .. vertex_count-1). O(faces + vertex_count).
Submesh submesh(const Triangles& triangles, Eigen::Index vertex_count, std::vector<Eigen::Index> faces);

// The faces of each of `count` pieces (`pieces`: an id 0 .. count-1 per face),
// ascending: bucketed once, O(faces).
std::vector<std::vector<Eigen::Index>> faces_of_pieces(const std::vector<int>& pieces, int count);

}  // namespace developable

#include "core/submesh.h"

namespace developable {

Positions Submesh::vertex_rows(const Positions& whole) const {
  Positions rows(vertex_count(), 3);
  for (Eigen::Index i = 0; i < vertex_count(); ++i) rows.row(i) = whole.row(vertices[static_cast<size_t>(i)]);
  return rows;
}

Positions Submesh::face_rows(const Positions& whole) const {
  Positions rows(face_count(), 3);
  for (Eigen::Index i = 0; i < face_count(); ++i) rows.row(i) = whole.row(faces[static_cast<size_t>(i)]);
  return rows;
}

void Submesh::scatter(const Positions& local, Positions& whole) const {
  for (Eigen::Index i = 0; i < vertex_count(); ++i) whole.row(vertices[static_cast<size_t>(i)]) = local.row(i);
}

Submesh submesh(const Triangles& triangles, Eigen::Index vertex_count, std::vector<Eigen::Index> faces) {
  Submesh out;
  out.faces = std::move(faces);
  out.local_of.assign(static_cast<size_t>(vertex_count), -1);
  for (Eigen::Index f : out.faces)
    for (int c = 0; c < 3; ++c) out.local_of[static_cast<size_t>(triangles(f, c))] = 0;
  for (Eigen::Index v = 0; v < vertex_count; ++v)
    if (out.local_of[static_cast<size_t>(v)] == 0) {
      out.local_of[static_cast<size_t>(v)] = static_cast<int>(out.vertices.size());
      out.vertices.push_back(v);
    }
  out.triangles.resize(out.face_count(), 3);
  for (Eigen::Index i = 0; i < out.face_count(); ++i)
    for (int c = 0; c < 3; ++c)
      out.triangles(i, c) = out.local_of[static_cast<size_t>(triangles(out.faces[static_cast<size_t>(i)], c))];
  return out;
}

std::vector<std::vector<Eigen::Index>> faces_of_pieces(const std::vector<int>& pieces, int count) {
  std::vector<std::vector<Eigen::Index>> out(static_cast<size_t>(count));
  for (size_t f = 0; f < pieces.size(); ++f)
    out[static_cast<size_t>(pieces[f])].push_back(static_cast<Eigen::Index>(f));
  return out;
}

}  // namespace developable

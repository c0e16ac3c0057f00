#include "segmentation/curved_pieces.h"

#include "segmentation/segmentation.h"

#include <algorithm>

namespace developable {
namespace {

// The faces of one piece as a mesh of their own; faces[i] is its face i.
struct PieceMesh {
  std::vector<int> faces;
  Positions positions;
  Triangles triangles;
};

PieceMesh piece_mesh(const Positions& positions, const Triangles& triangles, const std::vector<int>& pieces,
                     int piece) {
  PieceMesh out;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    if (pieces[static_cast<size_t>(f)] == piece) out.faces.push_back(static_cast<int>(f));
  std::vector<int> local(static_cast<size_t>(positions.rows()), -1);
  std::vector<int> global;
  out.triangles.resize(static_cast<Eigen::Index>(out.faces.size()), 3);
  for (size_t i = 0; i < out.faces.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      int& v = local[static_cast<size_t>(triangles(out.faces[i], c))];
      if (v < 0) {
        v = static_cast<int>(global.size());
        global.push_back(triangles(out.faces[i], c));
      }
      out.triangles(static_cast<Eigen::Index>(i), c) = v;
    }
  out.positions.resize(static_cast<Eigen::Index>(global.size()), 3);
  for (size_t v = 0; v < global.size(); ++v) out.positions.row(static_cast<Eigen::Index>(v)) = positions.row(global[v]);
  return out;
}

}  // namespace

std::vector<bool> curved_pieces(const std::vector<int>& pieces, int count, const VertexFaces& connectivity,
                                const std::vector<bool>& inside, const std::vector<bool>& developable, double share,
                                int min_inside) {
  std::vector<int> total(static_cast<size_t>(count), 0), good(static_cast<size_t>(count), 0);
  for (Eigen::Index v = 0; v < connectivity.vertex_count(); ++v) {
    if (!inside[static_cast<size_t>(v)] || connectivity.count(v) == 0) continue;
    const auto piece = static_cast<size_t>(pieces[static_cast<size_t>(*connectivity.begin(v))]);
    ++total[piece];
    if (developable[static_cast<size_t>(v)]) ++good[piece];
  }
  std::vector<bool> split(static_cast<size_t>(count), false);
  for (size_t p = 0; p < split.size(); ++p) split[p] = total[p] >= min_inside && good[p] < share * total[p];
  return split;
}

std::vector<int> split_in_two(const Positions& positions, const Triangles& triangles, const std::vector<int>& pieces,
                              int count, const std::vector<bool>& split, const Progress& progress) {
  std::vector<int> out = pieces;
  int next = count;
  SegmentationOptions two;
  two.target_patches = 2;
  for (int piece = 0; piece < count; ++piece) {
    if (!split[static_cast<size_t>(piece)]) continue;
    progress.report(static_cast<double>(piece) / count, "splitting curved pieces");
    const PieceMesh mesh = piece_mesh(positions, triangles, pieces, piece);
    const std::vector<int> parts = segment_mesh(mesh.positions, mesh.triangles, two, progress.sub(0.0, 0.0));
    // segment_mesh numbers its patches in the order of their first faces:
    // part 0 holds the piece's lowest face. More than two parts only where
    // the piece is in more than one component of its own.
    const int extra = *std::max_element(parts.begin(), parts.end());
    for (size_t i = 0; i < parts.size(); ++i)
      if (parts[i] > 0) out[static_cast<size_t>(mesh.faces[i])] = next + parts[i] - 1;
    next += extra;
  }
  return out;
}

}  // namespace developable

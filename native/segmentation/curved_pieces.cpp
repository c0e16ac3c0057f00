#include "segmentation/curved_pieces.h"

#include "core/submesh.h"
#include "segmentation/segmentation.h"

#include <algorithm>

namespace developable {
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
  std::vector<std::vector<Eigen::Index>> faces = faces_of_pieces(pieces, count);
  for (int piece = 0; piece < count; ++piece) {
    if (!split[static_cast<size_t>(piece)]) continue;
    progress.report(static_cast<double>(piece) / count, "splitting curved pieces");
    const Submesh mesh = submesh(triangles, positions.rows(), std::move(faces[static_cast<size_t>(piece)]));
    const std::vector<int> parts =
        segment_mesh(mesh.vertex_rows(positions), mesh.triangles, two, progress.sub(0.0, 0.0));
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

#include "segmentation/normal_jump_pieces.h"

#include "core/union_find.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace developable {
namespace {

struct FaceEdge {
  int f, g;      // f < g
  double angle;  // between their normals, rad
  bool creased;  // wider than its reference angle plus the growth
};

// Every edge between two faces, once, with its normal jump.
std::vector<FaceEdge> face_edges(const Triangles& triangles, const VertexFaces& connectivity, const Normals& normals,
                                 const Normals& reference, double growth) {
  std::vector<FaceEdge> edges;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      const int g = face_across(connectivity, triangles, static_cast<int>(f), a, b);
      if (g <= f) continue;
      const double cosine = std::clamp(normals.row(f).dot(normals.row(g)), -1.0, 1.0);
      const double angle = std::acos(cosine);
      bool creased = false;
      if (reference.rows() > 0) {
        const double before = std::acos(std::clamp(reference.row(f).dot(reference.row(g)), -1.0, 1.0));
        creased = angle > before + growth;
      }
      edges.push_back({static_cast<int>(f), g, angle, creased});
    }
  return edges;
}

// Labels 0 .. count-1 numbered by each set's lowest face.
std::vector<int> numbered(std::vector<int> labels) {
  std::vector<int> number(labels.size(), -1);
  int count = 0;
  for (int& l : labels) {
    if (number[static_cast<size_t>(l)] < 0) number[static_cast<size_t>(l)] = count++;
    l = number[static_cast<size_t>(l)];
  }
  return labels;
}

// Whether some corner of a face of `piece` has all its faces in it (a
// vertex of its own; else every corner is also another piece's).
bool has_vertex_of_its_own(int piece, const std::vector<int>& labels, const Triangles& triangles,
                           const VertexFaces& connectivity) {
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    if (labels[static_cast<size_t>(f)] != piece) continue;
    for (int c = 0; c < 3; ++c) {
      const int v = triangles(f, c);
      if (std::all_of(connectivity.begin(v), connectivity.end(v),
                      [&](int g) { return labels[static_cast<size_t>(g)] == piece; }))
        return true;
    }
  }
  return false;
}

}  // namespace

std::vector<int> normal_jump_pieces(const Triangles& triangles, const VertexFaces& connectivity, const Normals& normals,
                                    double crease, int min_faces, const Normals& reference, double growth) {
  const Eigen::Index m = triangles.rows();
  if (!(crease >= 0.0) || min_faces < 1)
    throw EngineError(Status::invalid_argument, "crease pieces: crease >= 0 and min_faces >= 1");
  if (normals.rows() != m || (reference.rows() != 0 && reference.rows() != m))
    throw EngineError(Status::invalid_argument, "crease pieces: one normal per face");
  const std::vector<FaceEdge> edges = face_edges(triangles, connectivity, normals, reference, growth);
  UnionFind sets(static_cast<size_t>(m));
  for (const FaceEdge& e : edges)
    if (e.angle <= crease) sets.unite(e.f, e.g);
  std::vector<int> labels(static_cast<size_t>(m));
  for (Eigen::Index f = 0; f < m; ++f) labels[static_cast<size_t>(f)] = sets.find(static_cast<int>(f));
  labels = numbered(std::move(labels));
  int count = m > 0 ? 1 + *std::max_element(labels.begin(), labels.end()) : 0;
  std::vector<int> size(static_cast<size_t>(count), 0);
  for (int l : labels) ++size[static_cast<size_t>(l)];
  // Merge the small pieces, smallest first. Each merge rescans the border
  // edges: the count of small pieces is small after a crease split of a
  // thinned mesh (hundreds), and a scan is linear in the edges.
  std::vector<bool> stuck(static_cast<size_t>(count), false);
  for (;;) {
    int smallest = -1;
    for (int p = 0; p < count; ++p)
      if (size[static_cast<size_t>(p)] > 0 && size[static_cast<size_t>(p)] < min_faces &&
          !stuck[static_cast<size_t>(p)] &&
          (smallest < 0 || size[static_cast<size_t>(p)] < size[static_cast<size_t>(smallest)]))
        smallest = p;
    if (smallest < 0) break;
    struct Border {
      double sum = 0.0;
      int edges = 0;
      bool creased = false;
    };
    std::map<int, Border> border;  // by neighbour
    for (const FaceEdge& e : edges) {
      const int a = labels[static_cast<size_t>(e.f)], b = labels[static_cast<size_t>(e.g)];
      if (a == b || (a != smallest && b != smallest)) continue;
      Border& entry = border[a == smallest ? b : a];
      entry.sum += e.angle;
      entry.edges += 1;
      entry.creased = entry.creased || e.creased;
    }
    // A piece with no vertex of its own has no surface to make developable:
    // it joins a neighbour whatever its borders (asked only where one is
    // creased: else the answer changes nothing).
    const bool any_creased = std::any_of(border.begin(), border.end(), [](const auto& b) { return b.second.creased; });
    const bool crosses_creases = any_creased && !has_vertex_of_its_own(smallest, labels, triangles, connectivity);
    int into = -1;
    double best = 0.0;
    for (const auto& [piece, b] : border) {
      const double mean = b.sum / b.edges;
      if ((!b.creased || crosses_creases) && (into < 0 || mean < best)) into = piece, best = mean;
    }
    if (into < 0) {
      stuck[static_cast<size_t>(smallest)] = true;
      continue;
    }
    for (int& l : labels)
      if (l == smallest) l = into;
    size[static_cast<size_t>(into)] += size[static_cast<size_t>(smallest)];
    size[static_cast<size_t>(smallest)] = 0;
  }
  return numbered(std::move(labels));
}

}  // namespace developable

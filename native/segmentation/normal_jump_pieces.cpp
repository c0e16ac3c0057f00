#include "segmentation/normal_jump_pieces.h"

#include "core/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <queue>

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

// Whether some corner of the piece of `faces` has all its faces in it (a
// vertex of its own; else every corner is also another piece's).
bool has_vertex_of_its_own(const std::vector<int>& faces, const std::vector<int>& labels, const Triangles& triangles,
                           const VertexFaces& connectivity) {
  const int piece = labels[static_cast<size_t>(faces.front())];
  for (const int f : faces) {
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
  const int count = m > 0 ? 1 + *std::max_element(labels.begin(), labels.end()) : 0;
  // Merge the small pieces, smallest first (the lowest id of equal sizes).
  // A merge reads only the small piece's own faces and border edges, in the
  // order of `edges`, so its sums and choice are those of a scan of them all.
  std::vector<std::vector<int>> faces_of(static_cast<size_t>(count));
  for (Eigen::Index f = 0; f < m; ++f)
    faces_of[static_cast<size_t>(labels[static_cast<size_t>(f)])].push_back(static_cast<int>(f));
  std::vector<std::array<int, 3>> edges_of(static_cast<size_t>(m), {-1, -1, -1});  // indices into `edges`
  for (size_t e = 0; e < edges.size(); ++e)
    for (const int f : {edges[e].f, edges[e].g}) {
      std::array<int, 3>& slots = edges_of[static_cast<size_t>(f)];
      *std::find(slots.begin(), slots.end(), -1) = static_cast<int>(e);
    }
  const auto size = [&](int piece) { return static_cast<int>(faces_of[static_cast<size_t>(piece)].size()); };
  using Entry = std::pair<int, int>;  // (size, piece), smallest first
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int p = 0; p < count; ++p)
    if (size(p) < min_faces) queue.emplace(size(p), p);
  std::vector<bool> stuck(static_cast<size_t>(count), false);  // no border it may cross, for good
  std::vector<int> border_edges;
  while (!queue.empty()) {
    const auto [entry_size, smallest] = queue.top();
    queue.pop();
    if (entry_size != size(smallest) || stuck[static_cast<size_t>(smallest)])
      continue;  // merged, grown since, or stuck
    border_edges.clear();
    for (const int f : faces_of[static_cast<size_t>(smallest)])
      for (const int e : edges_of[static_cast<size_t>(f)])
        if (e >= 0 && labels[static_cast<size_t>(edges[static_cast<size_t>(e)].f)] !=
                          labels[static_cast<size_t>(edges[static_cast<size_t>(e)].g)])
          border_edges.push_back(e);
    std::sort(border_edges.begin(), border_edges.end());
    struct Border {
      double sum = 0.0;
      int edges = 0;
      bool creased = false;
    };
    std::map<int, Border> border;  // by neighbour
    for (const int index : border_edges) {
      const FaceEdge& e = edges[static_cast<size_t>(index)];
      const int a = labels[static_cast<size_t>(e.f)], b = labels[static_cast<size_t>(e.g)];
      Border& entry = border[a == smallest ? b : a];
      entry.sum += e.angle;
      entry.edges += 1;
      entry.creased = entry.creased || e.creased;
    }
    // A piece with no vertex of its own has no surface to make developable:
    // it joins a neighbour whatever its borders (asked only where one is
    // creased: else the answer changes nothing).
    const bool any_creased = std::any_of(border.begin(), border.end(), [](const auto& b) { return b.second.creased; });
    const bool crosses_creases =
        any_creased && !has_vertex_of_its_own(faces_of[static_cast<size_t>(smallest)], labels, triangles, connectivity);
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
    std::vector<int>& merged = faces_of[static_cast<size_t>(into)];
    for (const int f : faces_of[static_cast<size_t>(smallest)]) {
      labels[static_cast<size_t>(f)] = into;
      merged.push_back(f);
    }
    faces_of[static_cast<size_t>(smallest)] = {};
    if (size(into) < min_faces) queue.emplace(size(into), into);
  }
  return numbered(std::move(labels));
}

}  // namespace developable

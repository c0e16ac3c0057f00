#include "pattern/piece_split.h"

#include "core/measures.h"
#include "core/union_find.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace developable::unfolding {
namespace {

using Vec3 = Eigen::Vector3d;

// The disc a chord is drawn on: the piece cut open, its graph of inner
// edges and where each border vertex sits along the border.
struct Disc {
  EdgeTable edges;
  std::vector<char> is_cut;
  PieceTopology t;
  VertexGraph g;
  std::vector<char> border;  // per vertex
  std::vector<double> arc;   // per border vertex: arc length from the loop's start
  double perimeter = 0.0;
};

bool open_disc(const Positions& positions, const LocalPiece& piece, Disc& d) {
  d.edges = edge_table(piece.tris);
  d.is_cut.assign(d.edges.keys.size(), 0);
  if (!choose_cuts(positions, piece, d.edges, Holes::join, d.is_cut)) return false;
  d.t = piece_topology(piece, d.edges, d.is_cut);
  if (!d.t.flattenable() || d.t.loops.size() != 1) return false;
  d.g = vertex_graph(positions, piece, d.edges, d.t.verts, d.is_cut);
  d.border.assign(d.t.verts.count, 0);
  d.arc.assign(d.t.verts.count, 0.0);
  for (int fe : d.t.loops[0]) {
    const int v = d.t.verts.of_corner[fe];
    d.border[v] = 1;
    d.arc[v] = d.perimeter;
    d.perimeter += d.g.length[d.edges.of_face_edge[fe]];
  }
  return true;
}

// |angle defect| of every vertex of the disc off its border (0 on it).
std::vector<double> inner_defects(const Positions& positions, const LocalPiece& piece, const Disc& d) {
  std::vector<double> angle(d.t.verts.count, 0.0);
  for (size_t f = 0; f < piece.tris.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3 c = positions.row(piece.tris[f][k]).transpose();
      const Vec3 u = positions.row(piece.tris[f][(k + 1) % 3]).transpose() - c;
      const Vec3 w = positions.row(piece.tris[f][(k + 2) % 3]).transpose() - c;
      angle[d.t.verts.of_corner[3 * f + k]] += std::atan2(u.cross(w).norm(), u.dot(w));
    }
  std::vector<double> out(d.t.verts.count, 0.0);
  for (int v = 0; v < d.t.verts.count; ++v)
    if (!d.border[v]) out[v] = std::abs(2.0 * M_PI - angle[v]);
  return out;
}

// An inner vertex with an edge in the graph nearest to position `i` of the
// path (alternately after and before it), or -1.
int inner_near(const std::vector<int>& path, size_t i, const Disc& d) {
  for (size_t step = 0; step < path.size(); ++step)
    for (const size_t j : {i + step, i - step}) {
      if (j >= path.size()) continue;
      const int v = path[j];
      if (!d.border[v] && d.g.offsets[v + 1] > d.g.offsets[v]) return v;
    }
  return -1;
}

// The vertex halfway along a longest shortest path (two sweeps).
int middle_vertex(const Disc& d) {
  const ShortestPaths first = dijkstra(d.g, {0}, {});
  const ShortestPaths second = dijkstra(d.g, {first.reached}, {});
  std::vector<int> path;
  for (int v = second.reached; v >= 0; v = second.prev_vertex[v]) path.push_back(v);
  if (path.empty()) return -1;
  const double half = 0.5 * second.dist[second.reached];
  size_t i = 0;
  while (i + 1 < path.size() && second.dist[path[i]] > half) ++i;
  return inner_near(path, i, d);
}

int chord_centre(const Positions& positions, const LocalPiece& piece, const Disc& d, SplitThrough through) {
  if (through == SplitThrough::largest_defect) {
    std::vector<double> score = inner_defects(positions, piece, d);
    if (std::any_of(score.begin(), score.end(), [](double x) { return x >= kFlatDefect; })) {
      // Among the vertices that are not flat, |defect| times the distance
      // from the border: a central one of large curvature, not one the
      // border nearly reaches.
      std::vector<int> border;
      for (int v = 0; v < d.t.verts.count; ++v)
        if (d.border[v]) border.push_back(v);
      const ShortestPaths from_border = dijkstra(d.g, border, {});
      int worst = -1;
      for (int v = 0; v < d.t.verts.count; ++v) {
        if (d.border[v] || d.g.offsets[v + 1] == d.g.offsets[v] || !std::isfinite(from_border.dist[v]) ||
            score[v] < kFlatDefect)
          continue;
        score[v] *= from_border.dist[v];
        if (worst < 0 || score[v] > score[worst]) worst = v;
      }
      if (worst >= 0) return worst;
    }
  }
  return middle_vertex(d);
}

// The chord's edges through `centre` (see split_along_chord), or none.
std::vector<int> chord_edges(const Disc& d, int centre) {
  const ShortestPaths sp = dijkstra(d.g, {centre}, {}, d.border);
  const int n = d.t.verts.count;
  std::vector<int> order(n);
  for (int v = 0; v < n; ++v) order[v] = v;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return sp.dist[a] < sp.dist[b]; });
  std::vector<int> branch(n, -1);  // the first vertex after the centre on the way to v
  for (int v : order)
    if (sp.prev_vertex[v] >= 0) branch[v] = sp.prev_vertex[v] == centre ? v : branch[sp.prev_vertex[v]];
  int b1 = -1;
  for (int v = 0; v < n; ++v)
    if (d.border[v] && std::isfinite(sp.dist[v]) && (b1 < 0 || sp.dist[v] < sp.dist[b1])) b1 = v;
  if (b1 < 0) return {};
  const auto along = [&](int v) {
    const double gap = std::abs(d.arc[v] - d.arc[b1]);
    return std::min(gap, d.perimeter - gap);
  };
  // The other end: the least chord length per border length cut off.
  int b2 = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int v = 0; v < n; ++v) {
    if (!d.border[v] || !std::isfinite(sp.dist[v]) || branch[v] == branch[b1] || !(along(v) > 0.0)) continue;
    const double ratio = (sp.dist[b1] + sp.dist[v]) / along(v);
    if (ratio < best) best = ratio, b2 = v;
  }
  if (b2 < 0) return {};
  std::vector<int> chord;
  for (int end : {b1, b2})
    for (int v = end; sp.prev_edge[v] >= 0; v = sp.prev_vertex[v]) chord.push_back(sp.prev_edge[v]);
  return chord;
}

// The faces on either side of the chord (connected across the disc's other
// inner edges), or nothing unless there are exactly two sides.
std::array<std::vector<int>, 2> sides(const LocalPiece& piece, const Disc& d, const std::vector<int>& chord) {
  std::vector<char> blocked = d.is_cut;
  for (int e : chord) blocked[e] = 1;
  UnionFind uf(piece.tris.size());
  for (size_t e = 0; e < d.edges.keys.size(); ++e)
    if (d.edges.uses[e][1] >= 0 && !blocked[e]) uf.unite(d.edges.uses[e][0] / 3, d.edges.uses[e][1] / 3);
  const int first = uf.find(0);
  int second = -1;
  std::array<std::vector<int>, 2> out;
  for (size_t f = 0; f < piece.tris.size(); ++f) {
    const int root = uf.find(static_cast<int>(f));
    if (root != first && second < 0) second = root;
    if (root != first && root != second) return {};
    out[root == first ? 0 : 1].push_back(piece.faces[f]);
  }
  if (out[1].empty()) return {};
  return out;
}

}  // namespace

std::array<std::vector<int>, 2> split_along_chord(const Positions& positions, const LocalPiece& piece,
                                                  SplitThrough through) {
  Disc d;
  if (piece.tris.size() < 2 || !open_disc(positions, piece, d)) return {};
  const int centre = chord_centre(positions, piece, d, through);
  if (centre < 0) return {};
  const std::vector<int> chord = chord_edges(d, centre);
  if (chord.empty()) return {};
  return sides(piece, d, chord);
}

std::array<std::vector<int>, 2> split_across_axis(const Positions& positions, const Triangles& triangles,
                                                  const std::vector<int>& faces, const std::vector<int>& face_groups) {
  std::vector<Vec3> centroid(faces.size());
  Vec3 mean = Vec3::Zero();
  for (size_t i = 0; i < faces.size(); ++i) {
    const int f = faces[i];
    centroid[i] =
        (positions.row(triangles(f, 0)) + positions.row(triangles(f, 1)) + positions.row(triangles(f, 2))).transpose() /
        3.0;
    mean += centroid[i];
  }
  mean /= static_cast<double>(faces.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& c : centroid) cov += (c - mean) * (c - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Vec3 axis = eig.eigenvectors().col(2);
  const auto group = [&](int f) { return face_groups.empty() ? -1 - f : face_groups[f]; };
  std::unordered_map<int, std::pair<double, int>> place;  // group -> (sum, count)
  for (size_t i = 0; i < faces.size(); ++i) {
    auto& p = place[group(faces[i])];
    p.first += centroid[i].dot(axis);
    ++p.second;
  }
  std::vector<std::tuple<double, int, int>> order(faces.size());  // (place, group, face)
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto& p = place[group(faces[i])];
    order[i] = {p.first / p.second, group(faces[i]), faces[i]};
  }
  std::sort(order.begin(), order.end());
  size_t half = faces.size() / 2;
  while (half < order.size() && std::get<1>(order[half]) == std::get<1>(order[half - 1])) ++half;
  if (half == order.size()) half = faces.size() / 2;  // one group: split it after all
  std::array<std::vector<int>, 2> out;
  for (size_t i = 0; i < order.size(); ++i) out[i < half ? 0 : 1].push_back(std::get<2>(order[i]));
  return out;
}

}  // namespace developable::unfolding

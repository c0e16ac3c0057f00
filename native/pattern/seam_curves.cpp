#include "pattern/seam_curves.h"

#include "pattern/flatten.h"
#include "pattern/plane_geometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace developable::unfolding {
namespace {

using Vec2 = Eigen::Vector2d;

struct SeamEdge {
  int from, to, left, right;
};

int corner_of(const Triangles& triangles, int face, int vertex) {
  for (int k = 0; k < 3; ++k)
    if (triangles(face, k) == vertex) return k;
  return -1;
}

// The seam edges grouped by their pair of pieces.
std::map<std::pair<int, int>, std::vector<SeamEdge>> seam_edges(const Triangles& triangles, const EdgeTable& mesh_edges,
                                                                const std::vector<uint64_t>& cut_keys,
                                                                const UnfoldResult& result) {
  std::map<std::pair<int, int>, std::vector<SeamEdge>> groups;
  for (size_t e = 0; e < mesh_edges.keys.size(); ++e) {
    const auto [u0, u1] = mesh_edges.uses[e];
    if (u1 < 0) continue;
    const int f0 = u0 / 3, f1 = u1 / 3;
    const int p0 = result.piece_of_face[f0], p1 = result.piece_of_face[f1];
    if (p0 == p1 && !std::binary_search(cut_keys.begin(), cut_keys.end(), mesh_edges.keys[e])) continue;
    const int a = triangles(f0, u0 % 3), b = triangles(f0, (u0 % 3 + 1) % 3);
    groups[{std::min(p0, p1), std::max(p0, p1)}].push_back({a, b, f0, f1});
  }
  return groups;
}

// Flat lengths on both sides and the 3D length of a chained seam.
void measure_seam(const Positions& positions, const Triangles& triangles, const UnfoldResult& result,
                  UnfoldSeam& seam) {
  for (size_t i = 0; i < seam.edges.size(); ++i) {
    const auto [a, b] = seam.edges[i];
    seam.length_3d += (positions.row(a) - positions.row(b)).norm();
    for (int side = 0; side < 2; ++side) {
      const int f = seam.faces[i][side];
      const Vec2 qa = result.corners.row(3 * f + corner_of(triangles, f, a)).transpose();
      const Vec2 qb = result.corners.row(3 * f + corner_of(triangles, f, b)).transpose();
      (side == 0 ? seam.length_a : seam.length_b) += (qa - qb).norm();
    }
  }
}

// The chains of one group of seam edges.
void chain_group(const std::vector<SeamEdge>& list, const std::vector<int>& patch_ids, const UnfoldResult& result,
                 std::vector<UnfoldSeam>& seams) {
  const auto patch_of = [&](int f) { return patch_ids.empty() ? 0 : patch_ids[f]; };
  std::unordered_map<int, std::vector<int>> at_vertex;  // vertex -> edges of the group
  for (size_t i = 0; i < list.size(); ++i) {
    at_vertex[list[i].from].push_back(static_cast<int>(i));
    at_vertex[list[i].to].push_back(static_cast<int>(i));
  }
  std::vector<char> used(list.size(), 0);
  const auto walk = [&](int v, int e) {
    UnfoldSeam seam;
    while (e >= 0 && !used[e]) {
      used[e] = 1;
      const SeamEdge& s = list[e];
      // Directed from v: the face with the half-edge v -> w is on the left.
      const bool forward = s.from == v;
      const int w = forward ? s.to : s.from;
      seam.edges.push_back({v, w});
      seam.faces.push_back({forward ? s.left : s.right, forward ? s.right : s.left});
      v = w;
      e = -1;
      const auto& next = at_vertex[v];
      if (next.size() == 2) e = used[next[0]] ? next[1] : next[0];
    }
    seam.piece_a = result.piece_of_face[seam.faces[0][0]];
    seam.piece_b = result.piece_of_face[seam.faces[0][1]];
    seam.cut = patch_of(seam.faces[0][0]) == patch_of(seam.faces[0][1]);
    seams.push_back(std::move(seam));
  };
  std::vector<int> vertices;
  for (const auto& [v, incident] : at_vertex) vertices.push_back(v);
  std::sort(vertices.begin(), vertices.end());
  for (int v : vertices)  // chains end where the seam does not go on uniquely
    if (at_vertex[v].size() != 2)
      for (int e : at_vertex[v])
        if (!used[e]) walk(v, e);
  for (size_t e = 0; e < list.size(); ++e)  // closed chains
    if (!used[e]) walk(list[e].from, static_cast<int>(e));
}

// Where each outline row (3 f + k) sits: piece, loop and index, or -1.
struct OutlineIndex {
  std::vector<int> loop, index;
};

OutlineIndex outline_index(const UnfoldResult& result) {
  OutlineIndex at;
  at.loop.assign(result.corners.rows(), -1);
  at.index.assign(result.corners.rows(), -1);
  for (const UnfoldPiece& piece : result.pieces)
    for (size_t l = 0; l < piece.outline.size(); ++l)
      for (size_t j = 0; j < piece.outline[l].size(); ++j) {
        at.loop[piece.outline[l][j]] = static_cast<int>(l);
        at.index[piece.outline[l][j]] = static_cast<int>(j);
      }
  return at;
}

// The outline row of the face-edge from -> to of face f, or -1.
Eigen::Index row_of(const Triangles& triangles, int f, int from) {
  const int k = corner_of(triangles, f, from);
  return k < 0 ? -1 : 3 * static_cast<Eigen::Index>(f) + k;
}

// One seam's points on each side: the outline positions (loop, index) of its
// chain's vertices 0 .. n-1 (n = edges, + 1 if open), or empty when an edge
// is not on its outline.
struct SeamPoints {
  bool closed = false;
  std::array<std::vector<std::array<int, 2>>, 2> at;  // per side: (loop, index)
};

SeamPoints seam_points(const Triangles& triangles, const OutlineIndex& index, const UnfoldSeam& seam) {
  SeamPoints s;
  const size_t m = seam.edges.size();
  s.closed = m >= 3 && seam.edges.front()[0] == seam.edges.back()[1];
  const size_t n = s.closed ? m : m + 1;
  for (int side = 0; side < 2; ++side)
    for (size_t i = 0; i < n; ++i) {
      // Side a: the start of edge i. Side b runs backwards: vertex i ends
      // edge i - 1 there, which starts at it on side b (the last vertex of
      // an open chain: the start of edge m - 1 on side a ends it).
      Eigen::Index row;
      if (side == 0)
        row = i < m ? row_of(triangles, seam.faces[i][0], seam.edges[i][0]) : -2;
      else
        row =
            i > 0 || s.closed ? row_of(triangles, seam.faces[(i + m - 1) % m][1], seam.edges[(i + m - 1) % m][1]) : -2;
      if (row == -2) {  // an open chain's end: found through its neighbour below
        s.at[side].push_back({-1, -1});
        continue;
      }
      if (row < 0 || index.loop[row] < 0) return {};
      s.at[side].push_back({index.loop[row], index.index[row]});
    }
  return s;
}

// The signed turns of a polyline at its points (0 at an open one's ends).
std::vector<double> turns_of(const std::vector<Vec2>& p, bool closed) {
  const size_t n = p.size();
  std::vector<double> turns(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (!closed && (i == 0 || i + 1 == n)) continue;
    const Vec2 u = p[i] - p[(i + n - 1) % n], w = p[(i + 1) % n] - p[i];
    turns[i] = std::atan2(cross2(u, w), u.dot(w));
  }
  return turns;
}

}  // namespace

std::vector<UnfoldSeam> seam_chains(const Positions& positions, const Triangles& triangles,
                                    const std::vector<int>& patch_ids, const EdgeTable& mesh_edges,
                                    const std::vector<uint64_t>& cut_keys, const UnfoldResult& result) {
  std::vector<UnfoldSeam> seams;
  for (const auto& group : seam_edges(triangles, mesh_edges, cut_keys, result))
    chain_group(group.second, patch_ids, result, seams);
  for (UnfoldSeam& seam : seams) measure_seam(positions, triangles, result, seam);
  return seams;
}

std::vector<char> zigzag_points(const std::vector<double>& turns, bool closed, double min_turn, int max_gap) {
  const int n = static_cast<int>(turns.size());
  std::vector<char> zig(n, 0);
  const auto sharp = [&](int i) { return std::abs(turns[i]) > min_turn; };
  for (int i = 0; i < n; ++i)
    for (int j : {i - 1, i + 1}) {
      if (!closed && (j < 0 || j >= n)) continue;
      const int k = (j + n) % n;
      if (k != i && sharp(i) && sharp(k) && turns[i] * turns[k] < 0) zig[i] = 1;
    }
  // Fill short gaps between zigzag points.
  std::vector<char> out = zig;
  int last = -1;
  for (int i = 0; i < (closed ? 2 * n : n); ++i) {
    if (!zig[i % n]) continue;
    if (last >= 0 && i - last <= max_gap + 1)
      for (int j = last + 1; j < i; ++j) out[j % n] = 1;
    last = i;
  }
  if (!closed && n > 0) out[0] = out[n - 1] = 0;
  return out;
}

void smooth_polyline(std::vector<Vec2>& points, const std::vector<char>& movable, bool closed, int rounds) {
  const size_t n = points.size();
  if (n < 3) return;
  for (int r = 0; r < rounds; ++r) {
    const std::vector<Vec2> before = points;
    for (size_t i = 0; i < n; ++i) {
      if (!movable[i] || (!closed && (i == 0 || i + 1 == n))) continue;
      points[i] = 0.25 * (before[(i + n - 1) % n] + 2.0 * before[i] + before[(i + 1) % n]);
    }
  }
}

void smooth_outlines(const Triangles& triangles, const std::vector<UnfoldSeam>& seams, UnfoldResult& result) {
  for (UnfoldPiece& piece : result.pieces) {
    piece.outline_curve.assign(piece.outline.size(), {});
    for (size_t l = 0; l < piece.outline.size(); ++l)
      for (Eigen::Index row : piece.outline[l]) piece.outline_curve[l].push_back(result.corners.row(row).transpose());
  }
  const OutlineIndex index = outline_index(result);
  std::vector<SeamPoints> points(seams.size());
  std::vector<std::vector<char>> movable(seams.size());
  for (size_t s = 0; s < seams.size(); ++s) {
    points[s] = seam_points(triangles, index, seams[s]);
    if (points[s].at[0].empty()) continue;
    std::vector<Vec2> side_a;
    // ... measured on side a (its open end's point: the end of the last edge).
    const UnfoldPiece& a = result.pieces[seams[s].piece_a];
    for (size_t i = 0; i < points[s].at[0].size(); ++i) {
      if (points[s].at[0][i][0] < 0) {
        const auto [l, j] = points[s].at[0][i - 1];
        points[s].at[0][i] = {l, (j + 1) % static_cast<int>(a.outline[l].size())};
      }
      const auto [l, j] = points[s].at[0][i];
      side_a.push_back(a.outline_curve[l][j]);
    }
    const UnfoldPiece& b = result.pieces[seams[s].piece_b];
    if (points[s].at[1][0][0] < 0) {  // side b's open start: the end of its first edge
      auto [l, j] = points[s].at[1][1];
      points[s].at[1][0] = {l, (j + 1) % static_cast<int>(b.outline[l].size())};
    }
    movable[s] = zigzag_points(turns_of(side_a, points[s].closed), points[s].closed);
  }
  // Smooth, and take back the seams of pieces whose outline would cross itself.
  std::vector<char> kept(seams.size(), 1);
  for (int round = 0; round < 4; ++round) {
    std::vector<std::vector<std::vector<Vec2>>> curves(result.pieces.size());
    for (size_t p = 0; p < result.pieces.size(); ++p) curves[p] = result.pieces[p].outline_curve;
    for (size_t s = 0; s < seams.size(); ++s) {
      if (!kept[s] || movable[s].empty() ||
          std::none_of(movable[s].begin(), movable[s].end(), [](char c) { return c; }))
        continue;
      for (int side = 0; side < 2; ++side) {
        const int p = side == 0 ? seams[s].piece_a : seams[s].piece_b;
        std::vector<Vec2> polyline;
        for (const auto& [l, j] : points[s].at[side]) polyline.push_back(curves[p][l][j]);
        smooth_polyline(polyline, movable[s], points[s].closed);
        for (size_t i = 0; i < polyline.size(); ++i)
          curves[p][points[s].at[side][i][0]][points[s].at[side][i][1]] = polyline[i];
      }
    }
    bool all_simple = true;
    for (size_t p = 0; p < result.pieces.size(); ++p) {
      std::vector<Vec2> flat;
      std::vector<std::array<int, 2>> segments;
      for (const auto& loop : curves[p]) {
        const int first = static_cast<int>(flat.size()), n = static_cast<int>(loop.size());
        for (int i = 0; i < n; ++i) flat.push_back(loop[i]), segments.push_back({first + i, first + (i + 1) % n});
      }
      if (outline_is_simple(flat, segments)) continue;
      all_simple = false;
      for (size_t s = 0; s < seams.size(); ++s)
        if (seams[s].piece_a == static_cast<int>(p) || seams[s].piece_b == static_cast<int>(p)) kept[s] = 0;
    }
    if (all_simple) {
      for (size_t p = 0; p < result.pieces.size(); ++p) result.pieces[p].outline_curve = std::move(curves[p]);
      return;
    }
  }
}

}  // namespace developable::unfolding

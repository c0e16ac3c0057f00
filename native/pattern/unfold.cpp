#include "pattern/unfold.h"

#include "core/union_find.h"
#include "pattern/plane_geometry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <tuple>
#include <unordered_map>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

constexpr double kTwoPi = 2.0 * M_PI;

uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

// The undirected edges of a set of faces. Edge k of a face runs from its
// corner k to corner k + 1; `faces` of an edge holds the face-edge uses
// (3 f + k, f local), at most two on a manifold mesh.
struct EdgeTable {
  std::vector<uint64_t> keys;
  std::vector<std::array<int, 2>> uses;  // -1 when the edge has one face
  std::vector<int> of_face_edge;         // per 3 f + k: edge id
};

EdgeTable edge_table(const std::vector<std::array<int, 3>>& tris) {
  const size_t n = tris.size() * 3;
  std::vector<std::pair<uint64_t, int>> half(n);
  for (size_t f = 0; f < tris.size(); ++f)
    for (int k = 0; k < 3; ++k)
      half[3 * f + k] = {edge_key(tris[f][k], tris[f][(k + 1) % 3]), static_cast<int>(3 * f + k)};
  std::sort(half.begin(), half.end());
  EdgeTable table;
  table.of_face_edge.assign(n, -1);
  for (size_t i = 0; i < n;) {
    size_t j = i;
    std::array<int, 2> uses{-1, -1};
    while (j < n && half[j].first == half[i].first) {
      if (j - i < 2) uses[j - i] = half[j].second;
      table.of_face_edge[half[j].second] = static_cast<int>(table.keys.size());
      ++j;
    }
    table.keys.push_back(half[i].first);
    table.uses.push_back(uses);
    i = j;
  }
  return table;
}

// One piece being unfolded: its faces (global ids) and local triangles.
struct LocalPiece {
  std::vector<int> faces;
  std::vector<std::array<int, 3>> tris;  // vertex ids of the mesh
  std::vector<int> groups;               // per face: its group, -1 for none
  // An edge inside a group (both faces in one polygon) is never cut.
  bool inner(const std::array<int, 2>& uses) const {
    return uses[1] >= 0 && groups[uses[0] / 3] >= 0 && groups[uses[0] / 3] == groups[uses[1] / 3];
  }
};

LocalPiece local_piece(const Triangles& triangles, std::vector<int> faces, const std::vector<int>& face_groups) {
  LocalPiece piece;
  piece.faces = std::move(faces);
  piece.tris.reserve(piece.faces.size());
  for (int f : piece.faces) {
    piece.tris.push_back({triangles(f, 0), triangles(f, 1), triangles(f, 2)});
    piece.groups.push_back(face_groups.empty() ? -1 : face_groups[f]);
  }
  return piece;
}

// Vertices of a piece as classes of corners joined across the edges that are
// neither on the border nor cut. Pinched vertices (two fans of the piece meet
// there) become separate vertices; so do the two sides of a cut.
struct CornerVertices {
  std::vector<int> of_corner;  // 3 f + k -> vertex 0 .. count-1
  int count = 0;
};

CornerVertices corner_vertices(const LocalPiece& piece, const EdgeTable& edges, const std::vector<char>& is_cut) {
  UnionFind uf(piece.tris.size() * 3);
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const auto [u0, u1] = edges.uses[e];
    if (u1 < 0 || is_cut[e]) continue;
    // u0 runs a -> b in its face, u1 runs b -> a in its face.
    const int f0 = u0 / 3, k0 = u0 % 3, f1 = u1 / 3, k1 = u1 % 3;
    uf.unite(3 * f0 + k0, 3 * f1 + (k1 + 1) % 3);
    uf.unite(3 * f0 + (k0 + 1) % 3, 3 * f1 + k1);
  }
  CornerVertices out;
  out.of_corner.assign(piece.tris.size() * 3, -1);
  std::vector<int> id(piece.tris.size() * 3, -1);
  for (size_t c = 0; c < out.of_corner.size(); ++c) {
    const int root = uf.find(static_cast<int>(c));
    if (id[root] < 0) id[root] = out.count++;
    out.of_corner[c] = id[root];
  }
  return out;
}

// Boundary loops as lists of boundary face-edges (3 f + k) in order.
std::vector<std::vector<int>> boundary_loops(const LocalPiece& piece, const EdgeTable& edges,
                                             const std::vector<char>& is_cut, const CornerVertices& verts,
                                             bool* manifold) {
  std::vector<int> outgoing(verts.count, -1);
  *manifold = true;
  std::vector<int> boundary;
  for (size_t fe = 0; fe < piece.tris.size() * 3; ++fe) {
    const int e = edges.of_face_edge[fe];
    if (edges.uses[e][1] >= 0 && !is_cut[e]) continue;
    const int from = verts.of_corner[fe];
    if (outgoing[from] >= 0) *manifold = false;
    outgoing[from] = static_cast<int>(fe);
    boundary.push_back(static_cast<int>(fe));
  }
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(piece.tris.size() * 3, 0);
  for (int start : boundary) {
    if (seen[start]) continue;
    std::vector<int> loop;
    int fe = start;
    while (fe >= 0 && !seen[fe]) {
      seen[fe] = 1;
      loop.push_back(fe);
      const int f = fe / 3, k = fe % 3;
      fe = outgoing[verts.of_corner[3 * f + (k + 1) % 3]];
    }
    if (fe != start) *manifold = false;
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Graph of the piece's vertices (corner classes) along its interior edges.
struct VertexGraph {
  std::vector<int> offsets, neighbour, edge;
  std::vector<double> length;  // per edge of the table
};

VertexGraph vertex_graph(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges,
                         const CornerVertices& verts) {
  VertexGraph g;
  g.offsets.assign(verts.count + 1, 0);
  g.length.assign(edges.keys.size(), 0.0);
  std::vector<std::array<int, 3>> arcs;  // (from, to, edge)
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const int fe = edges.uses[e][0];
    const int f = fe / 3, k = fe % 3;
    const int a = piece.tris[f][k], b = piece.tris[f][(k + 1) % 3];
    g.length[e] = (positions.row(a) - positions.row(b)).norm();
    if (edges.uses[e][1] < 0 || piece.inner(edges.uses[e])) continue;
    const int va = verts.of_corner[fe], vb = verts.of_corner[3 * f + (k + 1) % 3];
    arcs.push_back({va, vb, static_cast<int>(e)});
    arcs.push_back({vb, va, static_cast<int>(e)});
  }
  for (const auto& arc : arcs) ++g.offsets[arc[0] + 1];
  for (int v = 0; v < verts.count; ++v) g.offsets[v + 1] += g.offsets[v];
  g.neighbour.resize(arcs.size());
  g.edge.resize(arcs.size());
  std::vector<int> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& arc : arcs) {
    g.neighbour[fill[arc[0]]] = arc[1];
    g.edge[fill[arc[0]]++] = arc[2];
  }
  return g;
}

// Dijkstra from `sources` until a vertex with stop[v] is settled (or all, when
// stop is empty). Returns the settled stop vertex (or the farthest vertex);
// prev_edge / prev_vertex give the path back.
struct ShortestPaths {
  std::vector<double> dist;
  std::vector<int> prev_vertex, prev_edge;
  int reached = -1;
};

ShortestPaths dijkstra(const VertexGraph& g, const std::vector<int>& sources, const std::vector<char>& stop) {
  const size_t n = g.offsets.size() - 1;
  ShortestPaths sp;
  sp.dist.assign(n, std::numeric_limits<double>::infinity());
  sp.prev_vertex.assign(n, -1);
  sp.prev_edge.assign(n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int s : sources) {
    sp.dist[s] = 0.0;
    queue.push({0.0, s});
  }
  double farthest = -1.0;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > sp.dist[v]) continue;
    if (!stop.empty() && stop[v]) {
      sp.reached = v;
      return sp;
    }
    if (d > farthest) farthest = d, sp.reached = v;
    for (int i = g.offsets[v]; i < g.offsets[v + 1]; ++i) {
      const int w = g.neighbour[i];
      const double nd = d + g.length[g.edge[i]];
      if (nd < sp.dist[w]) {
        sp.dist[w] = nd;
        sp.prev_vertex[w] = v;
        sp.prev_edge[w] = g.edge[i];
        queue.push({nd, w});
      }
    }
  }
  if (!stop.empty()) sp.reached = -1;
  return sp;
}

void mark_path(const ShortestPaths& sp, int v, std::vector<char>& is_cut, std::vector<int>* visited) {
  while (v >= 0 && sp.prev_edge[v] >= 0) {
    is_cut[sp.prev_edge[v]] = 1;
    if (visited) visited->push_back(v);
    v = sp.prev_vertex[v];
  }
}

// Interior edges to cut so that the piece becomes a disc (see unfold.h).
// Returns false when the piece's topology is not that of a surface.
bool choose_cuts(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges,
                 std::vector<char>& is_cut) {
  const CornerVertices verts = corner_vertices(piece, edges, is_cut);
  bool manifold = true;
  const auto loops = boundary_loops(piece, edges, is_cut, verts, &manifold);
  if (!manifold) return false;
  const long euler =
      static_cast<long>(verts.count) - static_cast<long>(edges.keys.size()) + static_cast<long>(piece.tris.size());
  const long twice_genus = 2 - euler - static_cast<long>(loops.size());
  if (twice_genus < 0 || twice_genus % 2 != 0) return false;
  if (twice_genus == 0 && loops.size() == 1) return true;  // a disc already

  const VertexGraph g = vertex_graph(positions, piece, edges, verts);
  if (loops.size() >= 2) {
    // Join every further loop to the first along the shortest interior path
    // from what is already joined.
    std::vector<int> loop_of(verts.count, -1);
    for (size_t l = 0; l < loops.size(); ++l)
      for (int fe : loops[l]) loop_of[verts.of_corner[fe]] = static_cast<int>(l);
    std::vector<int> joined;
    for (int fe : loops[0]) joined.push_back(verts.of_corner[fe]);
    std::vector<char> stop(verts.count, 0);
    for (int v = 0; v < verts.count; ++v) stop[v] = loop_of[v] > 0;
    for (size_t round = 1; round < loops.size(); ++round) {
      const ShortestPaths sp = dijkstra(g, joined, stop);
      if (sp.reached < 0) return false;
      const int l = loop_of[sp.reached];
      mark_path(sp, sp.reached, is_cut, &joined);
      for (int fe : loops[l]) {
        const int v = verts.of_corner[fe];
        stop[v] = 0;
        joined.push_back(v);
      }
    }
  } else if (loops.empty()) {
    // Closed: open along the longest shortest path (two sweeps).
    const ShortestPaths first = dijkstra(g, {0}, {});
    const ShortestPaths second = dijkstra(g, {first.reached}, {});
    if (second.reached < 0 || second.reached == first.reached) return false;
    mark_path(second, second.reached, is_cut, nullptr);
  }
  if (twice_genus == 0) return true;

  // Handles: a maximum spanning tree of the dual graph over the uncut interior
  // edges crosses the long edges; the short edges it leaves, pruned of
  // dangling branches, cut every handle.
  std::vector<int> order;
  for (size_t e = 0; e < edges.keys.size(); ++e)
    if (edges.uses[e][1] >= 0 && !is_cut[e]) order.push_back(static_cast<int>(e));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const bool ia = piece.inner(edges.uses[a]), ib = piece.inner(edges.uses[b]);
    return ia != ib ? ia : g.length[a] > g.length[b];
  });
  UnionFind dual(piece.tris.size());
  std::vector<char> in_graph(edges.keys.size(), 1);
  for (int e : order) {
    const int fa = edges.uses[e][0] / 3, fb = edges.uses[e][1] / 3;
    if (dual.find(fa) != dual.find(fb)) {
      dual.unite(fa, fb);
      in_graph[e] = 0;
    }
  }
  std::vector<int> degree(verts.count, 0);
  std::vector<std::array<int, 2>> ends(edges.keys.size());
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const int fe = edges.uses[e][0];
    ends[e] = {verts.of_corner[fe], verts.of_corner[3 * (fe / 3) + (fe % 3 + 1) % 3]};
    if (in_graph[e]) ++degree[ends[e][0]], ++degree[ends[e][1]];
  }
  // Prune: interior edges of the graph only (the boundary loops stay).
  std::vector<std::vector<int>> incident(verts.count);
  for (size_t e = 0; e < edges.keys.size(); ++e)
    if (in_graph[e]) incident[ends[e][0]].push_back(e), incident[ends[e][1]].push_back(e);
  std::vector<int> stack;
  for (int v = 0; v < verts.count; ++v)
    if (degree[v] == 1) stack.push_back(v);
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    if (degree[v] != 1) continue;
    for (int e : incident[v]) {
      if (!in_graph[e]) continue;
      in_graph[e] = 0;
      const int w = ends[e][0] == v ? ends[e][1] : ends[e][0];
      --degree[v];
      if (--degree[w] == 1) stack.push_back(w);
    }
  }
  for (size_t e = 0; e < edges.keys.size(); ++e) is_cut[e] = edges.uses[e][1] >= 0 && in_graph[e];
  return true;
}

// Proper crossings between non-adjacent outline segments, on a uniform grid.
bool outline_is_simple(const std::vector<Vec2>& uv, const std::vector<std::array<int, 2>>& segments) {
  if (segments.size() < 4) return true;
  Eigen::AlignedBox2d box;
  double total = 0.0;
  for (const auto& s : segments) {
    box.extend(uv[s[0]]);
    total += (uv[s[1]] - uv[s[0]]).norm();
  }
  const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
  const double cell = std::max(2.0 * total / segments.size(), extent / 4096.0);
  const auto index = [&](double x, double lo) { return static_cast<int64_t>(std::floor((x - lo) / cell)); };
  std::unordered_map<int64_t, std::vector<int>> grid;
  const int64_t stride = index(box.max().y(), box.min().y()) + 2;
  for (size_t i = 0; i < segments.size(); ++i) {
    const Vec2& a = uv[segments[i][0]];
    const Vec2& b = uv[segments[i][1]];
    for (int64_t x = index(std::min(a.x(), b.x()), box.min().x()); x <= index(std::max(a.x(), b.x()), box.min().x());
         ++x)
      for (int64_t y = index(std::min(a.y(), b.y()), box.min().y()); y <= index(std::max(a.y(), b.y()), box.min().y());
           ++y)
        grid[x * stride + y].push_back(static_cast<int>(i));
  }
  const double eps = 1e-12 * extent * extent;
  for (const auto& [cell_id, list] : grid) {
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        const auto& s = segments[list[i]];
        const auto& t = segments[list[j]];
        if (s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1]) continue;
        const Vec2 &a = uv[s[0]], &b = uv[s[1]], &c = uv[t[0]], &d = uv[t[1]];
        const double o1 = cross2(b - a, c - a), o2 = cross2(b - a, d - a);
        const double o3 = cross2(d - c, a - c), o4 = cross2(d - c, b - c);
        if (((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps)) &&
            ((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps)))
          return false;
      }
  }
  return true;
}

struct FlatPiece {
  std::vector<Vec2> corner_uv;            // per local corner
  std::vector<std::vector<int>> outline;  // local face-edges (3 f + k)
  std::vector<uint64_t> cut_keys;         // mesh edges cut inside the piece
  int arap_iterations = 0;
};

// Flat map of a disc (verts: its vertices as corner classes) or nothing when
// a factorisation fails or the result overlaps itself.
// Greedy start: each triangle laid down beside the one it is reached from
// (breadth first over uncut edges), by its edge lengths. Exact on a
// developable disc, and O(#faces); where the disc is not developable the
// vertices reached twice disagree and the largest edge strain says so.
std::vector<Vec2> greedy_layout(const LocalPiece& piece, const CornerVertices& verts, const EdgeTable& edges,
                                const std::vector<char>& is_cut, const std::vector<std::array<Vec2, 3>>& local) {
  const size_t nf = piece.tris.size();
  std::vector<Vec2> uv(verts.count, Vec2::Zero());
  std::vector<char> placed(verts.count, 0), visited(nf, 0);
  for (int k = 0; k < 3; ++k) uv[verts.of_corner[k]] = local[0][k], placed[verts.of_corner[k]] = 1;
  std::vector<int> queue{0};
  visited[0] = 1;
  for (size_t head = 0; head < queue.size(); ++head) {
    const int f = queue[head];
    for (int k = 0; k < 3; ++k) {
      const int e = edges.of_face_edge[3 * f + k];
      if (edges.uses[e][1] < 0 || is_cut[e]) continue;
      const int twin = edges.uses[e][0] == 3 * f + k ? edges.uses[e][1] : edges.uses[e][0];
      const int g = twin / 3, kg = twin % 3;  // in g the edge runs b -> a
      if (visited[g]) continue;
      visited[g] = 1;
      queue.push_back(g);
      const int c = verts.of_corner[3 * g + (kg + 2) % 3];
      if (placed[c]) continue;
      const Vec2 b = uv[verts.of_corner[3 * g + kg]], a = uv[verts.of_corner[3 * g + (kg + 1) % 3]];
      const double d = (a - b).norm();
      const double lbc = (local[g][(kg + 2) % 3] - local[g][kg]).norm();
      const double lac = (local[g][(kg + 2) % 3] - local[g][(kg + 1) % 3]).norm();
      const Vec2 along = d > 0 ? Vec2((a - b) / d) : Vec2(1, 0);
      const double x = d > 0 ? (lbc * lbc - lac * lac + d * d) / (2 * d) : 0.0;
      const double h = std::sqrt(std::max(0.0, lbc * lbc - x * x));
      uv[c] = b + x * along + h * Vec2(-along.y(), along.x());  // b, a, c counter-clockwise
      placed[c] = 1;
    }
  }
  return uv;
}

// A greedy start this close to isometric replaces the conformal one (whose
// 2n x 2n factorisation is the unfolding's largest cost); this close, the
// refinement is skipped too: it cannot do better than rounding.
constexpr double kGreedyStart = 1e-3;
constexpr double kAlreadyIsometric = 1e-9;

bool flatten_disc(const Positions& positions, const LocalPiece& piece, const CornerVertices& verts,
                  const EdgeTable& edges, const std::vector<char>& is_cut, const std::vector<int>& outline,
                  const UnfoldOptions& options, std::vector<Vec2>* uv_out, int* iterations, bool allow_greedy = true) {
  const int nv = verts.count;
  const size_t nf = piece.tris.size();
  // Each triangle in its own plane: x0 = 0, x1 on the first axis.
  std::vector<std::array<Vec2, 3>> local(nf);
  std::vector<double> area(nf);
  double total_area = 0.0;
  for (size_t f = 0; f < nf; ++f) {
    const Vec3 p0 = positions.row(piece.tris[f][0]).transpose();
    const Vec3 e1 = positions.row(piece.tris[f][1]).transpose() - p0;
    const Vec3 e2 = positions.row(piece.tris[f][2]).transpose() - p0;
    const double l1 = e1.norm();
    const double x2 = e2.dot(e1) / l1;
    const double y2 = e1.cross(e2).norm() / l1;
    local[f] = {Vec2(0, 0), Vec2(l1, 0), Vec2(x2, y2)};
    area[f] = 0.5 * l1 * y2;
    total_area += area[f];
  }
  if (!(total_area > 0.0)) return false;

  std::vector<Vec2> uv;
  double greedy_strain = std::numeric_limits<double>::infinity();
  if (allow_greedy) {
    uv = greedy_layout(piece, verts, edges, is_cut, local);
    greedy_strain = 0.0;
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const double l3 = (local[f][(k + 1) % 3] - local[f][k]).norm();
        const double l2 = (uv[verts.of_corner[3 * f + (k + 1) % 3]] - uv[verts.of_corner[3 * f + k]]).norm();
        greedy_strain = std::max(greedy_strain, std::abs(l2 / l3 - 1.0));
      }
  }
  const bool from_greedy = greedy_strain <= kGreedyStart;
  if (!from_greedy) {
    // Conformal start (LSCM): two far-apart outline vertices pinned.
    const auto vertex_of = [&](int fe) { return verts.of_corner[fe]; };
    const auto point_of = [&](int v_corner) { return positions.row(piece.tris[v_corner / 3][v_corner % 3]); };
    int pa = outline[0], pb = outline[0];
    for (int pass = 0; pass < 2; ++pass) {
      double best = -1.0;
      const int from = pass == 0 ? outline[0] : pa;
      for (int fe : outline) {
        const double d = (point_of(fe) - point_of(from)).norm();
        if (d > best) best = d, (pass == 0 ? pa : pb) = fe;
      }
    }
    const int va = vertex_of(pa), vb = vertex_of(pb);
    if (va == vb) return false;
    const double pin_distance = (point_of(pa) - point_of(pb)).norm();
    std::vector<int> column(nv, -1);
    int free_count = 0;
    for (int v = 0; v < nv; ++v)
      if (v != va && v != vb) column[v] = free_count++;
    const Vec2 pinned_a(0, 0), pinned_b(pin_distance, 0);
    uv.assign(nv, Vec2::Zero());
    uv[va] = pinned_a;
    uv[vb] = pinned_b;
    if (free_count > 0) {
      std::vector<Triplet> rows;
      rows.reserve(nf * 12);
      Eigen::VectorXd rhs_rows = Eigen::VectorXd::Zero(2 * nf);
      for (size_t f = 0; f < nf; ++f) {
        const double scale = 1.0 / std::sqrt(area[f]);
        for (int k = 0; k < 3; ++k) {
          // W_k = z_{k+2} - z_{k+1} (complex), row: sum_k W_k U_k = 0.
          const Vec2 w = (local[f][(k + 2) % 3] - local[f][(k + 1) % 3]) * scale;
          const int v = verts.of_corner[3 * f + k];
          const int c = column[v];
          if (c >= 0) {
            rows.emplace_back(2 * f, 2 * c, w.x());
            rows.emplace_back(2 * f, 2 * c + 1, -w.y());
            rows.emplace_back(2 * f + 1, 2 * c, w.y());
            rows.emplace_back(2 * f + 1, 2 * c + 1, w.x());
          } else {
            const Vec2 u = uv[v];
            rhs_rows[2 * f] -= w.x() * u.x() - w.y() * u.y();
            rhs_rows[2 * f + 1] -= w.y() * u.x() + w.x() * u.y();
          }
        }
      }
      SparseMatrix a(2 * nf, 2 * free_count);
      a.setFromTriplets(rows.begin(), rows.end());
      const SparseMatrix at = a.transpose();
      const SparseMatrix normal = at * a;
      Eigen::SimplicialLDLT<SparseMatrix> solver(normal);
      if (solver.info() != Eigen::Success) return false;
      const Eigen::VectorXd x = solver.solve(at * rhs_rows);
      if (solver.info() != Eigen::Success || !x.allFinite()) return false;
      for (int v = 0; v < nv; ++v)
        if (column[v] >= 0) uv[v] = Vec2(x[2 * column[v]], x[2 * column[v] + 1]);
    }
    const auto flat_area = [&](const std::vector<Vec2>& p) {
      double sum = 0.0;
      for (size_t f = 0; f < nf; ++f) {
        const Vec2& q0 = p[verts.of_corner[3 * f]];
        sum += 0.5 * cross2(p[verts.of_corner[3 * f + 1]] - q0, p[verts.of_corner[3 * f + 2]] - q0);
      }
      return sum;
    };
    const double conformal_area = flat_area(uv);
    if (!(conformal_area > 0.0)) return false;
    const double to_scale = std::sqrt(total_area / conformal_area);
    for (auto& p : uv) p *= to_scale;
  }
  const int max_rounds = greedy_strain <= kAlreadyIsometric ? 0 : options.arap_iterations;

  // ARAP: cotangent weights of the edge opposite each corner.
  std::vector<std::array<double, 3>> cot(nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec2 e1 = local[f][(k + 1) % 3] - local[f][k];
      const Vec2 e2 = local[f][(k + 2) % 3] - local[f][k];
      cot[f][k] = e1.dot(e2) / (2.0 * area[f]);
    }
  // Vertex 0 keeps its place (the map is otherwise free up to a translation).
  std::vector<int> unknown(nv, -1);
  int unknowns = 0;
  for (int v = 1; v < nv; ++v) unknown[v] = unknowns++;
  std::vector<Triplet> entries;
  entries.reserve(nf * 12);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = unknown[verts.of_corner[3 * f + (k + 1) % 3]];
      const int j = unknown[verts.of_corner[3 * f + (k + 2) % 3]];
      const double w = cot[f][k];
      if (i >= 0) entries.emplace_back(i, i, w);
      if (j >= 0) entries.emplace_back(j, j, w);
      if (i >= 0 && j >= 0) entries.emplace_back(i, j, -w), entries.emplace_back(j, i, -w);
    }
  SparseMatrix laplacian(unknowns, unknowns);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<SparseMatrix> arap;
  if (unknowns > 0 && max_rounds > 0) {
    arap.compute(laplacian);
    if (arap.info() != Eigen::Success) return false;
  }
  const std::vector<Vec2> start = uv;
  std::vector<Eigen::Matrix2d> rotation(nf);
  double previous = std::numeric_limits<double>::infinity();
  int rounds = 0;
  const auto energy = [&](const std::vector<Vec2>& p) {
    double sum = 0.0;
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const Vec2 d =
            (p[verts.of_corner[3 * f + a]] - p[verts.of_corner[3 * f + b]]) - rotation[f] * (local[f][a] - local[f][b]);
        sum += cot[f][k] * d.squaredNorm();
      }
    return sum;
  };
  for (; unknowns > 0 && rounds < max_rounds; ++rounds) {
    // Local: the rotation closest to each triangle's current map.
    for (size_t f = 0; f < nf; ++f) {
      Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const Vec2 du = uv[verts.of_corner[3 * f + a]] - uv[verts.of_corner[3 * f + b]];
        s += cot[f][k] * du * (local[f][a] - local[f][b]).transpose();
      }
      const double angle = std::atan2(s(1, 0) - s(0, 1), s(0, 0) + s(1, 1));
      rotation[f] << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    }
    // Global: L u = b, vertex 0 fixed.
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(unknowns, 2);
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const int va2 = verts.of_corner[3 * f + a], vb2 = verts.of_corner[3 * f + b];
        const Vec2 target = cot[f][k] * (rotation[f] * (local[f][a] - local[f][b]));
        const int i = unknown[va2], j = unknown[vb2];
        if (i >= 0) rhs.row(i) += target.transpose();
        if (j >= 0) rhs.row(j) -= target.transpose();
        // The fixed vertex's known position moves to the right-hand side.
        if (i >= 0 && j < 0) rhs.row(i) += cot[f][k] * uv[vb2].transpose();
        if (j >= 0 && i < 0) rhs.row(j) += cot[f][k] * uv[va2].transpose();
      }
    const Eigen::MatrixXd x = arap.solve(rhs);
    if (arap.info() != Eigen::Success || !x.allFinite()) return false;
    for (int v = 1; v < nv; ++v) uv[v] = x.row(unknown[v]).transpose();
    const double e = energy(uv);
    // e / area is about the mean squared edge strain: 1e-18 is far below any figure shown.
    if (e <= 1e-18 * total_area ||
        (std::isfinite(previous) && std::abs(previous - e) <= options.arap_tolerance * previous)) {
      ++rounds;
      break;
    }
    previous = e;
  }
  *iterations = rounds;

  // Checks: positive triangles, a flat angle sum of 2 pi around interior
  // vertices (at most 2 pi on the outline) and an outline without crossings.
  const auto valid = [&](const std::vector<Vec2>& p) {
    std::vector<double> angle_sum(nv, 0.0);
    for (size_t f = 0; f < nf; ++f) {
      const Vec2& q0 = p[verts.of_corner[3 * f]];
      const Vec2& q1 = p[verts.of_corner[3 * f + 1]];
      const Vec2& q2 = p[verts.of_corner[3 * f + 2]];
      if (!q0.allFinite() || !q1.allFinite() || !q2.allFinite()) return false;
      if (!(0.5 * cross2(q1 - q0, q2 - q0) > 1e-12 * area[f])) return false;
      for (int k = 0; k < 3; ++k) {
        const Vec2& c = p[verts.of_corner[3 * f + k]];
        const Vec2 e1 = p[verts.of_corner[3 * f + (k + 1) % 3]] - c;
        const Vec2 e2 = p[verts.of_corner[3 * f + (k + 2) % 3]] - c;
        angle_sum[verts.of_corner[3 * f + k]] += std::atan2(cross2(e1, e2), e1.dot(e2));
      }
    }
    std::vector<char> on_outline(nv, 0);
    std::vector<std::array<int, 2>> segments;
    for (int fe : outline) {
      const int a = verts.of_corner[fe], b = verts.of_corner[3 * (fe / 3) + (fe % 3 + 1) % 3];
      on_outline[a] = 1;
      segments.push_back({a, b});
    }
    for (int v = 0; v < nv; ++v) {
      if (on_outline[v] ? angle_sum[v] > kTwoPi + 1e-9 : std::abs(angle_sum[v] - kTwoPi) > 1e-6) return false;
    }
    return outline_is_simple(p, segments);
  };
  if (valid(uv)) {
    *uv_out = std::move(uv);
    return true;
  }
  // The refinement can fold what the conformal start had flat: keep the start then.
  if (valid(start)) {
    *uv_out = start;
    return true;
  }
  // The greedy start can mislead the refinement: the conformal one decides.
  if (from_greedy)
    return flatten_disc(positions, piece, verts, edges, is_cut, outline, options, uv_out, iterations, false);
  return false;
}

// Cuts a piece into a disc and lays it flat; false when it must be split.
bool flatten_piece(const Positions& positions, const LocalPiece& piece, const UnfoldOptions& options, FlatPiece* out) {
  const EdgeTable edges = edge_table(piece.tris);
  std::vector<char> is_cut(edges.keys.size(), 0);
  if (!choose_cuts(positions, piece, edges, is_cut)) return false;
  const CornerVertices verts = corner_vertices(piece, edges, is_cut);
  bool manifold = true;
  const auto loops = boundary_loops(piece, edges, is_cut, verts, &manifold);
  const long euler = static_cast<long>(verts.count) -
                     static_cast<long>(edges.keys.size() + std::count(is_cut.begin(), is_cut.end(), 1)) +
                     static_cast<long>(piece.tris.size());
  if (!manifold || loops.size() != 1 || euler != 1) return false;
  std::vector<Vec2> uv;
  if (!flatten_disc(positions, piece, verts, edges, is_cut, loops[0], options, &uv, &out->arap_iterations))
    return false;
  // Seams must match: no outline edge may stretch beyond the tolerance.
  if (options.seam_tolerance > 0.0)
    for (int fe : loops[0]) {
      const int f = fe / 3, k = fe % 3;
      const double l3 = (positions.row(piece.tris[f][k]) - positions.row(piece.tris[f][(k + 1) % 3])).norm();
      const double l2 = (uv[verts.of_corner[3 * f + (k + 1) % 3]] - uv[verts.of_corner[fe]]).norm();
      if (std::abs(l2 / l3 - 1.0) > options.seam_tolerance) return false;
    }
  out->corner_uv.resize(piece.tris.size() * 3);
  for (size_t c = 0; c < out->corner_uv.size(); ++c) out->corner_uv[c] = uv[verts.of_corner[c]];
  out->outline = loops;
  out->cut_keys.clear();
  for (size_t e = 0; e < edges.keys.size(); ++e)
    if (is_cut[e]) out->cut_keys.push_back(edges.keys[e]);
  return true;
}

// Connected parts (across shared edges) of a set of faces.
std::vector<std::vector<int>> connected_parts(const Triangles& triangles, const std::vector<int>& faces) {
  const LocalPiece piece = local_piece(triangles, faces, {});
  const EdgeTable edges = edge_table(piece.tris);
  UnionFind uf(faces.size());
  for (const auto& uses : edges.uses)
    if (uses[1] >= 0) uf.unite(uses[0] / 3, uses[1] / 3);
  std::unordered_map<int, int> part_of_root;
  std::vector<std::vector<int>> parts;
  for (size_t i = 0; i < faces.size(); ++i) {
    const int root = uf.find(static_cast<int>(i));
    auto [it, inserted] = part_of_root.emplace(root, static_cast<int>(parts.size()));
    if (inserted) parts.emplace_back();
    parts[it->second].push_back(faces[i]);
  }
  return parts;
}

// Two halves across the principal axis of the face centroids, a group's faces
// on one side (they take the group's mean place) unless the piece is one group.
std::array<std::vector<int>, 2> split_in_two(const Positions& positions, const Triangles& triangles,
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

int corner_of(const Triangles& triangles, int face, int vertex) {
  for (int k = 0; k < 3; ++k)
    if (triangles(face, k) == vertex) return k;
  return -1;
}

}  // namespace

UnfoldResult unfold(const Positions& positions, const Triangles& triangles, const std::vector<int>& patch_ids,
                    const UnfoldOptions& options, const std::vector<int>& face_groups, const Progress& progress) {
  const Eigen::Index nf = triangles.rows();
  if (!patch_ids.empty() && static_cast<Eigen::Index>(patch_ids.size()) != nf)
    throw EngineError(Status::invalid_argument, "patch_ids has " + std::to_string(patch_ids.size()) + " entries for " +
                                                    std::to_string(nf) + " triangles");
  if (!face_groups.empty() && static_cast<Eigen::Index>(face_groups.size()) != nf)
    throw EngineError(Status::invalid_argument, "face_groups has " + std::to_string(face_groups.size()) +
                                                    " entries for " + std::to_string(nf) + " triangles");
  for (size_t f = 0; f < patch_ids.size(); ++f)
    if (patch_ids[f] < 0)
      throw EngineError(Status::invalid_argument, "patch id of triangle " + std::to_string(f) + " is negative");
  if (!(options.seam_tolerance >= 0.0))
    throw EngineError(Status::invalid_argument, "seam_tolerance must not be negative");
  if (options.arap_iterations < 0) throw EngineError(Status::invalid_argument, "arap_iterations must not be negative");
  const auto patch_of = [&](Eigen::Index f) { return patch_ids.empty() ? 0 : patch_ids[f]; };

  // The mesh's edges, for the first pieces and the seams.
  std::vector<std::array<int, 3>> all_tris(nf);
  for (Eigen::Index f = 0; f < nf; ++f) all_tris[f] = {triangles(f, 0), triangles(f, 1), triangles(f, 2)};
  const EdgeTable mesh_edges = edge_table(all_tris);

  UnionFind same_patch(nf);
  for (const auto& uses : mesh_edges.uses)
    if (uses[1] >= 0 && patch_of(uses[0] / 3) == patch_of(uses[1] / 3)) same_patch.unite(uses[0] / 3, uses[1] / 3);
  std::vector<std::vector<int>> jobs;
  {
    std::unordered_map<int, int> job_of_root;
    for (Eigen::Index f = 0; f < nf; ++f) {
      auto [it, inserted] = job_of_root.emplace(same_patch.find(static_cast<int>(f)), static_cast<int>(jobs.size()));
      if (inserted) jobs.emplace_back();
      jobs[it->second].push_back(static_cast<int>(f));
    }
  }
  std::vector<int> job_splits(jobs.size(), 0);

  UnfoldResult result;
  result.corners.setZero(3 * nf, 2);
  result.piece_of_face.assign(nf, -1);
  result.face_strain = Eigen::VectorXd::Zero(nf);
  std::vector<uint64_t> cut_keys;
  std::vector<std::vector<int>> done;  // faces per piece
  // Largest first, so that piece numbers follow size.
  std::vector<std::pair<std::vector<int>, int>> stack;
  for (size_t j = 0; j < jobs.size(); ++j) stack.emplace_back(std::move(jobs[j]), 0);
  std::sort(stack.begin(), stack.end(), [](const auto& a, const auto& b) {
    return a.first.size() != b.first.size() ? a.first.size() < b.first.size() : a.first[0] > b.first[0];
  });
  Eigen::Index faces_done = 0;
  while (!stack.empty()) {
    progress.report(static_cast<double>(faces_done) / static_cast<double>(nf), "unfolding");
    auto [faces, splits] = std::move(stack.back());
    stack.pop_back();
    const LocalPiece piece = local_piece(triangles, faces, face_groups);
    FlatPiece flat;
    if (!flatten_piece(positions, piece, options, &flat)) {
      if (faces.size() <= 1)
        throw EngineError(Status::numerical_failure,
                          "triangle " + std::to_string(faces[0]) + " could not be laid flat");
      ++result.split_count;
      for (const auto& half : split_in_two(positions, triangles, faces, face_groups))
        for (auto& part : connected_parts(triangles, half)) stack.emplace_back(std::move(part), splits + 1);
      continue;
    }
    faces_done += static_cast<Eigen::Index>(faces.size());
    const int id = static_cast<int>(result.pieces.size());
    UnfoldPiece out;
    out.patch = patch_of(faces[0]);
    out.faces = static_cast<Eigen::Index>(faces.size());
    out.cut_edges = static_cast<int>(flat.cut_keys.size());
    out.splits = splits;
    out.arap_iterations = flat.arap_iterations;
    double strain_sum = 0.0;
    for (size_t i = 0; i < faces.size(); ++i) {
      const int f = faces[i];
      result.piece_of_face[f] = id;
      double face_max = 0.0;
      for (int k = 0; k < 3; ++k) {
        result.corners.row(3 * f + k) = flat.corner_uv[3 * i + k].transpose();
      }
      for (int k = 0; k < 3; ++k) {
        const double l3 = (positions.row(triangles(f, k)) - positions.row(triangles(f, (k + 1) % 3))).norm();
        const double l2 = (flat.corner_uv[3 * i + k] - flat.corner_uv[3 * i + (k + 1) % 3]).norm();
        const double strain = std::abs(l2 / l3 - 1.0);
        face_max = std::max(face_max, strain);
        strain_sum += strain;
      }
      result.face_strain[f] = face_max;
      out.max_strain = std::max(out.max_strain, face_max);
      const Vec3 p0 = positions.row(triangles(f, 0)).transpose();
      out.area_3d += 0.5 * (positions.row(triangles(f, 1)).transpose() - p0)
                               .cross(positions.row(triangles(f, 2)).transpose() - p0)
                               .norm();
      const Vec2& q0 = flat.corner_uv[3 * i];
      out.area_flat += 0.5 * cross2(flat.corner_uv[3 * i + 1] - q0, flat.corner_uv[3 * i + 2] - q0);
    }
    out.mean_strain = strain_sum / (3.0 * faces.size());
    out.area_change = out.area_flat / out.area_3d - 1.0;
    for (const auto& loop : flat.outline) {
      std::vector<Eigen::Index> rows;
      for (int fe : loop) {
        const int i = fe / 3, k = fe % 3;
        rows.push_back(3 * static_cast<Eigen::Index>(faces[i]) + k);
        out.outline_length += (flat.corner_uv[3 * i + (k + 1) % 3] - flat.corner_uv[fe]).norm();
      }
      out.outline.push_back(std::move(rows));
    }
    cut_keys.insert(cut_keys.end(), flat.cut_keys.begin(), flat.cut_keys.end());
    result.pieces.push_back(std::move(out));
  }
  std::sort(cut_keys.begin(), cut_keys.end());

  // Seams: interior edges with a different piece on each side, or cut inside
  // one piece; grouped by the pair of pieces, then into chains.
  struct SeamEdge {
    int from, to, left, right;
  };
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
  for (auto& group : groups) {
    auto& list = group.second;
    std::unordered_map<int, std::vector<int>> at_vertex;  // vertex -> edges of the group
    for (size_t i = 0; i < list.size(); ++i) {
      at_vertex[list[i].from].push_back(static_cast<int>(i));
      at_vertex[list[i].to].push_back(static_cast<int>(i));
    }
    std::vector<char> used(list.size(), 0);
    const auto walk = [&](int start_vertex, int first_edge) {
      UnfoldSeam seam;
      int v = start_vertex, e = first_edge;
      while (e >= 0 && !used[e]) {
        used[e] = 1;
        const SeamEdge& s = list[e];
        // Directed from v: the face with the half-edge v -> w is on the left.
        const bool forward = s.from == v;
        const int w = forward ? s.to : s.from;
        const int left = forward ? s.left : s.right, right = forward ? s.right : s.left;
        seam.edges.push_back({v, w});
        seam.faces.push_back({left, right});
        v = w;
        e = -1;
        const auto& next = at_vertex[v];
        if (next.size() == 2) e = used[next[0]] ? next[1] : next[0];
      }
      // Side a: the left faces; with two pieces, the chain's first left face.
      seam.piece_a = result.piece_of_face[seam.faces[0][0]];
      seam.piece_b = result.piece_of_face[seam.faces[0][1]];
      seam.cut = patch_of(seam.faces[0][0]) == patch_of(seam.faces[0][1]);
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
      result.seams.push_back(std::move(seam));
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
  return result;
}

}  // namespace developable

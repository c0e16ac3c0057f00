#include "pattern/unfold_mesh.h"

#include "core/union_find.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

namespace developable::unfolding {

uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

namespace {

// The face-edges (3 f + k) in the order of their edge keys, ties in the
// order of the face-edges: a counting sort by the lower vertex, then by the
// upper one within each vertex's few, when the vertex ids span no more than
// a few times the face-edges; else a comparison sort (the same order).
std::vector<int> face_edges_by_key(const std::vector<std::array<int, 3>>& tris) {
  const size_t n = tris.size() * 3;
  const auto lower = [&](size_t fe) { return std::min(tris[fe / 3][fe % 3], tris[fe / 3][(fe % 3 + 1) % 3]); };
  const auto key = [&](size_t fe) { return edge_key(tris[fe / 3][fe % 3], tris[fe / 3][(fe % 3 + 1) % 3]); };
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (const auto& t : tris)
    for (int v : t) lo = std::min(lo, v), hi = std::max(hi, v);
  std::vector<int> order(n);
  const size_t range = n == 0 ? 0 : static_cast<size_t>(hi - lo) + 1;
  if (range > 4 * n + 1024) {
    for (size_t fe = 0; fe < n; ++fe) order[fe] = static_cast<int>(fe);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
    return order;
  }
  std::vector<int> start(range + 1, 0);
  for (size_t fe = 0; fe < n; ++fe) ++start[lower(fe) - lo + 1];
  for (size_t v = 0; v < range; ++v) start[v + 1] += start[v];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t fe = 0; fe < n; ++fe) order[fill[lower(fe) - lo]++] = static_cast<int>(fe);
  for (size_t v = 0; v < range; ++v)  // insertion sort by key within the bucket: stable
    for (int i = start[v] + 1; i < start[v + 1]; ++i)
      for (int j = i; j > start[v] && key(order[j - 1]) > key(order[j]); --j) std::swap(order[j - 1], order[j]);
  return order;
}

}  // namespace

EdgeTable edge_table(const std::vector<std::array<int, 3>>& tris) {
  const size_t n = tris.size() * 3;
  const std::vector<int> order = face_edges_by_key(tris);
  const auto key = [&](int fe) { return edge_key(tris[fe / 3][fe % 3], tris[fe / 3][(fe % 3 + 1) % 3]); };
  EdgeTable table;
  table.of_face_edge.assign(n, -1);
  for (size_t i = 0; i < n;) {
    size_t j = i;
    const uint64_t k = key(order[i]);
    std::array<int, 2> uses{-1, -1};
    while (j < n && key(order[j]) == k) {
      if (j - i < 2) uses[j - i] = order[j];
      table.of_face_edge[order[j]] = static_cast<int>(table.keys.size());
      ++j;
    }
    table.keys.push_back(k);
    table.uses.push_back(uses);
    i = j;
  }
  return table;
}

LocalPiece local_piece(const Triangles& triangles, std::vector<int> faces, const std::vector<int>& face_groups) {
  LocalPiece piece;
  piece.faces = std::move(faces);
  piece.tris.reserve(piece.faces.size());
  piece.groups.reserve(piece.faces.size());
  for (int f : piece.faces) {
    piece.tris.push_back({triangles(f, 0), triangles(f, 1), triangles(f, 2)});
    piece.groups.push_back(face_groups.empty() ? -1 : face_groups[f]);
  }
  return piece;
}

CornerVertices corner_vertices(const LocalPiece& piece, const EdgeTable& edges, const std::vector<char>& is_cut) {
  UnionFind uf(piece.tris.size() * 3);
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const auto [u0, u1] = edges.uses[e];
    if (u1 < 0 || is_cut[e]) continue;
    // u0 runs a -> b in its face, u1 runs b -> a in its face.
    uf.unite(u0, next_in_face(u1));
    uf.unite(next_in_face(u0), u1);
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

PieceTopology piece_topology(const LocalPiece& piece, const EdgeTable& edges, const std::vector<char>& is_cut) {
  PieceTopology t;
  t.verts = corner_vertices(piece, edges, is_cut);
  std::vector<int> outgoing(t.verts.count, -1);
  std::vector<int> boundary;
  for (size_t fe = 0; fe < piece.tris.size() * 3; ++fe) {
    const int e = edges.of_face_edge[fe];
    if (edges.uses[e][1] >= 0 && !is_cut[e]) continue;
    const int from = t.verts.of_corner[fe];
    if (outgoing[from] >= 0) t.manifold = false;
    outgoing[from] = static_cast<int>(fe);
    boundary.push_back(static_cast<int>(fe));
  }
  std::vector<char> seen(piece.tris.size() * 3, 0);
  for (int start : boundary) {
    if (seen[start]) continue;
    std::vector<int> loop;
    int fe = start;
    while (fe >= 0 && !seen[fe]) {
      seen[fe] = 1;
      loop.push_back(fe);
      fe = outgoing[t.verts.of_corner[next_in_face(fe)]];
    }
    if (fe != start) t.manifold = false;
    t.loops.push_back(std::move(loop));
  }
  const long cuts = std::count(is_cut.begin(), is_cut.end(), 1);
  t.euler = static_cast<long>(t.verts.count) - static_cast<long>(edges.keys.size()) - cuts +
            static_cast<long>(piece.tris.size());
  return t;
}

VertexGraph vertex_graph(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges,
                         const CornerVertices& verts, const std::vector<char>& is_cut) {
  VertexGraph g;
  g.offsets.assign(verts.count + 1, 0);
  g.length.assign(edges.keys.size(), 0.0);
  std::vector<std::array<int, 3>> arcs;  // (from, to, edge)
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const int fe = edges.uses[e][0];
    const int f = fe / 3, k = fe % 3;
    g.length[e] = (positions.row(piece.tris[f][k]) - positions.row(piece.tris[f][(k + 1) % 3])).norm();
    if (edges.uses[e][1] < 0 || is_cut[e] || piece.inner(edges.uses[e])) continue;
    const int va = verts.of_corner[fe], vb = verts.of_corner[next_in_face(fe)];
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

ShortestPaths dijkstra(const VertexGraph& g, const std::vector<int>& sources, const std::vector<char>& stop,
                       const std::vector<char>& blocked) {
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
    if (!blocked.empty() && blocked[v] && d > 0.0) continue;
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

namespace {

void mark_path(const ShortestPaths& sp, int v, std::vector<char>& is_cut, std::vector<int>* visited) {
  while (v >= 0 && sp.prev_edge[v] >= 0) {
    is_cut[sp.prev_edge[v]] = 1;
    if (visited) visited->push_back(v);
    v = sp.prev_vertex[v];
  }
}

// Joins every further loop to the first along the shortest interior path
// from what is already joined.
bool join_loops(const PieceTopology& t, const VertexGraph& g, std::vector<char>& is_cut) {
  std::vector<int> loop_of(t.verts.count, -1);
  for (size_t l = 0; l < t.loops.size(); ++l)
    for (int fe : t.loops[l]) loop_of[t.verts.of_corner[fe]] = static_cast<int>(l);
  std::vector<int> joined;
  for (int fe : t.loops[0]) joined.push_back(t.verts.of_corner[fe]);
  std::vector<char> stop(t.verts.count, 0);
  for (int v = 0; v < t.verts.count; ++v) stop[v] = loop_of[v] > 0;
  for (size_t round = 1; round < t.loops.size(); ++round) {
    const ShortestPaths sp = dijkstra(g, joined, stop);
    if (sp.reached < 0) return false;
    const int l = loop_of[sp.reached];
    mark_path(sp, sp.reached, is_cut, &joined);
    for (int fe : t.loops[l]) {
      const int v = t.verts.of_corner[fe];
      stop[v] = 0;
      joined.push_back(v);
    }
  }
  return true;
}

// Handles: a maximum spanning tree of the dual graph over the uncut interior
// edges crosses the long edges; the short edges it leaves, pruned of
// dangling branches, cut every handle.
void cut_handles(const LocalPiece& piece, const EdgeTable& edges, const CornerVertices& verts, const VertexGraph& g,
                 std::vector<char>& is_cut) {
  std::vector<int> order;
  for (size_t e = 0; e < edges.keys.size(); ++e)
    if (edges.uses[e][1] >= 0 && !is_cut[e]) order.push_back(static_cast<int>(e));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const bool ia = piece.inner(edges.uses[a]), ib = piece.inner(edges.uses[b]);
    return ia != ib ? ia : g.length[a] > g.length[b];
  });
  UnionFind dual(piece.tris.size());
  std::vector<char> in_graph(edges.keys.size(), 1);
  for (int e : order)
    if (dual.unite(edges.uses[e][0] / 3, edges.uses[e][1] / 3)) in_graph[e] = 0;
  std::vector<int> degree(verts.count, 0);
  std::vector<std::array<int, 2>> ends(edges.keys.size());
  std::vector<std::vector<int>> incident(verts.count);
  for (size_t e = 0; e < edges.keys.size(); ++e) {
    const int fe = edges.uses[e][0];
    ends[e] = {verts.of_corner[fe], verts.of_corner[next_in_face(fe)]};
    if (!in_graph[e]) continue;
    ++degree[ends[e][0]], ++degree[ends[e][1]];
    incident[ends[e][0]].push_back(static_cast<int>(e)), incident[ends[e][1]].push_back(static_cast<int>(e));
  }
  // Prune: interior edges of the graph only (the boundary loops stay).
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
}

}  // namespace

bool choose_cuts(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges, Holes holes,
                 std::vector<char>& is_cut) {
  const PieceTopology t = piece_topology(piece, edges, is_cut);
  if (!t.manifold) return false;
  const long twice_genus = 2 - t.euler - static_cast<long>(t.loops.size());
  if (twice_genus < 0 || twice_genus % 2 != 0) return false;
  const bool join = holes == Holes::join && t.loops.size() >= 2;
  if (twice_genus == 0 && !t.loops.empty() && !join) return true;  // a disc (with holes kept) already

  const VertexGraph g = vertex_graph(positions, piece, edges, t.verts, is_cut);
  if (join) {
    if (!join_loops(t, g, is_cut)) return false;
  } else if (t.loops.empty()) {
    // Closed: open along the longest shortest path (two sweeps).
    const ShortestPaths first = dijkstra(g, {0}, {});
    const ShortestPaths second = dijkstra(g, {first.reached}, {});
    if (second.reached < 0 || second.reached == first.reached) return false;
    mark_path(second, second.reached, is_cut, nullptr);
  }
  if (twice_genus == 0) return true;
  cut_handles(piece, edges, t.verts, g, is_cut);
  return true;
}

}  // namespace developable::unfolding

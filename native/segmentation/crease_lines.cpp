#include "segmentation/crease_lines.h"

#include "core/union_find.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace developable {
namespace {

// Edges beside one another are parallel within these cosines: for the ridge
// test's facets (45 degrees) and for the suppression (60 degrees, wider: a
// zigzag line's neighbours).
constexpr double kBesideParallel = 0.7;
constexpr double kSuppressParallel = 0.5;
// Loops around at most this many faces are what is left of a line two edges
// wide, not a piece.
constexpr int kTinyLoopFaces = 2;
// A line's direction at its end: over its last few edges.
constexpr int kEndDirectionEdges = 4;

// The mesh as the lines see it: edges' geometry, the edges at each vertex.
class LineMesh {
 public:
  LineMesh(const Positions& positions, const Triangles& triangles, const Normals& normals,
           const VertexFaces& connectivity, const std::vector<MeshEdge>& edges)
      : positions(positions), triangles(triangles), normals(normals), connectivity(connectivity), edges(edges) {
    const Eigen::Index n = connectivity.vertex_count();
    boundary.assign(static_cast<size_t>(n), false);
    std::vector<int> count(static_cast<size_t>(n) + 1, 0);
    for (const MeshEdge& e : edges) {
      ++count[static_cast<size_t>(e.a) + 1];
      ++count[static_cast<size_t>(e.b) + 1];
      if (e.g < 0) boundary[static_cast<size_t>(e.a)] = boundary[static_cast<size_t>(e.b)] = true;
    }
    for (size_t v = 0; v < static_cast<size_t>(n); ++v) count[v + 1] += count[v];
    offsets = count;
    at.resize(static_cast<size_t>(offsets.back()));
    for (size_t e = 0; e < edges.size(); ++e)
      for (int v : {edges[e].a, edges[e].b})
        at[static_cast<size_t>(count[static_cast<size_t>(v)]++)] = static_cast<int>(e);
    dihedral.resize(edges.size(), 0.0);
    for (size_t e = 0; e < edges.size(); ++e)
      if (edges[e].g >= 0) {
        const double c = normals.row(edges[e].f).dot(normals.row(edges[e].g));
        dihedral[e] = std::acos(std::clamp(c, -1.0, 1.0));
      }
  }

  Eigen::Vector3d point(int v) const { return positions.row(v).transpose(); }
  Eigen::Vector3d vector(int e) const {
    const MeshEdge& m = edges[static_cast<size_t>(e)];
    return point(m.b) - point(m.a);
  }
  Eigen::Vector3d middle(int e) const {
    const MeshEdge& m = edges[static_cast<size_t>(e)];
    return 0.5 * (point(m.a) + point(m.b));
  }
  int other(int e, int v) const {
    const MeshEdge& m = edges[static_cast<size_t>(e)];
    return m.a == v ? m.b : m.a;
  }
  // The normalised sum of the face normals around v.
  Eigen::Vector3d vertex_normal(int v) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) sum += normals.row(*f).transpose();
    return sum.normalized();
  }
  const int* begin(int v) const { return at.data() + offsets[static_cast<size_t>(v)]; }
  const int* end(int v) const { return at.data() + offsets[static_cast<size_t>(v) + 1]; }

  // The edges beside edge e: at the vertices of its faces' neighbourhood
  // (the 1-rings of its ends), sharing no vertex with it, parallel to it
  // (|cos| >= parallel) and level with it (their midpoints within half its
  // length along it); `side` gets each one's side of e (0 or 1).
  void beside(int e, double parallel, std::vector<int>& out, std::vector<int>& side) const {
    const MeshEdge& m = edges[static_cast<size_t>(e)];
    std::vector<int> vertices{m.a, m.b};
    for (int v : {m.a, m.b})
      for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f)
        for (int c = 0; c < 3; ++c) vertices.push_back(triangles(*f, c));
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    std::vector<int> near;
    for (int v : vertices) near.insert(near.end(), begin(v), end(v));
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    const Eigen::Vector3d t = vector(e), mid = middle(e);
    const double length = t.norm();
    const Eigen::Vector3d unit = t / length;
    const Eigen::Vector3d across = (normals.row(m.f) + normals.row(m.g)).transpose().cross(unit);
    out.clear();
    side.clear();
    for (int j : near) {
      const MeshEdge& n = edges[static_cast<size_t>(j)];
      if (j == e || n.a == m.a || n.a == m.b || n.b == m.a || n.b == m.b) continue;
      if (std::abs(vector(j).normalized().dot(unit)) < parallel) continue;
      const Eigen::Vector3d offset = middle(j) - mid;
      if (std::abs(offset.dot(unit)) > 0.5 * length) continue;
      out.push_back(j);
      side.push_back(offset.dot(across) > 0.0 ? 1 : 0);
    }
  }

  const Positions& positions;
  const Triangles& triangles;
  const Normals& normals;
  const VertexFaces& connectivity;
  const std::vector<MeshEdge>& edges;
  std::vector<bool> boundary;    // per vertex
  std::vector<double> dihedral;  // per edge, rad (0 on the boundary)
  std::vector<int> offsets, at;  // the edges at each vertex, compressed rows
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Steps 1 and 2, asked edge by edge: an edge is a candidate when its score is
// above line_score, its dihedral angle at least ridge_ratio times the facets
// beside it (a ridge), and no parallel ridge beside it scores higher. Each
// edge's ridge test runs once, when first asked: the weak candidates of step
// 4 are asked only around the lines' loose ends (over every edge they cost
// 0.75 s of CPU on a 1M-face sheet without a line).
class Candidates {
 public:
  Candidates(const LineMesh& mesh, const Eigen::VectorXd& score, double line_score, double ridge_ratio)
      : mesh_(mesh),
        score_(score),
        line_score_(line_score),
        ridge_ratio_(ridge_ratio),
        ridge_(mesh.edges.size(), kUnknown) {}

  bool operator()(int e) {
    if (!ridge(e)) return false;
    std::vector<int> near, side;
    mesh_.beside(e, kSuppressParallel, near, side);
    for (int j : near)
      if (ridge(j) && score_[j] > score_[e]) return false;
    return true;
  }

  // Every edge asked.
  std::vector<bool> all() {
    std::vector<bool> kept(mesh_.edges.size());
    for (size_t e = 0; e < kept.size(); ++e) kept[e] = (*this)(static_cast<int>(e));
    return kept;
  }

 private:
  static constexpr signed char kUnknown = -1;

  bool ridge(int e) {
    signed char& known = ridge_[static_cast<size_t>(e)];
    if (known == kUnknown) {
      known = 0;
      if (mesh_.edges[static_cast<size_t>(e)].g >= 0 && score_[e] > line_score_) {
        mesh_.beside(e, kBesideParallel, near_, side_);
        std::vector<double> facets[2];
        for (size_t k = 0; k < near_.size(); ++k)
          facets[side_[k]].push_back(mesh_.dihedral[static_cast<size_t>(near_[k])]);
        known = mesh_.dihedral[static_cast<size_t>(e)] >= ridge_ratio_ * std::max(median(facets[0]), median(facets[1]));
      }
    }
    return known == 1;
  }

  const LineMesh& mesh_;
  const Eigen::VectorXd& score_;
  const double line_score_, ridge_ratio_;
  std::vector<signed char> ridge_;  // per edge: kUnknown, 0 or 1
  std::vector<int> near_, side_;    // the ridge test's scratch
};

// The cut edges as a graph on the vertices.
class CutGraph {
 public:
  CutGraph(const LineMesh& mesh, std::vector<bool> cut)
      : mesh_(mesh), cut_(std::move(cut)), at_(static_cast<size_t>(mesh.connectivity.vertex_count())) {
    for (size_t e = 0; e < cut_.size(); ++e)
      if (cut_[e]) link(static_cast<int>(e));
  }

  bool cut(int e) const { return cut_[static_cast<size_t>(e)]; }
  const std::vector<bool>& flags() const { return cut_; }
  const std::vector<int>& at(int v) const { return at_[static_cast<size_t>(v)]; }
  int degree(int v) const { return static_cast<int>(at_[static_cast<size_t>(v)].size()); }
  bool on_line(int v) const { return degree(v) > 0; }
  // A loose end: one cut edge, inside the mesh.
  bool end(int v) const { return degree(v) == 1 && !mesh_.boundary[static_cast<size_t>(v)]; }

  void add(int e) {
    if (!cut_[static_cast<size_t>(e)]) {
      cut_[static_cast<size_t>(e)] = true;
      link(e);
    }
  }
  void remove(int e) {
    if (!cut_[static_cast<size_t>(e)]) return;
    cut_[static_cast<size_t>(e)] = false;
    for (int v : {mesh_.edges[static_cast<size_t>(e)].a, mesh_.edges[static_cast<size_t>(e)].b}) {
      auto& list = at_[static_cast<size_t>(v)];
      list.erase(std::find(list.begin(), list.end(), e));
    }
  }

  // The branch from loose end v: its vertices (v first) and edges, up to and
  // including the first vertex that is a junction (three cut edges or
  // more), a loose end or on the boundary.
  void branch(int v, std::vector<int>& vertices, std::vector<int>& edges) const {
    vertices.assign({v});
    edges.clear();
    int current = v, previous_edge = -1;
    while (true) {
      int next_edge = -1;
      for (int e : at(current))
        if (e != previous_edge) next_edge = e;
      if (next_edge < 0) return;
      current = mesh_.other(next_edge, current);
      if (std::find(vertices.begin(), vertices.end(), current) != vertices.end()) return;  // a loop
      vertices.push_back(current);
      edges.push_back(next_edge);
      previous_edge = next_edge;
      if (degree(current) != 2 || mesh_.boundary[static_cast<size_t>(current)]) return;
    }
  }

 private:
  void link(int e) {
    at_[static_cast<size_t>(mesh_.edges[static_cast<size_t>(e)].a)].push_back(e);
    at_[static_cast<size_t>(mesh_.edges[static_cast<size_t>(e)].b)].push_back(e);
  }

  const LineMesh& mesh_;
  std::vector<bool> cut_;
  std::vector<std::vector<int>> at_;
};

// The faces joined across every edge that is not cut; the root of each.
std::vector<int> face_roots(const LineMesh& mesh, const CutGraph& graph) {
  UnionFind pieces(static_cast<size_t>(mesh.triangles.rows()));
  for (size_t e = 0; e < mesh.edges.size(); ++e)
    if (mesh.edges[e].g >= 0 && !graph.cut(static_cast<int>(e))) pieces.unite(mesh.edges[e].f, mesh.edges[e].g);
  std::vector<int> roots(static_cast<size_t>(mesh.triangles.rows()));
  for (size_t f = 0; f < roots.size(); ++f) roots[f] = pieces.find(static_cast<int>(f));
  return roots;
}

// Step 3: loops around one or two faces opened at their weakest cut edge,
// until none is left.
void open_tiny_loops(const LineMesh& mesh, const Eigen::VectorXd& score, CutGraph& graph) {
  while (true) {
    const std::vector<int> roots = face_roots(mesh, graph);
    std::vector<int> size(roots.size(), 0);
    for (int r : roots) ++size[static_cast<size_t>(r)];
    std::map<int, int> weakest;  // per tiny piece (its root): its weakest cut edge
    for (size_t e = 0; e < mesh.edges.size(); ++e) {
      if (!graph.cut(static_cast<int>(e))) continue;
      for (int f : {mesh.edges[e].f, mesh.edges[e].g}) {
        const int r = roots[static_cast<size_t>(f)];
        if (size[static_cast<size_t>(r)] > kTinyLoopFaces) continue;
        auto [it, fresh] = weakest.emplace(r, static_cast<int>(e));
        if (!fresh && score[static_cast<Eigen::Index>(e)] < score[it->second]) it->second = static_cast<int>(e);
      }
    }
    if (weakest.empty()) return;
    for (const auto& entry : weakest) graph.remove(entry.second);
  }
}

// Steps 3 and 6: branches of fewer than kSpurEdges edges from a loose end
// to a junction or the boundary removed, one at a time (a junction left
// with two edges is a line again), until none is left.
void drop_spurs(const LineMesh& mesh, CutGraph& graph) {
  std::vector<int> vertices, edges;
  bool changed = true;
  while (changed) {
    changed = false;
    for (int v = 0; v < static_cast<int>(mesh.connectivity.vertex_count()) && !changed; ++v) {
      if (!graph.end(v)) continue;
      graph.branch(v, vertices, edges);
      const int last = vertices.back();
      const bool anchored = graph.degree(last) >= 3 || mesh.boundary[static_cast<size_t>(last)];
      if (anchored && static_cast<int>(edges.size()) < kSpurEdges) {
        for (int e : edges) graph.remove(e);
        changed = true;
      }
    }
  }
}

// Step 4, first: from each loose end, the weak candidate that turns least
// from the line's last edge (within the parallels' cosine) is cut too, until
// no end has one. A line grows into another's loose end, not into its middle:
// such a junction cuts the other line's branch short, and the trace of its
// gap (step 5), which reaches as far as its branch is long, then fails.
void grow_from_ends(const LineMesh& mesh, Candidates& weak, CutGraph& graph) {
  bool changed = true;
  while (changed) {
    changed = false;
    for (int v = 0; v < static_cast<int>(mesh.connectivity.vertex_count()); ++v) {
      if (!graph.end(v)) continue;
      const Eigen::Vector3d on = (mesh.point(v) - mesh.point(mesh.other(graph.at(v).front(), v))).normalized();
      int best = -1;
      double straightest = kBesideParallel;
      for (const int* e = mesh.begin(v); e != mesh.end(v); ++e) {
        const int w = mesh.other(*e, v);
        if (graph.cut(*e) || (graph.on_line(w) && !graph.end(w)) || !weak(*e)) continue;
        const double turn = (mesh.point(w) - mesh.point(v)).normalized().dot(on);
        if (turn > straightest) {
          straightest = turn;
          best = *e;
        }
      }
      if (best >= 0) {
        graph.add(best);
        changed = true;
      }
    }
  }
}

// A chain is a closed ring: every vertex of its edges on two cut edges, none
// on the boundary.
bool closed_ring(const LineMesh& mesh, const CutGraph& graph, const std::vector<int>& edges) {
  for (int e : edges)
    for (int v : {mesh.edges[static_cast<size_t>(e)].a, mesh.edges[static_cast<size_t>(e)].b})
      if (graph.degree(v) != 2 || mesh.boundary[static_cast<size_t>(v)]) return false;
  return true;
}

// Step 4, then: chains (connected cut edges) with too little evidence, or
// too little extent unless a ring, removed.
void drop_weak_chains(const LineMesh& mesh, const Eigen::VectorXd& score, CutGraph& graph) {
  const Eigen::Index n = mesh.connectivity.vertex_count();
  UnionFind chains(static_cast<size_t>(n));
  for (size_t e = 0; e < mesh.edges.size(); ++e)
    if (graph.cut(static_cast<int>(e))) chains.unite(mesh.edges[e].a, mesh.edges[e].b);
  struct Chain {
    double evidence = 0.0;
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    std::vector<double> lengths;
    std::vector<int> edges;
  };
  std::map<int, Chain> by_root;
  for (size_t e = 0; e < mesh.edges.size(); ++e) {
    if (!graph.cut(static_cast<int>(e))) continue;
    Chain& chain = by_root[chains.find(mesh.edges[e].a)];
    chain.evidence += score[static_cast<Eigen::Index>(e)] - kLineScore;
    for (int v : {mesh.edges[e].a, mesh.edges[e].b}) {
      chain.low = chain.low.cwiseMin(mesh.point(v));
      chain.high = chain.high.cwiseMax(mesh.point(v));
    }
    chain.lengths.push_back(mesh.vector(static_cast<int>(e)).norm());
    chain.edges.push_back(static_cast<int>(e));
  }
  for (auto& [root, chain] : by_root) {
    const double extent = (chain.high - chain.low).norm();
    const bool ring = static_cast<int>(chain.edges.size()) >= kRingEdges && closed_ring(mesh, graph, chain.edges);
    if (chain.evidence < kLineEvidence || (!ring && extent < kLineExtent * median(chain.lengths)))
      for (int e : chain.edges) graph.remove(e);
  }
}

}  // namespace

namespace {

struct Bridge {
  std::vector<int> edges;
  double length = 0.0;
};

// The plane a loose end's branch is traced along: the plane of its vertices
// when they are planar and bend (a ring's arc), else the normal section
// through its end direction.
Eigen::Vector3d trace_plane(const LineMesh& mesh, const std::vector<int>& vertices, const Eigen::Vector3d& direction) {
  if (vertices.size() >= 4) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int v : vertices) mean += mesh.point(v);
    mean /= static_cast<double>(vertices.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int v : vertices) covariance += (mesh.point(v) - mean) * (mesh.point(v) - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
    const Eigen::Vector3d values = eigen.eigenvalues();  // ascending
    if (values[1] > kPlanarBranch * kPlanarBranch * values[2]) return eigen.eigenvectors().col(0);
  }
  return direction.cross(mesh.vertex_normal(vertices.front())).normalized();
}

// Step 5 for one loose end: the edges from it, along its branch's plane,
// each step to the neighbour nearest the plane that moves on along the
// plane's line on the surface, until a vertex on another line (not its own
// last few) or on the boundary; nothing when it leaves the mesh over a
// boundary edge, finds no way on or goes farther than kBridgeReach times
// its branch.
std::optional<Bridge> trace(const LineMesh& mesh, const CutGraph& graph, int end) {
  std::vector<int> vertices, edges;
  graph.branch(end, vertices, edges);
  double reach = 0.0;
  for (int e : edges) reach += mesh.vector(e).norm();
  reach *= kBridgeReach;
  const size_t own = std::min(vertices.size(), static_cast<size_t>(kEndDirectionEdges + 1));
  const Eigen::Vector3d origin = mesh.point(end);
  Eigen::Vector3d direction = (origin - mesh.point(vertices[own - 1])).normalized();
  const Eigen::Vector3d plane = trace_plane(mesh, vertices, direction);
  if (!plane.allFinite() || !direction.allFinite()) return std::nullopt;
  Bridge bridge;
  std::vector<int> path{end};
  int current = end;
  while (bridge.length < reach) {
    Eigen::Vector3d along = plane.cross(mesh.vertex_normal(current));
    if (!(along.norm() > 1e-9)) return std::nullopt;
    along.normalize();
    direction = along.dot(direction) < 0.0 ? -along : along;
    int best_edge = -1;
    double best = std::numeric_limits<double>::infinity();
    for (const int* e = mesh.begin(current); e != mesh.end(current); ++e) {
      const int w = mesh.other(*e, current);
      if (std::find(path.begin(), path.end(), w) != path.end()) continue;
      const Eigen::Vector3d step = mesh.point(w) - mesh.point(current);
      const double length = step.norm(), progress = step.dot(direction);
      if (!(progress > 0.2 * length)) continue;
      const double cost = std::abs((mesh.point(w) - origin).dot(plane)) / length - 0.1 * progress / length;
      if (cost < best) {
        best = cost;
        best_edge = *e;
      }
    }
    if (best_edge < 0 || mesh.edges[static_cast<size_t>(best_edge)].g < 0) return std::nullopt;
    current = mesh.other(best_edge, current);
    path.push_back(current);
    bridge.edges.push_back(best_edge);
    bridge.length += mesh.vector(best_edge).norm();
    const bool mine = std::find(vertices.begin(), vertices.begin() + static_cast<std::ptrdiff_t>(own), current) !=
                      vertices.begin() + static_cast<std::ptrdiff_t>(own);
    if (mesh.boundary[static_cast<size_t>(current)] || (graph.on_line(current) && !mine)) return bridge;
  }
  return std::nullopt;
}

// Step 5: the loose ends traced, the shortest bridge taken first, until no
// end finds one; an end that found none does not try again.
void bridge_gaps(const LineMesh& mesh, CutGraph& graph) {
  const int n = static_cast<int>(mesh.connectivity.vertex_count());
  std::vector<bool> failed(static_cast<size_t>(n), false);
  while (true) {
    std::optional<Bridge> shortest;
    for (int v = 0; v < n; ++v) {
      if (!graph.end(v) || failed[static_cast<size_t>(v)]) continue;
      std::optional<Bridge> bridge = trace(mesh, graph, v);
      if (!bridge)
        failed[static_cast<size_t>(v)] = true;
      else if (!shortest || bridge->length < shortest->length)
        shortest = std::move(bridge);
    }
    if (!shortest) return;
    for (int e : shortest->edges) graph.add(e);
  }
}

}  // namespace

std::vector<bool> crease_lines(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, const std::vector<MeshEdge>& edges,
                               const CreaseStrengths& strengths) {
  const LineMesh mesh(positions, triangles, normals, connectivity, edges);
  CutGraph graph(mesh, Candidates(mesh, strengths.score, kLineScore, kRidgeRatio).all());
  open_tiny_loops(mesh, strengths.score, graph);
  drop_spurs(mesh, graph);
  Candidates weak(mesh, strengths.score, kWeakLineScore, kWeakRidgeRatio);
  grow_from_ends(mesh, weak, graph);
  drop_weak_chains(mesh, strengths.score, graph);
  bridge_gaps(mesh, graph);
  drop_spurs(mesh, graph);
  return graph.flags();
}

}  // namespace developable

#include "core/orientation.h"

#include "core/measures.h"
#include "core/union_find.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <numeric>
#include <queue>
#include <sstream>
#include <utility>

namespace developable {
namespace {

// Half-edge h = 3 f + k runs from corner k of face f to corner k + 1.
int from_vertex(const Triangles& t, int h) { return t(h / 3, h % 3); }
int to_vertex(const Triangles& t, int h) { return t(h / 3, (h % 3 + 1) % 3); }

// The faces across every face's edges.
struct Dual {
  std::vector<int> twin;    // per half-edge: the other half-edge of its edge; -1 unless the edge has two faces
  std::vector<char> agree;  // per half-edge: its twin runs the edge the other way
  bool consistent = true;   // every edge of two faces agrees
};

// Half-edges bucketed by their lower vertex (a counting sort), each bucket
// sorted by the higher one: O(faces) for the small buckets of a mesh.
Dual dual_graph(const Triangles& t, Eigen::Index vertex_count) {
  const int halves = static_cast<int>(3 * t.rows());
  const auto low = [&](int h) { return std::min(from_vertex(t, h), to_vertex(t, h)); };
  const auto high = [&](int h) { return std::max(from_vertex(t, h), to_vertex(t, h)); };
  std::vector<int> start(static_cast<size_t>(vertex_count) + 1, 0);
  for (int h = 0; h < halves; ++h) ++start[static_cast<size_t>(low(h)) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> order(static_cast<size_t>(halves));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int h = 0; h < halves; ++h) order[static_cast<size_t>(fill[static_cast<size_t>(low(h))]++)] = h;
  Dual dual;
  dual.twin.assign(static_cast<size_t>(halves), -1);
  dual.agree.assign(static_cast<size_t>(halves), 0);
  for (size_t v = 0; v + 1 < start.size(); ++v) {
    const auto first = order.begin() + start[v], last = order.begin() + start[v + 1];
    std::sort(first, last, [&](int a, int b) { return std::make_pair(high(a), a) < std::make_pair(high(b), b); });
    for (auto i = first; i != last;) {
      auto j = i + 1;
      while (j != last && high(*j) == high(*i)) ++j;
      if (j - i == 2 && *i / 3 != *(i + 1) / 3) {  // an edge of two faces
        const int a = *i, b = *(i + 1);
        const char agree = from_vertex(t, a) != from_vertex(t, b);
        dual.twin[static_cast<size_t>(a)] = b;
        dual.twin[static_cast<size_t>(b)] = a;
        dual.agree[static_cast<size_t>(a)] = dual.agree[static_cast<size_t>(b)] = agree;
        dual.consistent = dual.consistent && agree;
      }
      i = j;
    }
  }
  return dual;
}

bool usable(const Positions& positions, const Triangles& triangles) {
  if (!positions.allFinite()) return false;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (triangles(f, c) < 0 || triangles(f, c) >= positions.rows()) return false;
  return true;
}

// Whether half-edge h's edge disagrees once the faces with parity 1 are turned.
bool disagrees(const Dual& dual, const std::vector<char>& parity, int h) {
  const int twin = dual.twin[static_cast<size_t>(h)];
  if (twin < 0) return false;
  return !(dual.agree[static_cast<size_t>(h)] ^ parity[static_cast<size_t>(h / 3)] ^
           parity[static_cast<size_t>(twin / 3)]);
}

// The parity across half-edge h from its face's: what makes the edge agree.
char parity_across(const Dual& dual, const std::vector<char>& parity, int h) {
  return static_cast<char>(parity[static_cast<size_t>(h / 3)] ^ !dual.agree[static_cast<size_t>(h)]);
}

// The faces of `root`'s component (root first, then breadth first), each
// given the parity that makes its tree edge agree.
std::vector<int> component(const Dual& dual, int root, std::vector<char>& parity, std::vector<char>& seen) {
  std::vector<int> members{root};
  seen[static_cast<size_t>(root)] = 1;
  parity[static_cast<size_t>(root)] = 0;
  for (size_t head = 0; head < members.size(); ++head)
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * members[head] + k, twin = dual.twin[static_cast<size_t>(h)];
      if (twin < 0 || seen[static_cast<size_t>(twin / 3)]) continue;
      seen[static_cast<size_t>(twin / 3)] = 1;
      parity[static_cast<size_t>(twin / 3)] = parity_across(dual, parity, h);
      members.push_back(twin / 3);
    }
  return members;
}

// Scratch of the non-orientable components, sized for the whole mesh once
// and reset on each component's own faces, so that many small components
// cost their own size only.
struct Workspace {
  std::vector<double> distance;     // per face
  std::vector<int> via;             // per face: the tree's half-edge into it, -1 at the root
  std::vector<char> given, parity;  // per face: parity_for_path's
  std::vector<char> loop, path;     // per half-edge: crossed by the reversing loop / on a path
  std::vector<int> local;           // per vertex: its number in the component, -1
  Workspace(Eigen::Index faces, Eigen::Index vertices)
      : distance(static_cast<size_t>(faces), std::numeric_limits<double>::infinity()),
        via(static_cast<size_t>(faces), -1),
        given(static_cast<size_t>(faces), 0),
        parity(static_cast<size_t>(faces), 0),
        loop(static_cast<size_t>(3 * faces), 0),
        path(static_cast<size_t>(3 * faces), 0),
        local(static_cast<size_t>(vertices), -1) {}
  void reset(const Triangles& t, const std::vector<int>& members) {
    for (int f : members) {
      distance[static_cast<size_t>(f)] = std::numeric_limits<double>::infinity();
      via[static_cast<size_t>(f)] = -1;
      given[static_cast<size_t>(f)] = parity[static_cast<size_t>(f)] = 0;
      for (int k = 0; k < 3; ++k) {
        loop[static_cast<size_t>(3 * f + k)] = path[static_cast<size_t>(3 * f + k)] = 0;
        local[static_cast<size_t>(t(f, k))] = -1;
      }
    }
  }
};

// Parities along a shortest-path tree of the dual graph from members[0]
// (steps between face centroids; the tree in work.via), so that the edges
// that disagree lie where the paths round the surface one way meet those
// going the other.
void shortest_path_parity(const Positions& positions, const Triangles& triangles, const Dual& dual,
                          const std::vector<int>& members, std::vector<char>& parity, Workspace& work) {
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  work.distance[static_cast<size_t>(members[0])] = 0.0;
  queue.push({0.0, members[0]});
  while (!queue.empty()) {
    const auto [d, f] = queue.top();
    queue.pop();
    if (d > work.distance[static_cast<size_t>(f)]) continue;
    const int in = work.via[static_cast<size_t>(f)];
    parity[static_cast<size_t>(f)] = in < 0 ? 0 : parity_across(dual, parity, in);
    const Eigen::Vector3d c = face_centroid(positions, triangles, f);
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, twin = dual.twin[static_cast<size_t>(h)];
      if (twin < 0) continue;
      const int g = twin / 3;
      const double through = d + (face_centroid(positions, triangles, g) - c).norm();
      if (through < work.distance[static_cast<size_t>(g)]) {
        work.distance[static_cast<size_t>(g)] = through;
        work.via[static_cast<size_t>(g)] = h;
        queue.push({through, g});
      }
    }
  }
}

// Marks (work.loop, both twins) the edges a dual loop crosses that goes once
// round the surface against its orientation: from the tree's root to one
// face of the disagreeing edge h, across it and back along the tree. Any cut
// crosses it an odd number of times.
void mark_reversing_loop(const Dual& dual, int h, Workspace& work) {
  const auto toggle = [&](int half) {
    work.loop[static_cast<size_t>(half)] ^= 1;
    work.loop[static_cast<size_t>(dual.twin[static_cast<size_t>(half)])] ^= 1;
  };
  toggle(h);
  for (int f : {h / 3, dual.twin[static_cast<size_t>(h)] / 3})
    for (int in = work.via[static_cast<size_t>(f)]; in >= 0; in = work.via[static_cast<size_t>(in / 3)]) toggle(in);
}

// The shortest path of interior edges (two faces) from the component's rim
// back to it that crosses the reversing loop an odd number of times
// (Dijkstra on the vertices doubled by that parity), marked in work.path on
// both twins. False when the component has no rim or no such path.
bool shortest_crossing_path(const Positions& positions, const Triangles& t, const Dual& dual,
                            const std::vector<int>& members, Workspace& work) {
  std::vector<int> vertices;
  for (int f : members)
    for (int k = 0; k < 3; ++k)
      if (work.local[static_cast<size_t>(t(f, k))] < 0) {
        work.local[static_cast<size_t>(t(f, k))] = static_cast<int>(vertices.size());
        vertices.push_back(t(f, k));
      }
  const auto local = [&](int v) { return work.local[static_cast<size_t>(v)]; };
  std::vector<char> rim(vertices.size(), 0);
  // The interior edges both ways from each vertex, in compressed rows (a
  // counting sort, in the order of the faces), with their lengths.
  std::vector<int> first(vertices.size() + 1, 0);
  for (int f : members)
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, twin = dual.twin[static_cast<size_t>(h)];
      const int a = local(from_vertex(t, h)), b = local(to_vertex(t, h));
      if (twin < 0) rim[static_cast<size_t>(a)] = rim[static_cast<size_t>(b)] = 1;
      if (twin > h) ++first[static_cast<size_t>(a) + 1], ++first[static_cast<size_t>(b) + 1];
    }
  std::partial_sum(first.begin(), first.end(), first.begin());
  struct Arc {
    int to, half;
    double length;
  };
  std::vector<Arc> arcs(static_cast<size_t>(first.back()));
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (int f : members)
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k;
      if (dual.twin[static_cast<size_t>(h)] < h) continue;
      const int a = local(from_vertex(t, h)), b = local(to_vertex(t, h));
      const double length = (positions.row(from_vertex(t, h)) - positions.row(to_vertex(t, h))).norm();
      arcs[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = {b, h, length};
      arcs[static_cast<size_t>(fill[static_cast<size_t>(b)]++)] = {a, h, length};
    }
  // States 2 v + crossings mod 2.
  std::vector<double> distance(2 * vertices.size(), std::numeric_limits<double>::infinity());
  std::vector<int> back(2 * vertices.size(), -1);  // the state before
  std::vector<int> over(2 * vertices.size(), -1);  // the half-edge from it
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t v = 0; v < vertices.size(); ++v)
    if (rim[v]) distance[2 * v] = 0.0, queue.push({0.0, static_cast<int>(2 * v)});
  int reached = -1;
  while (!queue.empty() && reached < 0) {
    const auto [d, state] = queue.top();
    queue.pop();
    if (d > distance[static_cast<size_t>(state)]) continue;
    if (state % 2 == 1 && rim[static_cast<size_t>(state / 2)]) reached = state;
    const auto v = static_cast<size_t>(state / 2);
    for (int i = first[v]; reached < 0 && i < first[v + 1]; ++i) {
      const Arc& arc = arcs[static_cast<size_t>(i)];
      const auto next = static_cast<size_t>(2 * arc.to + ((state % 2) ^ work.loop[static_cast<size_t>(arc.half)]));
      if (d + arc.length < distance[next]) {
        distance[next] = d + arc.length;
        back[next] = state;
        over[next] = arc.half;
        queue.push({d + arc.length, static_cast<int>(next)});
      }
    }
  }
  if (reached < 0) return false;
  for (int state = reached; back[static_cast<size_t>(state)] >= 0; state = back[static_cast<size_t>(state)]) {
    const int h = over[static_cast<size_t>(state)];
    work.path[static_cast<size_t>(h)] ^= 1;
    work.path[static_cast<size_t>(dual.twin[static_cast<size_t>(h)])] ^= 1;
  }
  return true;
}

// Parities whose cut is exactly work.path, if there are any (breadth first
// from members[0], then checked on every edge); else `parity` stays.
bool parity_for_path(const Dual& dual, const std::vector<int>& members, Workspace& work, std::vector<char>& parity) {
  std::vector<int> found{members[0]};
  work.given[static_cast<size_t>(members[0])] = 1;
  for (size_t head = 0; head < found.size(); ++head) {
    const int f = found[head];
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k, twin = dual.twin[static_cast<size_t>(h)];
      if (twin < 0) continue;
      // Across h the parities differ when exactly one of "the faces
      // disagree as given" and "h is on the path" holds.
      const char across = static_cast<char>(work.parity[static_cast<size_t>(f)] ^ !dual.agree[static_cast<size_t>(h)] ^
                                            work.path[static_cast<size_t>(h)]);
      const auto g = static_cast<size_t>(twin / 3);
      if (!work.given[g]) {
        work.given[g] = 1;
        work.parity[g] = across;
        found.push_back(twin / 3);
      } else if (work.parity[g] != across) {
        return false;
      }
    }
  }
  for (int f : members) parity[static_cast<size_t>(f)] = work.parity[static_cast<size_t>(f)];
  return true;
}

// Shortens the cut: turns single faces while that makes the cut shorter
// (the turned face's edges on the cut leave it, its other edges of two faces
// join it).
void shorten_cut(const Positions& positions, const Triangles& triangles, const Dual& dual,
                 const std::vector<int>& members, std::vector<char>& parity) {
  const auto length = [&](int h) {
    return (positions.row(from_vertex(triangles, h)) - positions.row(to_vertex(triangles, h))).norm();
  };
  const auto gain = [&](int f, double* perimeter) {
    double sum = 0.0;
    *perimeter = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k;
      *perimeter += length(h);
      if (dual.twin[static_cast<size_t>(h)] >= 0) sum += disagrees(dual, parity, h) ? length(h) : -length(h);
    }
    return sum;
  };
  std::vector<char> listed(static_cast<size_t>(triangles.rows()), 0);
  std::vector<int> stack;
  for (int f : members)
    for (int k = 0; k < 3; ++k)
      if (disagrees(dual, parity, 3 * f + k) && !listed[static_cast<size_t>(f)]) {
        listed[static_cast<size_t>(f)] = 1;
        stack.push_back(f);
      }
  // Each turn shortens the cut; the cap only guards against rounding.
  for (size_t turns = 0; !stack.empty() && turns < 8 * members.size();) {
    const int f = stack.back();
    stack.pop_back();
    listed[static_cast<size_t>(f)] = 0;
    double perimeter = 0.0;
    if (!(gain(f, &perimeter) > 1e-12 * perimeter)) continue;
    parity[static_cast<size_t>(f)] ^= 1;
    ++turns;
    for (int k = 0; k < 3; ++k) {
      const int twin = dual.twin[static_cast<size_t>(3 * f + k)];
      if (twin >= 0 && !listed[static_cast<size_t>(twin / 3)]) {
        listed[static_cast<size_t>(twin / 3)] = 1;
        stack.push_back(twin / 3);
      }
    }
  }
}

// Of the component's two windings (parity and its complement, the same
// cut), the one that turns fewer faces; on a tie the one keeping members[0].
void keep_fewer_turned(const std::vector<int>& members, std::vector<char>& parity) {
  size_t turned = 0;
  for (int f : members) turned += parity[static_cast<size_t>(f)];
  const bool tie = 2 * turned == members.size();
  if (2 * turned > members.size() || (tie && parity[static_cast<size_t>(members[0])]))
    for (int f : members) parity[static_cast<size_t>(f)] ^= 1;
}

// The cut of a non-orientable component: the disagreeing edges of the
// parities along a shortest-path tree, shortened face by face; then, on a
// component with a rim, the shortest path from the rim back to it that
// crosses a loop going round against the orientation an odd number of times
// (across a strip: the shortest way across), if it is a cut of the
// component and shorter.
void shorten_cut_of(const Positions& positions, const Triangles& triangles, const Dual& dual,
                    const std::vector<int>& members, std::vector<char>& parity, Workspace& work) {
  shortest_path_parity(positions, triangles, dual, members, parity, work);
  const auto length = [&](int h) {
    return (positions.row(from_vertex(triangles, h)) - positions.row(to_vertex(triangles, h))).norm();
  };
  int first_cut = -1;
  for (int f : members)
    for (int k = 0; k < 3 && first_cut < 0; ++k)
      if (disagrees(dual, parity, 3 * f + k)) first_cut = 3 * f + k;
  mark_reversing_loop(dual, first_cut, work);
  shorten_cut(positions, triangles, dual, members, parity);
  if (!shortest_crossing_path(positions, triangles, dual, members, work)) return;
  double cut = 0.0, path = 0.0;
  for (int f : members)
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k;
      if (dual.twin[static_cast<size_t>(h)] < h) continue;
      if (disagrees(dual, parity, h)) cut += length(h);
      if (work.path[static_cast<size_t>(h)]) path += length(h);
    }
  if (path < cut * (1.0 - 1e-12)) parity_for_path(dual, members, work, parity);
}

int corner_of(const Triangles& t, int f, int v) { return t(f, 0) == v ? 0 : (t(f, 1) == v ? 1 : 2); }

}  // namespace

FaceOrientation orient_faces(const Positions& positions, const Triangles& triangles) {
  FaceOrientation out;
  out.triangles = triangles;
  const Eigen::Index nf = triangles.rows();
  out.turned.assign(static_cast<size_t>(nf), false);
  if (!usable(positions, triangles)) return out;
  const Dual dual = dual_graph(triangles, positions.rows());
  if (dual.consistent) return out;

  std::vector<char> parity(static_cast<size_t>(nf), 0), seen(static_cast<size_t>(nf), 0);
  std::unique_ptr<Workspace> work;  // for non-orientable components only
  for (int root = 0; root < nf; ++root) {
    if (seen[static_cast<size_t>(root)]) continue;
    const std::vector<int> members = component(dual, root, parity, seen);
    bool orientable = true;
    for (int f : members)
      for (int k = 0; k < 3; ++k) orientable = orientable && !disagrees(dual, parity, 3 * f + k);
    if (!orientable) {
      ++out.non_orientable_components;
      if (!work) work = std::make_unique<Workspace>(nf, positions.rows());
      shorten_cut_of(positions, triangles, dual, members, parity, *work);
      work->reset(triangles, members);
    }
    keep_fewer_turned(members, parity);
  }

  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!parity[static_cast<size_t>(f)]) continue;
    out.turned[static_cast<size_t>(f)] = true;
    ++out.turned_count;
    std::swap(out.triangles(f, 1), out.triangles(f, 2));
  }
  // The cut, as both faces now run its edges: the caller's direction of the
  // edge in its face, reversed if that face was turned.
  std::vector<std::pair<std::array<int, 2>, std::array<int, 2>>> cut;
  for (int h = 0; h < static_cast<int>(3 * nf); ++h) {
    const int twin = dual.twin[static_cast<size_t>(h)];
    if (twin < h || !disagrees(dual, parity, h)) continue;
    std::array<int, 2> edge{from_vertex(triangles, h), to_vertex(triangles, h)};
    if (parity[static_cast<size_t>(h / 3)]) std::swap(edge[0], edge[1]);
    cut.push_back({edge, {std::min(h / 3, twin / 3), std::max(h / 3, twin / 3)}});
  }
  std::sort(cut.begin(), cut.end());
  for (const auto& [edge, faces] : cut) {
    out.cut.push_back(edge);
    out.cut_faces.push_back(faces);
    out.cut_length += (positions.row(edge[0]) - positions.row(edge[1])).norm();
  }
  out.orientability = out.non_orientable_components > 0 ? Orientability::non_orientable
                      : out.turned_count > 0            ? Orientability::inconsistent
                                                        : Orientability::consistent;
  return out;
}

std::string orientation_note(const FaceOrientation& o) {
  std::ostringstream s;
  s << std::setprecision(3);
  if (o.orientability == Orientability::inconsistent) {
    s << o.turned_count << " of " << o.triangles.rows() << " triangles " << (o.turned_count == 1 ? "is" : "are")
      << " wound the other way round from the neighbours; the run turns " << (o.turned_count == 1 ? "it" : "them")
      << " over, which gives the result of "
         "the mesh wound consistently";
  } else if (o.orientability == Orientability::non_orientable) {
    s << "the surface is one-sided (like a Möbius strip"
      << (o.non_orientable_components > 1 ? ", in " + std::to_string(o.non_orientable_components) + " parts" : "")
      << "): no winding makes every triangle agree with its neighbours; the run winds it consistently but "
         "along a cut of "
      << o.cut.size() << (o.cut.size() == 1 ? " edge" : " edges") << " (length " << o.cut_length
      << "), which the flat pattern opens";
  }
  return s.str();
}

void to_caller_normals(Normals& normals, const std::vector<bool>& turned) {
  for (size_t f = 0; f < turned.size(); ++f)
    if (turned[f]) normals.row(static_cast<Eigen::Index>(f)) *= -1.0;
}

OpenedMesh open_along_cut(const Positions& positions, const FaceOrientation& orientation) {
  OpenedMesh m;
  m.positions = positions;
  m.triangles = orientation.triangles;
  m.original.resize(static_cast<size_t>(positions.rows()));
  std::iota(m.original.begin(), m.original.end(), 0);
  if (orientation.cut.empty()) return m;
  // Corners joined across every edge of two faces that agrees (the cut's
  // edges are the ones that do not): the classes are the fans the cut parts.
  const Triangles& t = orientation.triangles;
  const Dual dual = dual_graph(t, positions.rows());
  UnionFind corners(static_cast<size_t>(3 * t.rows()));
  for (int h = 0; h < static_cast<int>(dual.twin.size()); ++h) {
    const int twin = dual.twin[static_cast<size_t>(h)];
    if (twin < h || !dual.agree[static_cast<size_t>(h)]) continue;
    for (int v : {from_vertex(t, h), to_vertex(t, h)})
      corners.unite(3 * (h / 3) + corner_of(t, h / 3, v), 3 * (twin / 3) + corner_of(t, twin / 3, v));
  }
  std::vector<int> id(static_cast<size_t>(3 * t.rows()), -1);
  std::vector<char> kept(static_cast<size_t>(positions.rows()), 0);
  std::vector<int> copies;
  for (int c = 0; c < static_cast<int>(id.size()); ++c) {
    const int root = corners.find(c), v = t(c / 3, c % 3);
    if (id[static_cast<size_t>(root)] < 0) {
      if (!kept[static_cast<size_t>(v)]) {
        kept[static_cast<size_t>(v)] = 1;
        id[static_cast<size_t>(root)] = v;
      } else {
        id[static_cast<size_t>(root)] = static_cast<int>(positions.rows() + static_cast<Eigen::Index>(copies.size()));
        copies.push_back(v);
      }
    }
    m.triangles(c / 3, c % 3) = id[static_cast<size_t>(root)];
  }
  m.positions.conservativeResize(positions.rows() + static_cast<Eigen::Index>(copies.size()), 3);
  for (size_t i = 0; i < copies.size(); ++i) {
    m.positions.row(positions.rows() + static_cast<Eigen::Index>(i)) = positions.row(copies[i]);
    m.original.push_back(copies[i]);
  }
  return m;
}

std::vector<CutChain> cut_chains(const Positions& positions, const FaceOrientation& orientation,
                                 const OpenedMesh& opened) {
  const auto& cut = orientation.cut;
  // Cut edges at each vertex: (vertex, edge) pairs, sorted.
  std::vector<std::pair<int, int>> at;
  for (size_t e = 0; e < cut.size(); ++e)
    for (int v : cut[e]) at.push_back({v, static_cast<int>(e)});
  std::sort(at.begin(), at.end());
  const auto incident = [&](int v) {
    const auto first = std::lower_bound(at.begin(), at.end(), std::make_pair(v, -1));
    std::vector<int> edges;
    for (auto i = first; i != at.end() && i->first == v; ++i) edges.push_back(i->second);
    return edges;
  };
  // The copy of v in face f: tells the sides of the cut apart.
  const auto copy = [&](int f, int v) { return opened.triangles(f, corner_of(orientation.triangles, f, v)); };
  std::vector<char> used(cut.size(), 0);
  std::vector<CutChain> chains;
  const auto walk = [&](int start, int e) {
    std::vector<int> order;  // edges in walking order
    for (int v = start; e >= 0 && !used[static_cast<size_t>(e)];) {
      used[static_cast<size_t>(e)] = 1;
      order.push_back(e);
      v = cut[static_cast<size_t>(e)][0] == v ? cut[static_cast<size_t>(e)][1] : cut[static_cast<size_t>(e)][0];
      const std::vector<int> next = incident(v);
      e = next.size() == 2 ? (next[0] == e ? next[1] : next[0]) : -1;
    }
    // The chain runs as its edges do (all one way along it): walked backwards
    // when its first edge runs into the start.
    if (cut[static_cast<size_t>(order[0])][1] == start) std::reverse(order.begin(), order.end());
    CutChain chain;
    for (int edge : order) {
      const std::array<int, 2>& ends = cut[static_cast<size_t>(edge)];
      std::array<int, 2> faces = orientation.cut_faces[static_cast<size_t>(edge)];
      if (!chain.edges.empty()) {
        // Side a where the previous edge's side a is: the same copy of the
        // vertex the two edges share.
        const std::array<int, 2>& before = chain.edges.back();
        const int shared = ends[0] == before[0] || ends[0] == before[1] ? ends[0] : ends[1];
        const int a = copy(chain.faces.back()[0], shared), b = copy(chain.faces.back()[1], shared);
        const int first = copy(faces[0], shared), second = copy(faces[1], shared);
        if (second == a || (first != a && first == b)) std::swap(faces[0], faces[1]);
      }
      chain.edges.push_back(ends);
      chain.faces.push_back(faces);
      chain.length += (positions.row(ends[0]) - positions.row(ends[1])).norm();
    }
    chains.push_back(std::move(chain));
  };
  std::vector<int> ends;  // vertices on other than two cut edges, ascending
  for (size_t i = 0; i < at.size();) {
    size_t j = i;
    while (j < at.size() && at[j].first == at[i].first) ++j;
    if (j - i != 2) ends.push_back(at[i].first);
    i = j;
  }
  for (int v : ends)
    for (int e : incident(v))
      if (!used[static_cast<size_t>(e)]) walk(v, e);
  for (size_t e = 0; e < cut.size(); ++e)
    if (!used[e]) walk(cut[e][0], static_cast<int>(e));
  return chains;
}

}  // namespace developable

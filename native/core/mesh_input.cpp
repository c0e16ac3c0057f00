#include "core/mesh_input.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace developable {
namespace {

std::string triangle_text(const Triangles& triangles, Eigen::Index f) {
  std::ostringstream s;
  s << "triangle " << f << " (" << triangles(f, 0) << ", " << triangles(f, 1) << ", " << triangles(f, 2) << ")";
  return s.str();
}

[[noreturn]] void fail(Status status, const std::string& message) { throw EngineError(status, message); }

// A directed edge a -> b of triangle `face`, sortable by (a, b).
struct DirectedEdge {
  int from;
  int to;
  int face;
  bool operator<(const DirectedEdge& o) const {
    return from != o.from ? from < o.from : (to != o.to ? to < o.to : face < o.face);
  }
};

std::vector<DirectedEdge> sorted_directed_edges(const Triangles& triangles) {
  std::vector<DirectedEdge> edges;
  edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      edges.push_back({triangles(f, c), triangles(f, (c + 1) % 3), static_cast<int>(f)});
    }
  }
  std::sort(edges.begin(), edges.end());
  return edges;
}

void check_counts_and_indices(const Positions& positions, const Triangles& triangles) {
  if (positions.rows() == 0) fail(Status::empty_input, "the mesh has no vertices");
  if (triangles.rows() == 0) fail(Status::empty_input, "the mesh has no triangles");
  const Eigen::Index n = positions.rows();
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = triangles(f, c);
      if (v < 0 || v >= n) {
        std::ostringstream s;
        s << triangle_text(triangles, f) << " names vertex " << v << ", but the mesh has " << n
          << " vertices (valid indices 0.." << n - 1 << ")";
        fail(Status::index_out_of_range, s.str());
      }
    }
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!positions.row(v).allFinite()) {
      std::ostringstream s;
      s << "vertex " << v << " has a non-finite coordinate (" << positions(v, 0) << ", " << positions(v, 1) << ", "
        << positions(v, 2) << ")";
      fail(Status::non_finite_coordinate, s.str());
    }
  }
}

void check_degenerate(const Positions& positions, const Triangles& triangles) {
  const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
  // Relative to the mesh size so that the check is the same at any scale.
  const double min_double_area = 2e-14 * diagonal * diagonal;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const int a = triangles(f, 0), b = triangles(f, 1), c = triangles(f, 2);
    if (a == b || b == c || a == c) {
      fail(Status::degenerate_triangle, triangle_text(triangles, f) + " repeats a vertex");
    }
    const Eigen::Vector3d e1 = positions.row(b) - positions.row(a);
    const Eigen::Vector3d e2 = positions.row(c) - positions.row(a);
    if (!(e1.cross(e2).norm() > min_double_area)) {
      fail(Status::degenerate_triangle, triangle_text(triangles, f) + " has zero area");
    }
  }
}

void check_duplicates(const Triangles& triangles) {
  std::vector<std::pair<std::array<int, 3>, int>> sorted(static_cast<size_t>(triangles.rows()));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    std::array<int, 3> t{triangles(f, 0), triangles(f, 1), triangles(f, 2)};
    std::sort(t.begin(), t.end());
    sorted[static_cast<size_t>(f)] = {t, static_cast<int>(f)};
  }
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].first == sorted[i - 1].first) {
      const int first = std::min(sorted[i].second, sorted[i - 1].second);
      const int second = std::max(sorted[i].second, sorted[i - 1].second);
      fail(Status::duplicate_triangle,
           triangle_text(triangles, second) + " repeats the vertices of triangle " + std::to_string(first));
    }
  }
}

void check_edges(const std::vector<DirectedEdge>& edges) {
  for (size_t i = 1; i < edges.size(); ++i) {
    if (edges[i].from != edges[i - 1].from || edges[i].to != edges[i - 1].to) continue;
    // The same directed edge twice: either three or more triangles share the
    // edge, or two neighbours disagree on orientation.
    const int a = edges[i].from, b = edges[i].to;
    size_t uses = 0;
    for (const auto& e : edges) uses += (e.from == a && e.to == b) || (e.from == b && e.to == a);
    std::ostringstream s;
    s << "edge (" << a << ", " << b << ") ";
    if (uses > 2) {
      s << "is shared by " << uses << " triangles (a non-manifold edge)";
    } else {
      s << "is used in the same direction by triangles " << edges[i - 1].face << " and " << edges[i].face
        << " (inconsistent orientation: flip one of them)";
    }
    fail(Status::non_manifold, s.str());
  }
}

// A vertex is manifold when the link edges (a -> b for each triangle (v, a, b))
// of its triangles form a single fan: one open chain or one closed cycle.
void check_vertex_fans(const Triangles& triangles, const VertexFaces& table) {
  std::vector<std::pair<int, int>> fan;
  for (Eigen::Index v = 0; v < table.vertex_count(); ++v) {
    const int count = table.count(v);
    if (count < 2) continue;
    fan.clear();
    for (const int* g = table.begin(v); g != table.end(v); ++g) {
      const int c = triangles(*g, 0) == v ? 0 : (triangles(*g, 1) == v ? 1 : 2);
      fan.emplace_back(triangles(*g, (c + 1) % 3), triangles(*g, (c + 2) % 3));
    }
    // Link edges a -> b are unique per source (check_edges ran first), so the
    // link is a set of chains and cycles; a single fan walks through all of it
    // from the one chain start, or from anywhere on the one cycle.
    auto successor = [&](int a) {
      for (int i = 0; i < count; ++i)
        if (fan[i].first == a) return fan[i].second;
      return -1;
    };
    int start = fan[0].first;
    int chain_starts = 0;
    for (int i = 0; i < count; ++i) {
      bool has_predecessor = false;
      for (int j = 0; j < count; ++j) has_predecessor |= fan[j].second == fan[i].first;
      if (!has_predecessor) {
        ++chain_starts;
        start = fan[i].first;
      }
    }
    int visited = 0;
    for (int at = successor(start); at >= 0 && visited < count; at = successor(at)) {
      ++visited;
      if (at == start) break;
    }
    if (chain_starts > 1 || visited != count) {
      std::ostringstream s;
      s << "vertex " << v << " is non-manifold: its " << count
        << " triangles form more than one fan (the surface touches itself there)";
      fail(Status::non_manifold, s.str());
    }
  }
}

}  // namespace

VertexFaces validate_mesh(const Positions& positions, const Triangles& triangles) {
  check_counts_and_indices(positions, triangles);
  check_degenerate(positions, triangles);
  check_duplicates(triangles);
  check_edges(sorted_directed_edges(triangles));
  VertexFaces table = vertex_faces(triangles, positions.rows());
  check_vertex_fans(triangles, table);
  return table;
}

Eigen::Index coincident_vertices(const Positions& positions) {
  std::vector<Eigen::Index> order(static_cast<size_t>(positions.rows()));
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
  auto less = [&](Eigen::Index a, Eigen::Index b) {
    for (int c = 0; c < 3; ++c)
      if (positions(a, c) != positions(b, c)) return positions(a, c) < positions(b, c);
    return false;
  };
  std::sort(order.begin(), order.end(), less);
  Eigen::Index count = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same_as_previous = i > 0 && !less(order[i - 1], order[i]);
    const bool same_as_next = i + 1 < order.size() && !less(order[i], order[i + 1]);
    count += same_as_previous || same_as_next;
  }
  return count;
}

std::vector<bool> boundary_vertices(const Positions& positions, const Triangles& triangles) {
  // On a validated mesh an edge is on the boundary when one triangle has
  // it: its key (smaller index, larger index) appears once. One sort of
  // plain keys; looking up each directed edge's reverse cost a 1M-face run
  // half a second per call.
  std::vector<std::uint64_t> keys;
  keys.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const auto a = static_cast<std::uint32_t>(triangles(f, c)),
                 b = static_cast<std::uint32_t>(triangles(f, (c + 1) % 3));
      keys.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
    }
  std::sort(keys.begin(), keys.end());
  std::vector<bool> boundary(static_cast<size_t>(positions.rows()), false);
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i == 1) {
      boundary[static_cast<size_t>(keys[i] >> 32)] = true;
      boundary[static_cast<size_t>(keys[i] & 0xffffffffu)] = true;
    }
    i = j;
  }
  return boundary;
}

}  // namespace developable

#include "core/mesh_input.h"

#include "core/union_find.h"

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

// Every triangle's three edges as keys (smaller index << 32 | larger index),
// sorted: an edge's triangles are one run of equal keys. One sort of plain
// keys; a map from each directed edge to its reverse cost a 1M-face run half
// a second per call.
std::vector<std::uint64_t> sorted_edge_keys(const Triangles& triangles) {
  std::vector<std::uint64_t> keys;
  keys.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const auto a = static_cast<std::uint32_t>(triangles(f, c)),
                 b = static_cast<std::uint32_t>(triangles(f, (c + 1) % 3));
      keys.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
    }
  std::sort(keys.begin(), keys.end());
  return keys;
}

// Edges of more than two triangles. Either winding of a triangle is
// accepted: which way neighbours run their shared edge is no error (an
// inconsistently wound or one-sided mesh, orientation.h).
void check_edges(const Triangles& triangles) {
  const std::vector<std::uint64_t> keys = sorted_edge_keys(triangles);
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i > 2) {
      std::ostringstream s;
      s << "edge (" << (keys[i] >> 32) << ", " << (keys[i] & 0xffffffffu) << ") is shared by " << j - i
        << " triangles (a non-manifold edge)";
      fail(Status::non_manifold, s.str());
    }
    i = j;
  }
}

// A vertex is manifold when its triangles form a single fan: their link
// edges {a, b} (for each triangle (v, a, b), either winding) are connected.
// Each link vertex is on at most two of them (check_edges ran first), so the
// connected link is one chain or one cycle.
void check_vertex_fans(const Triangles& triangles, const VertexFaces& table) {
  std::vector<std::pair<int, int>> ends;  // (link vertex, index of the triangle in the fan)
  for (Eigen::Index v = 0; v < table.vertex_count(); ++v) {
    const int count = table.count(v);
    if (count < 2) continue;
    ends.clear();
    for (int i = 0; i < count; ++i) {
      const int g = table.begin(v)[i];
      for (int c = 0; c < 3; ++c)
        if (triangles(g, c) != v) ends.emplace_back(triangles(g, c), i);
    }
    std::sort(ends.begin(), ends.end());
    UnionFind fan(static_cast<size_t>(count));
    int parts = count;
    for (size_t k = 1; k < ends.size(); ++k)
      if (ends[k].first == ends[k - 1].first && fan.unite(ends[k].second, ends[k - 1].second)) --parts;
    if (parts > 1) {
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
  check_edges(triangles);
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
  // it: its key appears once.
  const std::vector<std::uint64_t> keys = sorted_edge_keys(triangles);
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

#include "measures.h"

#include "mesh_input.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

Eigen::Vector3d corner(const Positions& positions, const Triangles& triangles, Eigen::Index f,
                       int c) {
  return positions.row(triangles(f, c)).transpose();
}

}  // namespace

Normals face_normals(const Positions& positions, const Triangles& triangles) {
  Normals normals(triangles.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector3d a = corner(positions, triangles, f, 0);
    const Eigen::Vector3d n =
        (corner(positions, triangles, f, 1) - a).cross(corner(positions, triangles, f, 2) - a);
    const double length = n.norm();
    normals.row(f) = length > 0.0 ? Eigen::RowVector3d(n.transpose() / length)
                                  : Eigen::RowVector3d::Zero();
  }
  return normals;
}

Eigen::VectorXd face_areas(const Positions& positions, const Triangles& triangles) {
  Eigen::VectorXd areas(triangles.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector3d a = corner(positions, triangles, f, 0);
    areas[f] = 0.5 * (corner(positions, triangles, f, 1) - a)
                         .cross(corner(positions, triangles, f, 2) - a)
                         .norm();
  }
  return areas;
}

double average_edge_length(const Positions& positions, const Triangles& triangles) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double sum = 0.0;
  for (const auto& [a, b] : edges) sum += (positions.row(a) - positions.row(b)).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

Eigen::VectorXd angle_defects(const Positions& positions, const Triangles& triangles,
                              const std::vector<bool>& interior) {
  Eigen::VectorXd angle_sum = Eigen::VectorXd::Zero(positions.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = corner(positions, triangles, f, c);
      const Eigen::Vector3d u = corner(positions, triangles, f, (c + 1) % 3) - p;
      const Eigen::Vector3d w = corner(positions, triangles, f, (c + 2) % 3) - p;
      // atan2 of |u x w| and u.w is accurate for tiny and near-straight angles,
      // where acos of the normalised dot product loses digits.
      angle_sum[triangles(f, c)] += std::atan2(u.cross(w).norm(), u.dot(w));
    }
  }
  Eigen::VectorXd defects = Eigen::VectorXd::Zero(positions.rows());
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    if (interior[static_cast<size_t>(v)]) defects[v] = 2.0 * M_PI - angle_sum[v];
  }
  return defects;
}

DefectStats defect_stats(const Eigen::VectorXd& defects, const std::vector<bool>& interior) {
  DefectStats stats;
  double sum = 0.0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    const double value = std::abs(defects[v]);
    sum += value;
    stats.max_abs = std::max(stats.max_abs, value);
    ++stats.interior_count;
  }
  if (stats.interior_count > 0) stats.mean_abs = sum / static_cast<double>(stats.interior_count);
  return stats;
}

std::vector<bool> interior_vertices(const Positions& positions, const Triangles& triangles) {
  std::vector<bool> interior = boundary_vertices(positions, triangles);
  std::vector<bool> used(interior.size(), false);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) used[static_cast<size_t>(triangles(f, c))] = true;
  for (size_t v = 0; v < interior.size(); ++v) interior[v] = used[v] && !interior[v];
  return interior;
}

}  // namespace developable

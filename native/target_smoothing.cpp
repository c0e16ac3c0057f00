#include "target_smoothing.h"

#include <algorithm>

namespace developable {

TargetSmoother::TargetSmoother(const Triangles& triangles, const std::vector<int>& patch_ids) {
  const Eigen::Index face_count = triangles.rows();
  if (static_cast<Eigen::Index>(patch_ids.size()) != face_count)
    throw EngineError(Status::internal_error, "target smoothing: one patch id per face");
  const Eigen::Index vertex_count = face_count > 0 ? triangles.maxCoeff() + 1 : 0;

  // Vertex -> faces, in compressed rows.
  std::vector<Eigen::Index> vertex_offsets(static_cast<size_t>(vertex_count) + 1, 0);
  for (Eigen::Index f = 0; f < face_count; ++f)
    for (int c = 0; c < 3; ++c) ++vertex_offsets[static_cast<size_t>(triangles(f, c)) + 1];
  for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) vertex_offsets[v + 1] += vertex_offsets[v];
  std::vector<Eigen::Index> vertex_faces(static_cast<size_t>(vertex_offsets.back()));
  std::vector<Eigen::Index> fill(vertex_offsets.begin(), vertex_offsets.end() - 1);
  for (Eigen::Index f = 0; f < face_count; ++f)
    for (int c = 0; c < 3; ++c) vertex_faces[static_cast<size_t>(fill[static_cast<size_t>(triangles(f, c))]++)] = f;

  offsets_.reserve(static_cast<size_t>(face_count) + 1);
  offsets_.push_back(0);
  neighbours_.reserve(static_cast<size_t>(face_count) * 13);
  std::vector<int> ring;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    ring.clear();
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<size_t>(triangles(f, c));
      for (Eigen::Index i = vertex_offsets[v]; i < vertex_offsets[v + 1]; ++i) {
        const Eigen::Index g = vertex_faces[static_cast<size_t>(i)];
        if (patch_ids[static_cast<size_t>(g)] == patch_ids[static_cast<size_t>(f)])
          ring.push_back(static_cast<int>(g));
      }
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    neighbours_.insert(neighbours_.end(), ring.begin(), ring.end());
    offsets_.push_back(neighbours_.size());
  }
}

Normals TargetSmoother::smooth(const Normals& targets, const Eigen::VectorXd& areas, int rounds) const {
  Normals current = targets;
  Normals next(targets.rows(), 3);
  for (int round = 0; round < rounds; ++round) {
    for (Eigen::Index f = 0; f < targets.rows(); ++f) {
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
      for (size_t i = offsets_[static_cast<size_t>(f)]; i < offsets_[static_cast<size_t>(f) + 1]; ++i)
        sum += areas[neighbours_[i]] * current.row(neighbours_[i]);
      const double length = sum.norm();
      next.row(f) = length > 0.0 ? Eigen::RowVector3d(sum / length) : current.row(f);
    }
    current.swap(next);
  }
  return current;
}

}  // namespace developable

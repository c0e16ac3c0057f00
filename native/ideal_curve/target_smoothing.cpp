#include "ideal_curve/target_smoothing.h"

#include <algorithm>
#include <cmath>

namespace developable {

TargetSmoother::TargetSmoother(const Triangles& triangles, const std::vector<int>& patch_ids)
    : TargetSmoother(triangles, patch_ids,
                     vertex_faces(triangles, triangles.rows() > 0 ? triangles.maxCoeff() + 1 : 0)) {}

TargetSmoother::TargetSmoother(const Triangles& triangles, const std::vector<int>& patch_ids,
                               const VertexFaces& table) {
  const Eigen::Index face_count = triangles.rows();
  if (static_cast<Eigen::Index>(patch_ids.size()) != face_count)
    throw EngineError(Status::internal_error, "target smoothing: one patch id per face");

  offsets_.reserve(static_cast<size_t>(face_count) + 1);
  offsets_.push_back(0);
  neighbours_.reserve(static_cast<size_t>(face_count) * 13);
  std::vector<int> ring;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    ring.clear();
    for (int c = 0; c < 3; ++c) {
      for (const int* g = table.begin(triangles(f, c)); g != table.end(triangles(f, c)); ++g) {
        if (patch_ids[static_cast<size_t>(*g)] == patch_ids[static_cast<size_t>(f)]) ring.push_back(*g);
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

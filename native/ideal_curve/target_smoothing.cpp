#include "ideal_curve/target_smoothing.h"

#include <Eigen/Eigenvalues>

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

namespace {
// Neighbours whose target is farther than this from the face's do not count
// toward its ruling average (0.35 rad, 20 degrees).
constexpr double kSameCurveAngle = 0.35;
}  // namespace

Normals TargetSmoother::smooth_along_rulings(const Normals& targets, const Positions& positions,
                                             const Triangles& triangles, const Eigen::VectorXd& areas,
                                             int rounds) const {
  const double same_curve = std::cos(kSameCurveAngle);
  Positions centroids(triangles.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    centroids.row(f) =
        (positions.row(triangles(f, 0)) + positions.row(triangles(f, 1)) + positions.row(triangles(f, 2))) / 3.0;
  Normals current = targets;
  Normals next(targets.rows(), 3);
  for (int round = 0; round < rounds; ++round) {
    for (Eigen::Index f = 0; f < targets.rows(); ++f) {
      const Eigen::Vector3d t = current.row(f).transpose();
      const size_t begin = offsets_[static_cast<size_t>(f)], end = offsets_[static_cast<size_t>(f) + 1];
      // The curve's direction at t: the principal direction of the
      // neighbours' target differences, in t's tangent plane.
      Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
      for (size_t i = begin; i < end; ++i) {
        const Eigen::Vector3d g = current.row(neighbours_[i]).transpose();
        if (g.dot(t) < same_curve) continue;
        Eigen::Vector3d d = g - t;
        d -= d.dot(t) * t;
        spread += d * d.transpose();
      }
      if (!(spread.trace() > 1e-14)) {
        next.row(f) = t.transpose();
        continue;
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
      eigen.computeDirect(spread);
      const Eigen::Vector3d along_curve = eigen.eigenvectors().col(2);
      const Eigen::Vector3d ruling = t.cross(along_curve).normalized();
      Eigen::Vector3d sum = areas[f] * t;
      const Eigen::Vector3d c = centroids.row(f).transpose();
      for (size_t i = begin; i < end; ++i) {
        const int g = neighbours_[i];
        if (g == f) continue;
        const Eigen::Vector3d tg = current.row(g).transpose();
        if (tg.dot(t) < same_curve) continue;
        const Eigen::Vector3d offset = centroids.row(g).transpose() - c;
        const double length = offset.norm();
        if (!(length > 0.0)) continue;
        const double a = std::abs(offset.dot(ruling)) / length;
        const double a2 = a * a, a4 = a2 * a2;
        sum += areas[g] * a4 * a4 * tg;
      }
      const double length = sum.norm();
      next.row(f) = length > 0.0 ? Eigen::RowVector3d((sum / length).transpose()) : current.row(f);
    }
    current.swap(next);
  }
  return current;
}

}  // namespace developable

#include "deformation/jet_denoise.h"

#include "core/measures.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace developable {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kMinRing = 9;
// The fit's Gaussian weights, exp(-r^2 / kWeightScale) with r the distance
// over the plane in RMS radii of the two-ring (sigma = sqrt 2 RMS radii):
// the far vertices carry the third-order terms a quadric cannot follow.
// Unweighted, a noise-free wavy generalized cone moved by up to 1.32 times
// the noise it had to remove (0.27 on average), weighted 1.10 (0.22). On
// the families (bench/families.py, mean log Hausdorff ratio to the twin):
// tuning seeds 0-5 0.052 -> 0.046, 6-9 0.051 -> 0.035, held-out 100-102
// 0.031 -> 0.025; scales 2 and 8 did less on seeds 6-9 and 100-102
// (docs/method.md, "Smoothed input").
constexpr double kWeightScale = 4.0;

// Collects rings without repeats: the vertices of a vertex's faces (and
// those faces), each once, in the order first met.
class RingCollector {
 public:
  RingCollector(Eigen::Index vertices, Eigen::Index faces)
      : vertex_stamp_(static_cast<size_t>(vertices), 0), face_stamp_(static_cast<size_t>(faces), 0) {}

  // Starts a new ring: every vertex and face counts as not met.
  void clear() { ++stamp_; }

  // Appends the vertices of `v`'s faces not met yet to `ring` and, given
  // `faces`, the faces not met yet to it; with groups, only the faces of
  // `group`.
  void add_neighbours(const VertexFaces& connectivity, const Triangles& triangles, const std::vector<int>& groups,
                      int group, Eigen::Index v, std::vector<Eigen::Index>& ring,
                      std::vector<Eigen::Index>* faces = nullptr) {
    for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
      if (!groups.empty() && groups[static_cast<size_t>(*f)] != group) continue;
      for (int c = 0; c < 3; ++c) {
        const auto u = static_cast<size_t>(triangles(*f, c));
        if (vertex_stamp_[u] == stamp_) continue;
        vertex_stamp_[u] = stamp_;
        ring.push_back(triangles(*f, c));
      }
      if (faces != nullptr && face_stamp_[static_cast<size_t>(*f)] != stamp_) {
        face_stamp_[static_cast<size_t>(*f)] = stamp_;
        faces->push_back(*f);
      }
    }
  }

 private:
  std::vector<uint32_t> vertex_stamp_, face_stamp_;  // two rings a vertex: 2^31 vertices before a wrap
  uint32_t stamp_ = 0;
};

// The group of all of v's faces; -1 with faces of two groups (or none).
int group_of(const VertexFaces& connectivity, const std::vector<int>& groups, Eigen::Index v) {
  if (groups.empty()) return 0;
  int group = -1;
  for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
    const int g = groups[static_cast<size_t>(*f)];
    if (group >= 0 && g != group) return -1;
    group = g;
  }
  return group;
}

}  // namespace

std::vector<Positions> jet_denoise(const Positions& positions, const Triangles& triangles,
                                   const VertexFaces& connectivity, const std::vector<bool>& pinned,
                                   const std::vector<double>& feature_angles_deg, const std::vector<int>& groups) {
  if (!groups.empty() && static_cast<Eigen::Index>(groups.size()) != triangles.rows())
    throw EngineError(Status::internal_error, "jet_denoise: one group per face");
  std::vector<Positions> smoothed(feature_angles_deg.size(), positions);
  if (feature_angles_deg.empty()) return smoothed;
  std::vector<double> min_cos;
  for (const double angle : feature_angles_deg) min_cos.push_back(std::cos(angle * kPi / 180.0));
  // A vertex at a feature for every guard is not fitted.
  const double widest = *std::min_element(min_cos.begin(), min_cos.end());
  const Normals normals = face_normals(positions, triangles);
  RingCollector rings(positions.rows(), triangles.rows());
  std::vector<Eigen::Index> one_ring, two_ring, faces;
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    if (!pinned.empty() && pinned[static_cast<size_t>(v)]) continue;
    const int group = group_of(connectivity, groups, v);
    if (group < 0) continue;
    one_ring.clear();
    rings.clear();
    rings.add_neighbours(connectivity, triangles, groups, group, v, one_ring);
    two_ring.clear();
    faces.clear();
    rings.clear();
    for (Eigen::Index u : one_ring) rings.add_neighbours(connectivity, triangles, groups, group, u, two_ring, &faces);
    if (two_ring.size() < kMinRing) continue;
    // Ascending, as the fit's rows must come in one order whatever the
    // order the faces are stored in around a vertex.
    std::sort(two_ring.begin(), two_ring.end());

    // The ring in v's frame, in units of its RMS radius: the fit below (its
    // pivoting included) then sees the same numbers at any scale, and a
    // mesh scaled by a power of two is smoothed to the same bits, scaled.
    const auto m = static_cast<Eigen::Index>(two_ring.size());
    Eigen::MatrixX3d local(m, 3);
    for (Eigen::Index i = 0; i < m; ++i)
      local.row(i) = positions.row(two_ring[static_cast<size_t>(i)]) - positions.row(v);
    const double radius = std::sqrt(local.rowwise().squaredNorm().mean());
    if (!(radius > 0.0)) continue;
    local /= radius;

    // The ring's plane: its principal axes about the centroid.
    const Eigen::RowVector3d centroid = local.colwise().mean();
    const Eigen::Matrix3d scatter = (local.rowwise() - centroid).transpose() * (local.rowwise() - centroid);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(scatter);
    const Eigen::Vector3d normal = axes.eigenvectors().col(0);  // smallest spread
    const Eigen::Vector3d t1 = axes.eigenvectors().col(2), t2 = axes.eigenvectors().col(1);
    // The cosine of the ring's face turned farthest from the plane: each
    // guard keeps the vertex where it is below its own.
    double plane_cos = std::numeric_limits<double>::infinity();
    for (const Eigen::Index f : faces) plane_cos = std::min(plane_cos, std::abs(normals.row(f).dot(normal)));
    if (plane_cos < widest) continue;

    // The height field over the plane, in v's frame (f is v's height on
    // it), each row weighed (kWeightScale).
    Eigen::MatrixXd design(m, 6);
    Eigen::VectorXd height(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Vector3d p = local.row(i).transpose();
      const double x = p.dot(t1), y = p.dot(t2);
      const double weight = std::exp(-(x * x + y * y) / kWeightScale);
      design.row(i) << weight * x * x, weight * x * y, weight * y * y, weight * x, weight * y, weight;
      height[i] = weight * p.dot(normal);
    }
    const Eigen::VectorXd coefficients = design.colPivHouseholderQr().solve(height);
    if (!std::isfinite(coefficients[5])) continue;
    const Eigen::RowVector3d move = (coefficients[5] * radius) * normal.transpose();
    for (size_t k = 0; k < min_cos.size(); ++k)
      if (plane_cos >= min_cos[k]) smoothed[k].row(v) += move;
  }
  return smoothed;
}

Positions jet_denoise(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                      const std::vector<bool>& pinned, const JetDenoiseOptions& options) {
  std::vector<Positions> smoothed =
      jet_denoise(positions, triangles, connectivity, pinned, {options.feature_angle_deg}, options.face_groups);
  return std::move(smoothed.front());
}

}  // namespace developable

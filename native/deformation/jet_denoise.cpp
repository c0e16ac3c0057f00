#include "deformation/jet_denoise.h"

#include "core/measures.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

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

// Appends the vertices of `v`'s faces to `ring` (with repeats) and, given
// `faces`, the faces to it; with groups, only the faces of `group`.
void add_neighbours(const VertexFaces& connectivity, const Triangles& triangles, const std::vector<int>& groups,
                    int group, Eigen::Index v, std::vector<Eigen::Index>& ring,
                    std::vector<Eigen::Index>* faces = nullptr) {
  for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
    if (!groups.empty() && groups[static_cast<size_t>(*f)] != group) continue;
    for (int c = 0; c < 3; ++c) ring.push_back(triangles(*f, c));
    if (faces) faces->push_back(*f);
  }
}

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

void sort_unique(std::vector<Eigen::Index>& items) {
  std::sort(items.begin(), items.end());
  items.erase(std::unique(items.begin(), items.end()), items.end());
}

}  // namespace

Positions jet_denoise(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                      const std::vector<bool>& pinned, const JetDenoiseOptions& options) {
  const Normals normals = face_normals(positions, triangles);
  const double min_cos = std::cos(options.feature_angle_deg * kPi / 180.0);
  const std::vector<int>& groups = options.face_groups;
  if (!groups.empty() && static_cast<Eigen::Index>(groups.size()) != triangles.rows())
    throw EngineError(Status::internal_error, "jet_denoise: one group per face");
  Positions smoothed = positions;
  std::vector<Eigen::Index> one_ring, two_ring, faces;
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    if (!pinned.empty() && pinned[static_cast<size_t>(v)]) continue;
    const int group = group_of(connectivity, groups, v);
    if (group < 0) continue;
    one_ring.clear();
    add_neighbours(connectivity, triangles, groups, group, v, one_ring);
    sort_unique(one_ring);
    two_ring.clear();
    faces.clear();
    for (Eigen::Index u : one_ring) add_neighbours(connectivity, triangles, groups, group, u, two_ring, &faces);
    sort_unique(two_ring);
    if (two_ring.size() < kMinRing) continue;
    sort_unique(faces);

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
    const bool feature = std::any_of(faces.begin(), faces.end(),
                                     [&](Eigen::Index f) { return std::abs(normals.row(f).dot(normal)) < min_cos; });
    if (feature) continue;

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
    smoothed.row(v) += (coefficients[5] * radius) * normal.transpose();
  }
  return smoothed;
}

}  // namespace developable

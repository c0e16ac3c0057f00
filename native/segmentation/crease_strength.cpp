#include "segmentation/crease_strength.h"

#include "core/concurrent_jobs.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace developable {

std::vector<MeshEdge> mesh_edges(const Triangles& triangles, const VertexFaces& connectivity) {
  std::vector<MeshEdge> edges;
  edges.reserve(static_cast<size_t>(3 * triangles.rows() / 2 + 3));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      const int g = face_across(connectivity, triangles, static_cast<int>(f), a, b);
      if (g >= 0 && g < f) continue;  // listed from its first face
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f), g});
    }
  }
  return edges;
}

Eigen::Matrix3d barycentric_gradients(const Positions& positions, const Triangles& triangles, Eigen::Index face) {
  Eigen::Vector3d x[3];
  for (int c = 0; c < 3; ++c) x[c] = positions.row(triangles(face, c)).transpose();
  const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]);
  const double twice_area = n.norm();
  Eigen::Matrix3d gradients = Eigen::Matrix3d::Zero();
  if (!(twice_area > 0.0)) return gradients;
  const Eigen::Vector3d unit = n / twice_area;
  for (int c = 0; c < 3; ++c) gradients.col(c) = unit.cross(x[(c + 2) % 3] - x[(c + 1) % 3]) / twice_area;
  return gradients;
}

namespace {

// The median of a two-dimensional standard normal vector's norm, sqrt(2 ln 2):
// a score per unit noise has this median where the noise alone makes it.
constexpr double kMedianNormalNorm = 1.1774100225154747;

// What the fits need of a face: its centroid and the gradients of its three
// barycentric functions (columns; a corner's unit move along the normal tilts
// the face's normal by minus its gradient), and the RMS tilt per unit noise.
struct FaceData {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d gradients = Eigen::Matrix3d::Zero();
  double tilt = std::numeric_limits<double>::infinity();  // of a zero-area face
};

std::vector<FaceData> face_data(const Positions& positions, const Triangles& triangles) {
  std::vector<FaceData> data(static_cast<size_t>(triangles.rows()));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    FaceData& d = data[static_cast<size_t>(f)];
    for (int c = 0; c < 3; ++c) d.centroid += positions.row(triangles(f, c)).transpose() / 3.0;
    d.gradients = barycentric_gradients(positions, triangles, f);
    if (!d.gradients.isZero(0.0)) d.tilt = std::sqrt(d.gradients.squaredNorm() / 2.0);
  }
  return data;
}

// The faces of an edge's 2-ring: those around the edge's vertices and their
// neighbours, ascending. A ring holds a few dozen faces, so sorted small
// vectors beat marks over the whole mesh (and chunks of edges share nothing).
void two_ring(const MeshEdge& edge, const Triangles& triangles, const VertexFaces& connectivity,
              std::vector<int>& vertices, std::vector<int>& faces) {
  vertices.assign({edge.a, edge.b});
  for (int v : {edge.a, edge.b})
    for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f)
      for (int c = 0; c < 3; ++c) vertices.push_back(triangles(*f, c));
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  faces.clear();
  for (int v : vertices) faces.insert(faces.end(), connectivity.begin(v), connectivity.end(v));
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
}

// The weighted least-squares line y = a + b u + c w of one side and one
// component, from its sums.
struct SideSums {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();  // sum of W x x^T, x = (1, u, w)
  Eigen::Vector3d right = Eigen::Vector3d::Zero();   // sum of W x y
  int count = 0;

  void add(const Eigen::Vector3d& x, double y, double weight) {
    normal += weight * x * x.transpose();
    right += weight * x * y;
    ++count;
  }
};

// The fitted field's value at the edge's midpoint (a) and its variance per
// unit noise variance, or nothing (too few faces, or their centroids on one
// line).
std::optional<std::pair<double, double>> intercept(const SideSums& sums) {
  if (sums.count < kMinSideFaces) return std::nullopt;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(sums.normal);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  const Eigen::Vector3d d = ldlt.vectorD();
  if (!(d.minCoeff() > 1e-12 * d.maxCoeff())) return std::nullopt;
  const double value = ldlt.solve(sums.right)[0], variance = ldlt.solve(Eigen::Vector3d::UnitX())[0];
  if (!std::isfinite(value) || !(variance > 0.0)) return std::nullopt;
  return std::make_pair(value, variance);
}

// One edge's jump (rad) and its squared score per unit noise; found false
// without a score.
struct EdgeFit {
  double jump = 0.0, score_squared = 0.0;
  bool found = false;
};

EdgeFit fit_edge(const MeshEdge& edge, const Positions& positions, const Normals& normals,
                 const std::vector<FaceData>& data, const std::vector<bool>& usable, const std::vector<int>& ring) {
  EdgeFit out;
  if (!usable[static_cast<size_t>(edge.f)] || !usable[static_cast<size_t>(edge.g)]) return out;
  const Eigen::Vector3d pa = positions.row(edge.a).transpose(), pb = positions.row(edge.b).transpose();
  const double length = (pb - pa).norm();
  const Eigen::Vector3d mid = 0.5 * (pa + pb), t = (pb - pa) / length;
  Eigen::Vector3d n0 = normals.row(edge.f).transpose() + normals.row(edge.g).transpose();
  n0 -= t * n0.dot(t);
  if (!(n0.norm() > 1e-12)) return out;  // the two faces folded onto each other
  n0.normalize();
  const Eigen::Vector3d across = n0.cross(t);
  const Eigen::Vector3d axes[2] = {across, t};  // the tilt about the edge, then across it
  SideSums sums[2][2];                          // [component][side]
  for (int f : ring) {
    const auto fi = static_cast<size_t>(f);
    if (!usable[fi]) continue;
    const Eigen::Vector3d d = (data[fi].centroid - mid) / length;  // in edge lengths: better conditioned
    const double w = d.dot(across);
    const Eigen::Vector3d x(1.0, d.dot(t), w);
    for (int k = 0; k < 2; ++k) {
      const double variance = (data[fi].gradients.transpose() * axes[k]).squaredNorm();
      sums[k][w > 0.0 ? 1 : 0].add(x, normals.row(f).dot(axes[k]), 1.0 / variance);
    }
  }
  double jump_squared = 0.0;
  for (int k = 0; k < 2; ++k) {
    const auto low = intercept(sums[k][0]), high = intercept(sums[k][1]);
    if (!low || !high) return out;
    const double jump = high->first - low->first;
    jump_squared += jump * jump;
    out.score_squared += jump * jump / (low->second + high->second);
  }
  out.jump =
      2.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(jump_squared)));  // the chord between unit normals, as an angle
  out.found = true;
  return out;
}

// Edges per chunk of the parallel loop: some 30 faces' sums each.
constexpr Eigen::Index kEdgeChunk = 2048;

std::vector<EdgeFit> fit_edges(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, const std::vector<MeshEdge>& edges,
                               const std::vector<FaceData>& data, const std::vector<bool>& usable, int threads) {
  std::vector<EdgeFit> fits(edges.size());
  parallel_for(static_cast<Eigen::Index>(edges.size()), kEdgeChunk, threads, [&](Eigen::Index begin, Eigen::Index end) {
    std::vector<int> vertices, ring;
    for (Eigen::Index e = begin; e < end; ++e) {
      const MeshEdge& edge = edges[static_cast<size_t>(e)];
      if (edge.g < 0) continue;
      two_ring(edge, triangles, connectivity, vertices, ring);
      fits[static_cast<size_t>(e)] = fit_edge(edge, positions, normals, data, usable, ring);
    }
  });
  return fits;
}

// The middle value (0 without one).
double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The noise (caller's units) that makes the median score what noise alone
// gives: most edges are not on a crease. 0 without a scored edge.
double median_noise(const std::vector<EdgeFit>& fits) {
  std::vector<double> scores;
  for (const EdgeFit& fit : fits)
    if (fit.found) scores.push_back(std::sqrt(fit.score_squared));
  return median(std::move(scores)) / kMedianNormalNorm;
}

// The median tilt per unit noise of the faces with an area; 0 without one.
double median_tilt(const std::vector<FaceData>& data) {
  std::vector<double> tilts;
  for (const FaceData& d : data)
    if (std::isfinite(d.tilt)) tilts.push_back(d.tilt);
  return median(std::move(tilts));
}

double mean_edge_length(const Positions& positions, const std::vector<MeshEdge>& edges) {
  double sum = 0.0;
  for (const MeshEdge& e : edges) sum += (positions.row(e.a) - positions.row(e.b)).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

}  // namespace

CreaseStrengths crease_strengths(const Positions& positions, const Triangles& triangles, const Normals& normals,
                                 const VertexFaces& connectivity, const std::vector<MeshEdge>& edges, int threads) {
  const std::vector<FaceData> data = face_data(positions, triangles);
  std::vector<bool> usable(data.size());
  for (size_t f = 0; f < data.size(); ++f) usable[f] = std::isfinite(data[f].tilt);
  // First with every face that has an area, for the noise; then without the
  // faces that noise leaves without a direction.
  std::vector<EdgeFit> fits = fit_edges(positions, triangles, normals, connectivity, edges, data, usable, threads);
  CreaseStrengths out;
  out.noise = std::max(median_noise(fits), kNoiseFloor * mean_edge_length(positions, edges));
  const double outlier = kOutlierTilt * median_tilt(data);
  bool dropped = false;
  for (size_t f = 0; f < data.size(); ++f) {
    const bool keep = usable[f] && (out.noise * data[f].tilt < kUnreliableTilt || data[f].tilt < outlier);
    dropped = dropped || keep != usable[f];
    usable[f] = keep;
  }
  if (dropped) fits = fit_edges(positions, triangles, normals, connectivity, edges, data, usable, threads);
  const auto m = static_cast<Eigen::Index>(edges.size());
  out.jump = Eigen::VectorXd::Zero(m);
  out.score = Eigen::VectorXd::Zero(m);
  for (Eigen::Index e = 0; e < m; ++e) {
    const EdgeFit& fit = fits[static_cast<size_t>(e)];
    if (!fit.found) continue;
    out.jump[e] = fit.jump;
    out.score[e] = std::sqrt(fit.score_squared) / out.noise;
  }
  return out;
}

}  // namespace developable

#include "deformation/deformation.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>
#include <queue>

namespace developable {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// A_t^T A_t of Eq. 3's 11 x 9 triangle matrix (unknowns v_i, v_j, v_k, xyz
// each) in closed form: the 9 edge and centroid rows give the same 3 x 3
// pattern in every coordinate, and the 2 normal rows add omega^2 n n^T
// blocks with the pattern [[2, -1, -1], [-1, 1, 0], [-1, 0, 1]].
Eigen::Matrix<double, 9, 9> coupled_normal_block(const Eigen::Matrix3d& shape, const Eigen::Vector3d& target,
                                                 double omega) {
  static const Eigen::Matrix3d normal_pattern =
      (Eigen::Matrix3d() << 2.0, -1.0, -1.0, -1.0, 1.0, 0.0, -1.0, 0.0, 1.0).finished();
  const Eigen::Matrix3d nn = omega * omega * target * target.transpose();
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 9, 9> block;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) block.block<3, 3>(3 * r, 3 * c) = shape(r, c) * identity + normal_pattern(r, c) * nn;
  return block;
}

// The normal matrix on the free unknowns and its coupling to the pinned
// coordinates, summed from one block per face: block_of(f) is a 3 D x 3 D
// matrix over the face's corners' D unknowns each (row r: corner r / D,
// coordinate r % D; D = 1 in the decoupled system, 3 in the coupled one).
// Unknown D u + k is coordinate k of the free vertex numbered u
// (free_index), column D v + k of free_pinned that of pinned vertex v.
// block_of returns a matrix, not an Eigen expression (which could refer to
// a temporary gone by the time it is read).
template <int D, typename BlockOf>
void normal_matrices(const Triangles& triangles, const std::vector<int>& free_index, Eigen::Index free_count,
                     const BlockOf& block_of, Eigen::SparseMatrix<double>& free_free,
                     Eigen::SparseMatrix<double>& free_pinned) {
  const auto n = static_cast<Eigen::Index>(free_index.size());
  Triplets free_free_entries, free_pinned_entries;
  free_free_entries.reserve(static_cast<size_t>(triangles.rows()) * 9 * D * D);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Matrix<double, 3 * D, 3 * D> block = block_of(f);
    for (int r = 0; r < 3 * D; ++r) {
      const int row_vertex = free_index[static_cast<size_t>(triangles(f, r / D))];
      if (row_vertex < 0) continue;
      for (int c = 0; c < 3 * D; ++c) {
        const int v = triangles(f, c / D);
        const int col_vertex = free_index[static_cast<size_t>(v)];
        if (col_vertex >= 0)
          free_free_entries.emplace_back(D * row_vertex + r % D, D * col_vertex + c % D, block(r, c));
        else
          free_pinned_entries.emplace_back(D * row_vertex + r % D, D * v + c % D, block(r, c));
      }
    }
  }
  free_free.resize(D * free_count, D * free_count);
  free_free.setFromTriplets(free_free_entries.begin(), free_free_entries.end());
  free_pinned.resize(D * free_count, D * n);
  free_pinned.setFromTriplets(free_pinned_entries.begin(), free_pinned_entries.end());
}

// The 3 x 3 scalar rows shared by both systems: two edges and the centroid
// (weighted by sqrt(centroid_weight)).
Eigen::Matrix3d decoupled_rows(double centroid_weight) {
  const double c = std::sqrt(centroid_weight) / 3.0;
  Eigen::Matrix3d b;
  b << -1.0, 1.0, 0.0, -1.0, 0.0, 1.0, c, c, c;
  return b;
}

Eigen::Vector3d vertex(const Positions& p, int v) { return p.row(v).transpose(); }

// Rotation turning unit `from` toward unit `to` by about `fraction` of the
// angle between them: onto their normalised blend d = (1 - fraction) from +
// fraction to, by Rodrigues' formula R = I + [v]x + [v]x^2 / (1 + c) with
// v = from x d, c = from . d. No trigonometry (an atan2 and a sincos per face
// were a fifth of an iteration); the turned angle is fraction * angle to
// O(angle^3): 1.3 % more at 90 degrees for fraction 25/26. 1 + c is taken as
// |from + d|^2 / 2, which does not cancel. Identity when d is undefined or
// (anti)parallel to `from` (within ~1e-6 rad of pi the axis is noise).
Eigen::Matrix3d partial_rotation(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double fraction) {
  const Eigen::Vector3d blend = (1.0 - fraction) * from + fraction * to;
  const double length = blend.norm();
  if (!(length > 0.0)) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d d = blend / length;
  const double one_plus_cos = 0.5 * (from + d).squaredNorm();
  if (one_plus_cos < 1e-12) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d v = from.cross(d);
  Eigen::Matrix3d cross;
  cross << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  // [v]x^2 = v v^T - |v|^2 I.
  const double scale = 1.0 / one_plus_cos;
  return (1.0 - scale * v.squaredNorm()) * Eigen::Matrix3d::Identity() + cross + (scale * v) * v.transpose();
}

template <typename Derived>
void check_finite(const Eigen::MatrixBase<Derived>& x) {
  if (!x.allFinite()) throw EngineError(Status::numerical_failure, "the linear solve produced non-finite positions");
}

}  // namespace

Positions solve_three_columns(const CholeskySolver& solver, const Positions& b) {
  const Eigen::SparseMatrix<double>& lower = solver.matrixL().nestedExpression();  // unit diagonal implied
  const Eigen::VectorXd& diagonal = solver.vectorD();
  const int* permutation = solver.permutationP().indices().data();
  const Eigen::Index n = b.rows();
  Positions y(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) y.row(permutation[i]) = b.row(i);

  const int* column_start = lower.outerIndexPtr();
  const int* column_count = lower.innerNonZeroPtr();  // null when compressed
  const auto column_end = [&](Eigen::Index j) {
    return column_count ? column_start[j] + column_count[j] : column_start[j + 1];
  };
  const int* row_of = lower.innerIndexPtr();
  const double* value = lower.valuePtr();
  double* yd = y.data();
  for (Eigen::Index j = 0; j < n; ++j) {  // L y = P b, by columns
    const double y0 = yd[3 * j], y1 = yd[3 * j + 1], y2 = yd[3 * j + 2];
    for (int k = column_start[j]; k < column_end(j); ++k) {
      double* target = yd + 3 * static_cast<Eigen::Index>(row_of[k]);
      target[0] -= value[k] * y0;
      target[1] -= value[k] * y1;
      target[2] -= value[k] * y2;
    }
  }
  for (Eigen::Index j = 0; j < n; ++j) y.row(j) *= 1.0 / diagonal[j];  // as Eigen: by the inverse
  for (Eigen::Index j = n - 1; j >= 0; --j) {                          // L^T z = D^-1 y, by rows of L^T
    double z0 = yd[3 * j], z1 = yd[3 * j + 1], z2 = yd[3 * j + 2];
    for (int k = column_start[j]; k < column_end(j); ++k) {
      const double* source = yd + 3 * static_cast<Eigen::Index>(row_of[k]);
      z0 -= value[k] * source[0];
      z1 -= value[k] * source[1];
      z2 -= value[k] * source[2];
    }
    yd[3 * j] = z0;
    yd[3 * j + 1] = z1;
    yd[3 * j + 2] = z2;
  }
  Positions x(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) x.row(i) = y.row(permutation[i]);
  return x;
}

Eigen::VectorXd mls_row_weights(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                                double average_edge_length) {
  const Eigen::Index n = positions.rows();
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(triangles.rows());
  bool any_pin = false;
  for (Eigen::Index v = 0; v < n; ++v) any_pin |= pinned[static_cast<size_t>(v)];
  if (!any_pin) return weights;

  // Multi-source Dijkstra along the edges: the distance to the nearest pin
  // measured on the surface, so a pin across a gap does not stiffen a part
  // it is not connected to.
  std::vector<std::vector<std::pair<int, double>>> neighbours(static_cast<size_t>(n));
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      const double length = (positions.row(a) - positions.row(b)).norm();
      neighbours[static_cast<size_t>(a)].emplace_back(b, length);
      neighbours[static_cast<size_t>(b)].emplace_back(a, length);
    }
  }
  std::vector<double> distance(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (Eigen::Index v = 0; v < n; ++v) {
    if (pinned[static_cast<size_t>(v)]) {
      distance[static_cast<size_t>(v)] = 0.0;
      queue.emplace(0.0, static_cast<int>(v));
    }
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[static_cast<size_t>(v)]) continue;
    for (const auto& [w, length] : neighbours[static_cast<size_t>(v)]) {
      if (d + length < distance[static_cast<size_t>(w)]) {
        distance[static_cast<size_t>(w)] = d + length;
        queue.emplace(d + length, w);
      }
    }
  }

  constexpr double eps = 1e-3;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) nearest = std::min(nearest, distance[static_cast<size_t>(triangles(f, c))]);
    if (!std::isfinite(nearest)) continue;  // a component without pins
    const double d = nearest / average_edge_length;
    weights[f] = 1.0 + 1.0 / (d * d + eps * eps);
  }
  return weights;
}

NormalGuidedDeformation::NormalGuidedDeformation(const Triangles& triangles, const std::vector<bool>& pinned,
                                                 Eigen::VectorXd row_weights, double omega, double centroid_weight,
                                                 Formulation formulation, const Normals& targets, int threads)
    : triangles_(triangles),
      row_weights_(std::move(row_weights)),
      omega_(omega),
      centroid_weight_(centroid_weight),
      formulation_(formulation),
      targets_(targets),
      threads_(threads),
      system_(std::make_shared<System>()) {
  system_->free_index.assign(pinned.size(), -1);
  if (!(omega > 0.0) || !std::isfinite(omega))
    throw EngineError(Status::invalid_argument, "omega must be a positive number");
  if (!(centroid_weight > 0.0) || !std::isfinite(centroid_weight))
    throw EngineError(Status::invalid_argument, "the centroid weight must be a positive number");
  if (row_weights_.size() != triangles.rows() || targets.rows() != triangles.rows())
    throw EngineError(Status::internal_error, "deformation: one weight and target per triangle");
  if (!row_weights_.allFinite() || !(row_weights_.array() > 0.0).all())
    throw EngineError(Status::invalid_argument, "deformation: row weights must be positive numbers");

  // Unknowns are the free vertices that some triangle uses; unused vertices
  // simply stay where they are.
  std::vector<bool> used(pinned.size(), false);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) used[static_cast<size_t>(triangles(f, c))] = true;
  for (size_t v = 0; v < pinned.size(); ++v)
    if (used[v] && !pinned[v]) system_->free_index[v] = static_cast<int>(system_->free_count++);
  if (system_->free_count == 0)
    throw EngineError(Status::no_free_vertex, "every vertex is pinned: there is nothing the deformation may move");

  if (formulation_ == Formulation::coupled) {
    factor_coupled();
    return;
  }
  // The decoupled matrix is factored and let go (at 1M faces 42 MB through
  // the iterations, the run's peak); system_matrix() builds it anew.
  Eigen::SparseMatrix<double> free_free;
  decoupled_matrices(free_free, system_->free_pinned);
  system_->solver.compute(free_free);
  if (system_->solver.info() != Eigen::Success)
    throw EngineError(Status::numerical_failure, "factoring the deformation matrix failed");
}

void NormalGuidedDeformation::decoupled_matrices(Eigen::SparseMatrix<double>& free_free,
                                                 Eigen::SparseMatrix<double>& free_pinned) const {
  const Eigen::Matrix3d b = decoupled_rows(centroid_weight_);
  const Eigen::Matrix3d local = b.transpose() * b;
  normal_matrices<1>(
      triangles_, system_->free_index, system_->free_count,
      [&](Eigen::Index f) -> Eigen::Matrix3d { return row_weights_[f] * local; }, free_free, free_pinned);
}

void NormalGuidedDeformation::coupled_matrices(Eigen::SparseMatrix<double>& free_free,
                                               Eigen::SparseMatrix<double>& free_pinned) const {
  const Eigen::Matrix3d b = decoupled_rows(centroid_weight_);
  const Eigen::Matrix3d shape = b.transpose() * b;
  normal_matrices<3>(
      triangles_, system_->free_index, system_->free_count,
      [&](Eigen::Index f) -> Eigen::Matrix<double, 9, 9> {
        return row_weights_[f] * coupled_normal_block(shape, targets_.row(f).transpose(), omega_);
      },
      free_free, free_pinned);
}

void NormalGuidedDeformation::factor_coupled() {
  // The pattern depends only on the mesh and the pins: analysed once, at the
  // first factorisation. The matrices' triplets are gone before it.
  const bool first = system_->free_free.nonZeros() == 0;
  coupled_matrices(system_->free_free, system_->free_pinned);
  if (first) system_->solver.analyzePattern(system_->free_free);
  system_->solver.factorize(system_->free_free);
  if (system_->solver.info() != Eigen::Success)
    throw EngineError(Status::numerical_failure, "factoring the deformation matrix failed");
}

void NormalGuidedDeformation::set_targets(const Normals& targets) {
  if (targets.rows() != triangles_.rows())
    throw EngineError(Status::internal_error, "deformation: one target per triangle");
  targets_ = targets;
  if (formulation_ == Formulation::coupled) factor_coupled();
}

NormalGuidedDeformation NormalGuidedDeformation::sharing_factor() const {
  if (!system_ || formulation_ != Formulation::decoupled)
    throw EngineError(Status::internal_error, "deformation: only a decoupled system's factor can be shared");
  return NormalGuidedDeformation(*this);
}

Eigen::SparseMatrix<double> NormalGuidedDeformation::system_matrix() const {
  if (!system_) throw EngineError(Status::internal_error, "deformation: the system was released");
  if (formulation_ == Formulation::coupled) return system_->free_free;
  Eigen::SparseMatrix<double> free_free, free_pinned;
  decoupled_matrices(free_free, free_pinned);
  return free_free;
}

void NormalGuidedDeformation::release() {
  system_.reset();
  triangles_ = Triangles();
  row_weights_ = Eigen::VectorXd();
  targets_ = Normals();
  normal_weights_ = Eigen::VectorXd();
}

Positions NormalGuidedDeformation::step(const Positions& current) const {
  if (!system_) throw EngineError(Status::internal_error, "deformation: the system was released");
  if (formulation_ == Formulation::coupled) return step_coupled(current);
  return step_decoupled(current, face_normals(current, triangles_));
}

Positions NormalGuidedDeformation::step(const Positions& current, const Normals& normals) const {
  if (!system_) throw EngineError(Status::internal_error, "deformation: the system was released");
  if (formulation_ == Formulation::coupled) return step_coupled(current);
  if (normals.rows() != triangles_.rows())
    throw EngineError(Status::internal_error, "deformation: one normal per triangle");
  return step_decoupled(current, normals);
}

Positions NormalGuidedDeformation::step_coupled(const Positions& current) const {
  // Right-hand side W A^T c; the normal rows have c = 0 and add nothing.
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * system_->free_count);
  for (Eigen::Index f = 0; f < triangles_.rows(); ++f) {
    const int i = triangles_(f, 0), j = triangles_(f, 1), k = triangles_(f, 2);
    const Eigen::Vector3d pi = vertex(current, i), pj = vertex(current, j), pk = vertex(current, k);
    const Eigen::Vector3d eij = pj - pi, eik = pk - pi, third = centroid_weight_ * (pi + pj + pk) / 9.0;
    const Eigen::Vector3d g[3] = {-eij - eik + third, eij + third, eik + third};
    for (int c = 0; c < 3; ++c) {
      const int row = system_->free_index[static_cast<size_t>(triangles_(f, c))];
      if (row >= 0) rhs.segment<3>(3 * row) += row_weights_[f] * g[c];
    }
  }
  const Eigen::Map<const Eigen::VectorXd> all(current.data(), current.size());
  rhs -= system_->free_pinned * all;  // row-major positions: index 3 v + axis
  const Eigen::VectorXd x = system_->solver.solve(rhs);
  check_finite(x);
  Positions next = current;
  for (size_t v = 0; v < system_->free_index.size(); ++v) {
    const int row = system_->free_index[v];
    if (row >= 0) next.row(static_cast<Eigen::Index>(v)) = x.segment<3>(3 * row).transpose();
  }
  return next;
}

void NormalGuidedDeformation::set_normal_weights(Eigen::VectorXd weights) {
  if (weights.size() != 0 && weights.size() != triangles_.rows())
    throw EngineError(Status::internal_error, "deformation: one normal weight per triangle");
  for (Eigen::Index f = 0; f < weights.size(); ++f)
    if (!(weights[f] >= 0.0 && weights[f] <= 1.0))
      throw EngineError(Status::internal_error, "deformation: normal weights must be in [0, 1]");
  normal_weights_ = std::move(weights);
}

Positions NormalGuidedDeformation::step_decoupled(const Positions& current, const Normals& normals) const {
  const double full_fraction = omega_ * omega_ / (1.0 + omega_ * omega_);
  const bool weighted = normal_weights_.size() != 0;
  // Each triangle's three rows of the right-hand side (its rotated edges
  // and centroid term), a block of triangles at a time on the cores, then
  // added up in triangle order: the same sums whatever the thread count.
  // The rotations were a tenth of a 1M-face run.
  constexpr Eigen::Index kBlock = 65536, kChunk = 16384;
  const Eigen::Index faces = triangles_.rows();
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> rows(std::min(kBlock, faces), 9);
  Positions rhs = Positions::Zero(system_->free_count, 3);
  for (Eigen::Index first = 0; first < faces; first += kBlock) {
    const Eigen::Index last = std::min(faces, first + kBlock);
    parallel_for(last - first, kChunk, threads_, [&](Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index f = first + begin; f < first + end; ++f) {
        double fraction = full_fraction;
        if (weighted) {
          const double w = omega_ * normal_weights_[f];
          fraction = w * w / (1.0 + w * w);
        }
        const int i = triangles_(f, 0), j = triangles_(f, 1), k = triangles_(f, 2);
        const Eigen::Vector3d pi = vertex(current, i), pj = vertex(current, j), pk = vertex(current, k);
        const Eigen::Vector3d normal = normals.row(f).transpose();
        const Eigen::Matrix3d rotation = partial_rotation(normal, targets_.row(f).transpose(), fraction);
        const Eigen::Vector3d eij = rotation * (pj - pi), eik = rotation * (pk - pi);
        const Eigen::Vector3d third = centroid_weight_ * (pi + pj + pk) / 9.0;
        const Eigen::Vector3d g[3] = {-eij - eik + third, eij + third, eik + third};
        for (int c = 0; c < 3; ++c) rows.block<1, 3>(f - first, 3 * c) = row_weights_[f] * g[c].transpose();
      }
    });
    for (Eigen::Index f = first; f < last; ++f)
      for (int c = 0; c < 3; ++c) {
        const int row = system_->free_index[static_cast<size_t>(triangles_(f, c))];
        if (row >= 0) rhs.row(row) += rows.block<1, 3>(f - first, 3 * c);
      }
  }
  rhs -= system_->free_pinned * current;
  const Positions x = solve_three_columns(system_->solver, rhs);
  check_finite(x);
  Positions next = current;
  for (size_t v = 0; v < system_->free_index.size(); ++v) {
    const int row = system_->free_index[v];
    if (row >= 0) next.row(static_cast<Eigen::Index>(v)) = x.row(row);
  }
  return next;
}

}  // namespace developable

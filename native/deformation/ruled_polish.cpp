#include "deformation/ruled_polish.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "deformation/conjugate_gradients.h"
#include "deformation/move_limit.h"
#include "deformation/normal_equations.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

// A scored vertex takes part in a step while its |defect| or its spread is
// above this share of its threshold (kFlatDefect, kRuledSpread).
constexpr double kActiveShare = 0.3;
// Levenberg-Marquardt damping: start, cut after a kept step, raised after a
// failed one, and the trials per step.
constexpr double kFirstDamping = 1e-3;
constexpr double kDampingDown = 3.0;
constexpr double kDampingUp = 8.0;
constexpr double kSmallestDamping = 1e-9;
constexpr int kTrials = 6;
constexpr int kRevertRounds = 20;
// The conjugate gradients of a step: relative residual and iterations.
constexpr double kStepTolerance = 1e-2;
constexpr int kStepIterations = 50;

using SparseMatrix = Eigen::SparseMatrix<double>;

class RuledPolish {
 public:
  RuledPolish(const Positions& start, const Positions& reference, const Normals& reference_normals,
              const Triangles& triangles, const std::vector<bool>& scored, const std::vector<bool>& pinned,
              const RuledPolishOptions& options)
      : reference_(reference),
        reference_normals_(reference_normals),
        triangles_(triangles),
        options_(options),
        n_(start.rows()),
        table_(vertex_faces(triangles, start.rows())),
        current_(start) {
    if (options.fit_weight > 0.0) fit_scale_ = options.fit_weight / average_edge_length(reference, triangles);
    for (Eigen::Index v = 0; v < n_; ++v)
      if (scored[static_cast<size_t>(v)] && table_.count(v) >= 3) scored_.push_back(v);
    scored_mask_.assign(static_cast<size_t>(n_), false);
    for (Eigen::Index v : scored_) scored_mask_[static_cast<size_t>(v)] = true;
    free_.assign(static_cast<size_t>(n_), true);
    for (Eigen::Index v = 0; v < n_ && !pinned.empty(); ++v)
      free_[static_cast<size_t>(v)] = !pinned[static_cast<size_t>(v)];
  }

  RuledPolishResult run(const Progress& progress);

  // The objective the steps lower (robust groups and fit) at `p`, with the
  // axes fitted there.
  double objective(const Positions& p) const;

 private:
  // Per scored vertex (in scored_ order): its faces' tip angles and the axis.
  struct Star {
    std::vector<double> tips;  // per face of table_, in its order
    double total = 0.0;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  };

  // What a step starts from at `p`: the stars with their axes fitted there,
  // the face normals, the angle defects and the residual groups.
  struct State {
    std::vector<Star> stars;
    Normals normals;
    Eigen::VectorXd defects;
    Eigen::VectorXd r;
  };
  State state_at(const Positions& p) const;

  void measure(const Positions& p, std::vector<Star>& stars, bool refit) const;
  // The residual groups at `p` with the axes of `stars` (their tips refreshed).
  Eigen::VectorXd residual(const Positions& p, std::vector<Star>& stars, const Normals& normals,
                           const Eigen::VectorXd& defects) const;
  Eigen::VectorXd group_weights(const Eigen::VectorXd& r) const;
  double weighted(const Eigen::VectorXd& r, const Eigen::VectorXd& weights) const;
  double robust_objective(const Eigen::VectorXd& r) const;
  // The fit rows' sum of squares at `p`.
  double fit_energy(const Positions& p) const {
    return fit_scale_ > 0.0 ? fit_scale_ * fit_scale_ * (p - reference_).squaredNorm() : 0.0;
  }
  std::vector<int> active_columns(const Positions& p, const std::vector<Star>& stars, const Normals& normals,
                                  const Eigen::VectorXd& defects) const;
  // J of the residual groups at `p` over the active columns, into `equations`.
  void jacobian(const Positions& p, const std::vector<Star>& stars, const Normals& normals,
                const std::vector<int>& column_of, Eigen::Index columns, NormalEquations& equations) const;
  size_t group_size(size_t s) const { return 1 + static_cast<size_t>(table_.count(scored_[s])); }

  const Positions& reference_;
  const Normals& reference_normals_;
  const Triangles& triangles_;
  const RuledPolishOptions& options_;
  const Eigen::Index n_;
  const VertexFaces table_;
  std::vector<Eigen::Index> scored_;
  std::vector<bool> scored_mask_;
  std::vector<bool> free_;
  Positions current_;
  double fit_scale_ = 0.0;  // wF / AE; 0 without the fit
};

double tip_angle(const Positions& p, const Triangles& t, int f, Eigen::Index v) {
  int c = 0;
  while (t(f, c) != v) ++c;
  const Eigen::RowVector3d a = p.row(t(f, (c + 1) % 3)) - p.row(v);
  const Eigen::RowVector3d b = p.row(t(f, (c + 2) % 3)) - p.row(v);
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

void RuledPolish::measure(const Positions& p, std::vector<Star>& stars, bool refit) const {
  const Normals normals = refit ? face_normals(p, triangles_) : Normals();
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index v = scored_[s];
    Star& star = stars[s];
    star.tips.clear();
    star.total = 0.0;
    Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
    for (const int* f = table_.begin(v); f != table_.end(v); ++f) {
      const double tip = tip_angle(p, triangles_, *f, v);
      star.tips.push_back(tip);
      star.total += tip;
      if (refit) {
        const Eigen::Vector3d n = normals.row(*f).transpose();
        moments.noalias() += tip * n * n.transpose();
      }
    }
    if (refit) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(moments);
      star.axis = solver.eigenvectors().col(0);
    }
  }
}

Eigen::VectorXd RuledPolish::residual(const Positions& p, std::vector<Star>& stars, const Normals& normals,
                                      const Eigen::VectorXd& defects) const {
  measure(p, stars, false);
  size_t rows = 0;
  for (size_t s = 0; s < scored_.size(); ++s) rows += group_size(s);
  Eigen::VectorXd r(static_cast<Eigen::Index>(rows));
  Eigen::Index row = 0;
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index v = scored_[s];
    r[row++] = options_.defect_weight * defects[v];
    size_t k = 0;
    for (const int* f = table_.begin(v); f != table_.end(v); ++f, ++k) {
      const double share = std::sqrt(std::max(stars[s].tips[k], 0.0) / std::max(stars[s].total, 1e-300));
      r[row++] = options_.ruled_weight * share * stars[s].axis.dot(normals.row(*f).transpose());
    }
  }
  return r;
}

Eigen::VectorXd RuledPolish::group_weights(const Eigen::VectorXd& r) const {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(r.size());
  if (!(options_.robust > 0.0)) return w;
  const double eps = options_.robust;
  Eigen::Index row = 0;
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index size = static_cast<Eigen::Index>(group_size(s));
    const double rho = r.segment(row, size).norm();
    w.segment(row, size).setConstant(std::sqrt(eps / std::sqrt(rho * rho + eps * eps)));
    row += size;
  }
  return w;
}

double RuledPolish::weighted(const Eigen::VectorXd& r, const Eigen::VectorXd& weights) const {
  return r.cwiseProduct(weights).squaredNorm();
}

double RuledPolish::robust_objective(const Eigen::VectorXd& r) const {
  const double eps = options_.robust > 0.0 ? options_.robust : 1.0;
  double sum = 0.0;
  Eigen::Index row = 0;
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index size = static_cast<Eigen::Index>(group_size(s));
    const double rho2 = r.segment(row, size).squaredNorm();
    sum += 2.0 * eps * (std::sqrt(rho2 + eps * eps) - eps);
    row += size;
  }
  return sum;
}

std::vector<int> RuledPolish::active_columns(const Positions& p, const std::vector<Star>& stars, const Normals& normals,
                                             const Eigen::VectorXd& defects) const {
  (void)p;
  std::vector<int> column_of(static_cast<size_t>(n_), -1);
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index v = scored_[s];
    double spread2 = 0.0;
    size_t k = 0;
    for (const int* f = table_.begin(v); f != table_.end(v); ++f, ++k) {
      const double d = stars[s].axis.dot(normals.row(*f).transpose());
      spread2 += stars[s].tips[k] * d * d;
    }
    const double spread = std::sqrt(spread2 / std::max(stars[s].total, 1e-300));
    if (std::abs(defects[v]) <= kActiveShare * kFlatDefect && spread <= kActiveShare * kRuledSpread) continue;
    for (const int* f = table_.begin(v); f != table_.end(v); ++f)
      for (int c = 0; c < 3; ++c) {
        const int u = triangles_(*f, c);
        if (free_[static_cast<size_t>(u)]) column_of[static_cast<size_t>(u)] = 0;
      }
  }
  int next = 0;
  for (int& c : column_of)
    if (c == 0) c = next++;
  return column_of;
}

void RuledPolish::jacobian(const Positions& p, const std::vector<Star>& stars, const Normals& normals,
                           const std::vector<int>& column_of, Eigen::Index columns, NormalEquations& equations) const {
  // A scored vertex's rows: K_v first, then one ruled row per face. K_v's
  // entries come from every face, so each face's gradients are found first
  // and the rows written after, each in the order its entries arise.
  struct Corner {
    int vertex;
    Eigen::Vector3d gradient;
  };
  std::vector<Corner> k_entries, r_entries;
  std::vector<size_t> r_end;  // per face: the end of its ruled row's entries
  const auto add = [&](const Corner& corner) {
    const int c = column_of[static_cast<size_t>(corner.vertex)];
    if (c < 0) return;
    for (int k = 0; k < 3; ++k) equations.add(3 * c + k, corner.gradient[k]);
  };
  equations.start(3 * columns);
  for (size_t s = 0; s < scored_.size(); ++s) {
    const Eigen::Index v = scored_[s];
    k_entries.clear();
    r_entries.clear();
    r_end.clear();
    // K_v = 2 pi - sum of v's tip angles (defect_polish.cpp has the gradients).
    size_t k = 0;
    for (const int* f = table_.begin(v); f != table_.end(v); ++f, ++k) {
      int c = 0;
      while (triangles_(*f, c) != v) ++c;
      const int b = triangles_(*f, (c + 1) % 3), d = triangles_(*f, (c + 2) % 3);
      const Eigen::Vector3d u = (p.row(b) - p.row(v)).transpose();
      const Eigen::Vector3d w = (p.row(d) - p.row(v)).transpose();
      const Eigen::Vector3d cross = u.cross(w);
      const double length = cross.norm();
      const double share = std::sqrt(std::max(stars[s].tips[k], 0.0) / std::max(stars[s].total, 1e-300));
      if (length > 0.0) {
        const Eigen::Vector3d n = cross / length;
        const Eigen::Vector3d grad_b = n.cross(u) / u.squaredNorm();
        const Eigen::Vector3d grad_d = -n.cross(w) / w.squaredNorm();
        k_entries.push_back({static_cast<int>(v), options_.defect_weight * -(grad_b + grad_d)});
        k_entries.push_back({b, options_.defect_weight * grad_b});
        k_entries.push_back({d, options_.defect_weight * grad_d});
        // d(axis . n_f): the face's corners in its own order (i, j, l).
        const int i = triangles_(*f, 0), j = triangles_(*f, 1), l = triangles_(*f, 2);
        const Eigen::Vector3d e1 = (p.row(j) - p.row(i)).transpose(), e2 = (p.row(l) - p.row(i)).transpose();
        const Eigen::Vector3d nf = normals.row(*f).transpose();
        const double area2 = e1.cross(e2).norm();
        if (area2 > 0.0) {
          const Eigen::Vector3d g = (stars[s].axis - stars[s].axis.dot(nf) * nf) / area2;
          const double weight = options_.ruled_weight * share;
          const Eigen::Vector3d gj = e2.cross(g), gl = g.cross(e1);
          r_entries.push_back({i, -weight * (gj + gl)});
          r_entries.push_back({j, weight * gj});
          r_entries.push_back({l, weight * gl});
        }
      }
      r_end.push_back(r_entries.size());
    }
    equations.next_row();
    for (const Corner& corner : k_entries) add(corner);
    size_t first = 0;
    for (size_t end : r_end) {
      equations.next_row();
      for (; first < end; ++first) add(r_entries[first]);
    }
  }
}

RuledPolish::State RuledPolish::state_at(const Positions& p) const {
  State state;
  state.stars.resize(scored_.size());
  measure(p, state.stars, true);
  state.normals = face_normals(p, triangles_, options_.spare_cores);
  state.defects = angle_defects(p, triangles_, scored_mask_, options_.spare_cores);
  state.r = residual(p, state.stars, state.normals, state.defects);
  return state;
}

double RuledPolish::objective(const Positions& p) const { return robust_objective(state_at(p).r) + fit_energy(p); }

RuledPolishResult RuledPolish::run(const Progress& progress) {
  RuledPolishResult result;
  result.positions = current_;
  if (scored_.empty()) return result;
  auto [stars, normals, defects, r] = state_at(current_);
  Eigen::VectorXd weights = group_weights(r);
  double mu = kFirstDamping;
  std::vector<double> history;
  NormalEquations equations;  // its buffers serve every step
  for (int it = 0; it < options_.max_iterations; ++it) {
    progress.report(static_cast<double>(it) / options_.max_iterations, "ruled polish");
    const std::vector<int> column_of = active_columns(current_, stars, normals, defects);
    const Eigen::Index columns = *std::max_element(column_of.begin(), column_of.end()) + 1;
    if (columns <= 0) break;
    // The rows weighted in place (each entry times its row's weight, as
    // weights.asDiagonal() * J computes it, without a second matrix).
    jacobian(current_, stars, normals, column_of, columns, equations);
    equations.scale_rows(weights);
    const Eigen::VectorXd rw = weights.cwiseProduct(r);
    SparseMatrix& normal_matrix = equations.normal_matrix();
    Eigen::VectorXd gradient = equations.transposed_times(rw);
    const double scale = normal_matrix.diagonal().mean();
    // The fit and the damping go onto the diagonal in place (each attempt
    // sets the damping from the undamped values), not onto a copy of the
    // matrix per attempt; every column has its diagonal entry.
    std::vector<double*> diagonal(static_cast<size_t>(normal_matrix.rows()));
    for (Eigen::Index c = 0; c < normal_matrix.rows(); ++c)
      diagonal[static_cast<size_t>(c)] = &normal_matrix.coeffRef(c, c);
    // The fit rows: identity blocks times wF / AE (their Jacobian is diagonal).
    if (fit_scale_ > 0.0) {
      const double f2 = fit_scale_ * fit_scale_;
      for (Eigen::Index v = 0; v < n_; ++v) {
        const int c = column_of[static_cast<size_t>(v)];
        if (c < 0) continue;
        for (int k = 0; k < 3; ++k) {
          *diagonal[static_cast<size_t>(3 * c + k)] += f2;
          gradient[3 * c + k] += f2 * (current_(v, k) - reference_(v, k));
        }
      }
    }
    std::vector<double> undamped(diagonal.size());
    for (size_t c = 0; c < diagonal.size(); ++c) undamped[c] = *diagonal[c];
    const double energy = weighted(r, weights) + fit_energy(current_);
    bool kept = false;
    Positions trial;
    Eigen::VectorXd trial_r, trial_defects;
    Normals trial_normals;
    std::vector<Star> trial_stars = stars;
    for (int attempt = 0; attempt < kTrials && !kept; ++attempt) {
      for (size_t c = 0; c < diagonal.size(); ++c) *diagonal[c] = undamped[c] + mu * scale;
      // Conjugate gradients, inexact: the line search below judges the step.
      // A sparse Cholesky factor of this 3n system (3x3 blocks over two
      // rings) was four fifths of the run's time (bunny: 31 s in all).
      ConjugateGradients solver;
      solver.compute(normal_matrix);
      const Eigen::VectorXd step = -solver.solve(gradient, kStepIterations, kStepTolerance, options_.spare_cores);
      if (!step.allFinite()) {
        mu *= kDampingUp;
        continue;
      }
      for (double length : {1.0, 0.5, 0.25}) {
        trial = current_;
        for (Eigen::Index v = 0; v < n_; ++v) {
          const int c = column_of[static_cast<size_t>(v)];
          if (c < 0) continue;
          trial.row(v) += length * step.segment<3>(3 * c).transpose();
          trial.row(v) = within_limit(trial.row(v), reference_.row(v), options_.limit);
        }
        if (!put_back_folded_corners(trial, current_, triangles_, reference_normals_, options_.crease_guard,
                                     kRevertRounds, options_.spare_cores))
          continue;
        trial_normals = face_normals(trial, triangles_, options_.spare_cores);
        trial_defects = angle_defects(trial, triangles_, scored_mask_, options_.spare_cores);
        trial_r = residual(trial, trial_stars, trial_normals, trial_defects);
        if (weighted(trial_r, weights) + fit_energy(trial) < energy) {
          kept = true;
          if (length < 1.0) mu *= kDampingDown;
          break;
        }
      }
      if (!kept) mu *= kDampingUp;
    }
    if (!kept) break;
    current_ = std::move(trial);
    normals = std::move(trial_normals);
    defects = std::move(trial_defects);
    mu = std::max(mu / kDampingDown, kSmallestDamping);
    measure(current_, stars, true);
    r = residual(current_, stars, normals, defects);
    weights = group_weights(r);
    ++result.iterations;
    history.push_back(robust_objective(r) + fit_energy(current_));
    const size_t window = static_cast<size_t>(options_.stall_window);
    if (history.size() > window) {
      const double before = history[history.size() - 1 - window];
      if (before <= 0.0 || (before - history.back()) / before < options_.stall_decrease) break;
    }
  }
  result.positions = current_;
  return result;
}

}  // namespace

RuledPolishResult polish_ruled(const Positions& start, const Positions& reference, const Normals& reference_normals,
                               const Triangles& triangles, const std::vector<bool>& scored,
                               const std::vector<bool>& pinned, const RuledPolishOptions& options,
                               const Progress& progress) {
  const Eigen::Index n = start.rows();
  if (reference.rows() != n || static_cast<Eigen::Index>(scored.size()) != n ||
      (!pinned.empty() && static_cast<Eigen::Index>(pinned.size()) != n) ||
      reference_normals.rows() != triangles.rows())
    throw EngineError(Status::internal_error, "polish_ruled: sizes disagree");
  RuledPolish polish(start, reference, reference_normals, triangles, scored, pinned, options);
  return polish.run(progress);
}

double ruled_polish_objective(const Positions& positions, const Positions& reference, const Triangles& triangles,
                              const std::vector<bool>& scored, const RuledPolishOptions& options) {
  const Eigen::Index n = positions.rows();
  if (reference.rows() != n || static_cast<Eigen::Index>(scored.size()) != n)
    throw EngineError(Status::internal_error, "ruled_polish_objective: sizes disagree");
  const Normals unused;  // the guard's normals: no step is taken
  const RuledPolish polish(positions, reference, unused, triangles, scored, {}, options);
  return polish.objective(positions);
}

}  // namespace developable

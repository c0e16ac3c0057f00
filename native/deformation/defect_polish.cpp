#include "deformation/defect_polish.h"

#include "core/measures.h"
#include "deformation/move_limit.h"

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <limits>

namespace developable {
namespace {

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Levenberg-Marquardt damping, relative to the mean diagonal of J J^T.
constexpr double kInitialDamping = 1e-6;
constexpr double kSmallestDamping = 1e-12;
constexpr double kLargestDamping = 1e4;
constexpr double kDampingDown = 3.0;
constexpr double kDampingUp = 8.0;
// A kept step that lowered sum K^2 by less than this fraction ends the
// polish when the damping cannot grow (kLargestDamping); before, the damping
// grows by kDampingUp and the polish goes on.
constexpr double kStallDecrease = 1e-6;
// A factor is reused while its steps lower sum K^2 by at least this fraction.
constexpr double kReuseDecrease = 0.5;
// Halvings of a step that does not lower sum K^2 before the factor is renewed.
constexpr int kHalvings = 3;
// The stall window (kept steps) of the stall rule; its flat threshold is
// kFlatDefect (measures.h).
constexpr size_t kStallWindow = 10;
// Once every row is flat, the rest only finishes what is already flat: a
// polish whose last kFinishWindow steps took off less than kFinishDecrease of
// sum K^2 stops (the benchmark's noise-free wavy cone of 100k faces, flat
// from the start, spent 2.6 s for 0.1 % of it).
constexpr size_t kFinishWindow = 3;
constexpr double kFinishDecrease = 0.03;
// The conjugate gradients' limits (DampedSystem, above options.direct_rows).
constexpr int kIterativeSteps = 100;
constexpr double kIterativeTolerance = 1e-8;
// Rounds of putting back the corners of faces a step turns over before the
// step counts as not kept.
constexpr int kRevertRounds = 10;
// The damping of the projection's steps (PolishOptions::pull_steps): next to
// none, as they must reach the input's side of the constraints, not only
// lower K.
constexpr double kPullDamping = 1e-9;

// dK/dx of the constrained vertices, with a pattern fixed at construction:
// row r (constrained vertex v) holds the three coordinates of every free
// vertex of v's closed star, so J J^T keeps one pattern for the whole run.
class DefectJacobian {
 public:
  DefectJacobian(const Triangles& triangles, const std::vector<int>& row_of, const std::vector<int>& free_of,
                 Eigen::Index rows, Eigen::Index free_count)
      : triangles_(triangles), row_of_(row_of), free_of_(free_of) {
    // The free vertices of each constrained vertex's closed star, sorted.
    std::vector<std::vector<int>> star(static_cast<size_t>(rows));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int row = row_of[static_cast<size_t>(triangles(f, c))];
        if (row < 0) continue;
        for (int k = 0; k < 3; ++k) {
          const int u = free_of[static_cast<size_t>(triangles(f, k))];
          if (u >= 0) star[static_cast<size_t>(row)].push_back(u);
        }
      }
    jacobian_.resize(rows, 3 * free_count);
    Eigen::VectorXi sizes(rows);
    for (Eigen::Index r = 0; r < rows; ++r) {
      auto& s = star[static_cast<size_t>(r)];
      std::sort(s.begin(), s.end());
      s.erase(std::unique(s.begin(), s.end()), s.end());
      sizes[r] = 3 * static_cast<int>(s.size());
    }
    jacobian_.reserve(sizes);
    for (Eigen::Index r = 0; r < rows; ++r)
      for (int u : star[static_cast<size_t>(r)])
        for (int k = 0; k < 3; ++k) jacobian_.insert(r, 3 * u + k) = 0.0;
    jacobian_.makeCompressed();
  }

  const RowMatrix& matrix() const { return jacobian_; }

  // Fills the values at `positions` and returns K of the constrained rows.
  Eigen::VectorXd evaluate(const Positions& positions, const Eigen::VectorXd& defects) {
    std::fill(jacobian_.valuePtr(), jacobian_.valuePtr() + jacobian_.nonZeros(), 0.0);
    Eigen::VectorXd residual(jacobian_.rows());
    for (size_t v = 0; v < row_of_.size(); ++v)
      if (row_of_[v] >= 0) residual[row_of_[v]] = defects[static_cast<Eigen::Index>(v)];
    for (Eigen::Index f = 0; f < triangles_.rows(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const int a = triangles_(f, c), b = triangles_(f, (c + 1) % 3), d = triangles_(f, (c + 2) % 3);
        const int row = row_of_[static_cast<size_t>(a)];
        if (row < 0) continue;
        const Eigen::Vector3d u = (positions.row(b) - positions.row(a)).transpose();
        const Eigen::Vector3d w = (positions.row(d) - positions.row(a)).transpose();
        const Eigen::Vector3d cross = u.cross(w);
        const double length = cross.norm();
        if (!(length > 0.0)) continue;  // a collapsed corner has no direction to move in
        const Eigen::Vector3d n = cross / length;
        // K_a = 2 pi - sum theta: dK/dx = -d theta/dx.
        const Eigen::Vector3d grad_b = n.cross(u) / u.squaredNorm();   // -d theta / d b
        const Eigen::Vector3d grad_d = -n.cross(w) / w.squaredNorm();  // -d theta / d d
        add(row, a, -(grad_b + grad_d));
        add(row, b, grad_b);
        add(row, d, grad_d);
      }
    }
    return residual;
  }

 private:
  void add(int row, int vertex, const Eigen::Vector3d& gradient) {
    const int u = free_of_[static_cast<size_t>(vertex)];
    if (u < 0) return;
    const int* begin = jacobian_.innerIndexPtr() + jacobian_.outerIndexPtr()[row];
    const int* end = jacobian_.innerIndexPtr() + jacobian_.outerIndexPtr()[row + 1];
    const int* at = std::lower_bound(begin, end, 3 * u);
    double* value = jacobian_.valuePtr() + (at - jacobian_.innerIndexPtr());
    value[0] += gradient[0];
    value[1] += gradient[1];
    value[2] += gradient[2];
  }

  const Triangles& triangles_;
  const std::vector<int>& row_of_;
  const std::vector<int>& free_of_;
  RowMatrix jacobian_;
};

// The damped system (J J^T + damping) y = K. Up to `direct_rows` rows, a
// sparse Cholesky factorisation (exact steps, few iterations); above, J J^T
// couples each vertex to its two rings and the factor fills in (50k rows:
// 10M entries, 1.2 s a factorisation), so conjugate gradients with a
// diagonal preconditioner take over (memory of J J^T only, 0.15 s a solve
// at 50k rows); the Levenberg-Marquardt test takes their inexact steps or
// not like any other.
class DampedSystem {
 public:
  explicit DampedSystem(Eigen::Index direct_rows) : direct_rows_(direct_rows) {}

  // Factors (or prepares) `matrix`, kept by the system; false on failure.
  bool compute(Eigen::SparseMatrix<double> matrix) {
    matrix_ = std::move(matrix);
    if (matrix_.rows() <= direct_rows_) {
      if (!analysed_) {
        direct_.analyzePattern(matrix_);
        analysed_ = true;
      }
      direct_.factorize(matrix_);
      return direct_.info() == Eigen::Success;
    }
    iterative_.setMaxIterations(kIterativeSteps);
    iterative_.setTolerance(kIterativeTolerance);
    iterative_.compute(matrix_);
    return iterative_.info() == Eigen::Success;
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    if (matrix_.rows() <= direct_rows_) return direct_.solve(rhs);
    return iterative_.solve(rhs);
  }

 private:
  Eigen::Index direct_rows_;
  Eigen::SparseMatrix<double> matrix_;  // the iterative solver reads it at every solve
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct_;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> iterative_;
  bool analysed_ = false;
};

// Which vertices a polish moves and which defects it works on, read off the
// defects at its start. The free vertices of the closed stars of the active
// vertices (constrained, |K| >= active_defect) move; the rows are the
// constrained vertices whose closed star holds a moving vertex, i.e. every
// defect a step can change. Everything else stays where it is, so a mesh
// that is flat but for a few vertices costs a system of their size.
struct Region {
  std::vector<bool> moves;
  std::vector<bool> reachable;  // the vertices of the faces that hold a moving vertex
  std::vector<bool> rows;       // constrained and reachable
};

Region region_of(const Triangles& triangles, const std::vector<bool>& constrained, const std::vector<bool>& pinned,
                 const Eigen::VectorXd& defects, double active_defect) {
  const size_t n = constrained.size();
  auto is_free = [&](int v) { return pinned.empty() || !pinned[static_cast<size_t>(v)]; };
  Region region{std::vector<bool>(n, false), std::vector<bool>(n, false), std::vector<bool>(n, false)};
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    bool active = false;
    for (int c = 0; c < 3; ++c) {
      const int v = triangles(f, c);
      active = active || (constrained[static_cast<size_t>(v)] && std::abs(defects[v]) >= active_defect);
    }
    if (active)
      for (int c = 0; c < 3; ++c) region.moves[static_cast<size_t>(triangles(f, c))] = is_free(triangles(f, c));
  }
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    if (region.moves[static_cast<size_t>(triangles(f, 0))] || region.moves[static_cast<size_t>(triangles(f, 1))] ||
        region.moves[static_cast<size_t>(triangles(f, 2))])
      for (int c = 0; c < 3; ++c) {
        const auto v = static_cast<size_t>(triangles(f, c));
        region.reachable[v] = true;
        region.rows[v] = constrained[v];
      }
  }
  return region;
}

// The give-up bounds of PolishOptions (give_up_move, late_give_up_move) on a
// mesh that may be a submesh: the RMS move over the whole mesh from the
// squared moves of its own vertices.
struct GiveUp {
  const PolishOptions& options;
  double outside2 = 0.0;  // squared moves of the whole mesh's vertices outside the submesh, summed
  double count = 1.0;     // vertices of the whole mesh

  bool active() const { return options.give_up_move > 0.0 || options.late_give_up_move != nullptr; }
  double bound() const {
    if (options.give_up_move > 0.0) return options.give_up_move;
    const double known = options.late_give_up_move != nullptr ? options.late_give_up_move->load() : 0.0;
    return known > 0.0 ? known : std::numeric_limits<double>::infinity();
  }
  double rms(double inside2) const { return std::sqrt((inside2 + outside2) / count); }
};

// The polish of `region` on the mesh it was read off: the Levenberg-Marquardt
// iterations of polish_defects (their contract), from `start` with its
// `defects` (read at the rows only), giving up past `give_up`'s bound.
PolishResult polish_region(const Positions& start, const Positions& reference, const Normals& reference_normals,
                           const Triangles& triangles, const Region& region, Eigen::VectorXd defects,
                           const PolishOptions& options, const GiveUp& give_up, const Progress& progress) {
  const Eigen::Index n = start.rows();
  PolishResult result;
  result.positions = start;
  std::vector<int> free_of(static_cast<size_t>(n), -1);
  Eigen::Index free_count = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (region.moves[static_cast<size_t>(v)]) free_of[static_cast<size_t>(v)] = static_cast<int>(free_count++);
  std::vector<int> row_of(static_cast<size_t>(n), -1);
  Eigen::Index rows = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (region.rows[static_cast<size_t>(v)]) row_of[static_cast<size_t>(v)] = static_cast<int>(rows++);
  if (rows == 0 || free_count == 0) return result;

  DefectJacobian jacobian(triangles, row_of, free_of, rows, free_count);
  const CreaseGuard crease_guard(triangles, reference_normals, options.crease_groups, options.crease_growth);
  Eigen::VectorXd residual = jacobian.evaluate(start, defects);
  result.residual_before = std::sqrt(residual.squaredNorm() / static_cast<double>(rows));
  result.residual_after = result.residual_before;
  auto residual_at = [&](const Eigen::VectorXd& d) {
    Eigen::VectorXd r(rows);
    for (Eigen::Index v = 0; v < n; ++v)
      if (row_of[static_cast<size_t>(v)] >= 0) r[row_of[static_cast<size_t>(v)]] = d[v];
    return r;
  };

  // J J^T + damping is factored at one iterate and reused while its steps
  // keep lowering sum K^2 well (the vertices move little, so J changes
  // little); it is refactored at the current iterate when a step gains
  // little, and with more damping when even a fresh factor's steps fail.
  DampedSystem system(options.direct_rows);
  bool fresh = false;
  // The spreading damping holds until every |K| is below spread_until.
  double least_damping = std::max(kSmallestDamping, options.spread_damping);
  double damping = std::max(kInitialDamping, least_damping);
  // Factors J J^T + mu (relative to its mean diagonal) at the current J.
  auto factor = [&](double mu) {
    const RowMatrix& J = jacobian.matrix();
    Eigen::SparseMatrix<double> normal = J * J.transpose();
    const double scale = normal.diagonal().mean();
    if (!(scale > 0.0) || !std::isfinite(scale)) return false;
    for (Eigen::Index r = 0; r < rows; ++r) normal.coeffRef(r, r) += mu * scale;
    fresh = true;
    return system.compute(std::move(normal));
  };
  Positions current = start;
  // `current` moved by `length` times `step` (free vertices' coordinates),
  // each vertex then put back within `options.limit` of its reference.
  const auto moved = [&](const Eigen::VectorXd& step, double length) {
    Positions trial = current;
    for (Eigen::Index v = 0; v < n; ++v) {
      const int u = free_of[static_cast<size_t>(v)];
      if (u < 0) continue;
      trial.row(v) += length * step.segment<3>(3 * u).transpose();
      trial.row(v) = within_limit(trial.row(v), reference.row(v), options.limit);
    }
    return trial;
  };
  // Faces near 90 degrees from their reference turn over at any step length
  // (human_woman), and faces a step would crease (the crease guard): their
  // corners keep their place instead, ring by ring. False if faces still
  // turn over after kRevertRounds rounds.
  const auto unfold = [&](Positions& trial) {
    return put_back_folded_corners(trial, current, triangles, reference_normals, crease_guard, kRevertRounds);
  };
  // The projection's steps (PolishOptions::pull_steps).
  for (int pull = 0; pull < options.pull_steps; ++pull) {
    if (!factor(kPullDamping)) break;
    Eigen::VectorXd toward(3 * free_count);
    for (Eigen::Index v = 0; v < n; ++v)
      if (const int u = free_of[static_cast<size_t>(v)]; u >= 0)
        toward.segment<3>(3 * u) = (reference.row(v) - current.row(v)).transpose();
    const Eigen::VectorXd step =
        toward - jacobian.matrix().transpose() * system.solve(residual + jacobian.matrix() * toward);
    if (!step.allFinite()) break;
    Positions trial;
    bool kept = false;
    for (double length = 1.0; length >= std::ldexp(1.0, -kHalvings) && !kept; length *= 0.5) {
      trial = moved(step, length);
      kept = unfold(trial);
    }
    if (!kept) break;
    current = std::move(trial);
    defects = angle_defects(current, triangles, region.rows);
    residual = jacobian.evaluate(current, defects);
    ++result.iterations;
  }
  double energy = residual.squaredNorm();
  bool factored = false;
  std::vector<std::pair<double, Eigen::Index>> history;  // (sum K^2, flat rows) after each kept step
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (residual.lpNorm<Eigen::Infinity>() < options.target_defect) break;
    if (least_damping > kSmallestDamping && residual.lpNorm<Eigen::Infinity>() < options.spread_until) {
      least_damping = kSmallestDamping;
      damping = kInitialDamping;
      factored = false;
    }
    progress.report(static_cast<double>(iteration) / options.max_iterations, "polish");
    bool kept = false;
    Positions trial;
    Eigen::VectorXd trial_defects;
    double trial_energy = 0.0;
    while (!kept) {
      if (!factored) {
        factored = factor(damping);
        if (!factored) {
          damping *= kDampingUp;
          if (damping > kLargestDamping) break;
          continue;
        }
      }
      const Eigen::VectorXd step = -(jacobian.matrix().transpose() * system.solve(residual));
      if (!step.allFinite()) {
        factored = false;
        damping *= kDampingUp;
        if (damping > kLargestDamping) break;
        continue;
      }
      double length = 1.0;
      for (int halving = 0; halving <= kHalvings && !kept; ++halving, length *= 0.5) {
        trial = moved(step, length);
        if (!unfold(trial)) continue;
        trial_defects = angle_defects(trial, triangles, region.rows);
        trial_energy = residual_at(trial_defects).squaredNorm();
        kept = trial_energy < energy;
      }
      if (kept) break;
      // The full step and its halvings failed: a stale factor is refreshed
      // first, a fresh one gets more damping.
      if (fresh) damping *= kDampingUp;
      fresh = false;
      factored = false;
      if (damping > kLargestDamping) break;
    }
    if (!kept) break;
    const double decrease = (energy - trial_energy) / energy;
    current = std::move(trial);
    defects = std::move(trial_defects);
    residual = jacobian.evaluate(current, defects);
    energy = trial_energy;
    ++result.iterations;
    if (give_up.active()) {
      result.largest_move =
          std::max(result.largest_move, give_up.rms((current - reference).rowwise().squaredNorm().sum()));
      if (result.largest_move > give_up.bound()) {
        result.gave_up = true;
        break;
      }
    }
    // A step that gains next to nothing at small damping does not mean that
    // no step can: faces that would turn over keep their corners, and the
    // Gauss-Newton step of what is left may be a poor one. The steps of more
    // damping lean toward the gradient and may still descend (human_woman
    // rounded to single precision: its polish stopped at the 8th step; going
    // on, the run ends 55 % flat instead of 53 %, its mean |defect| -3.7 %
    // instead of +1.3 %).
    if (decrease < kStallDecrease) {
      if (damping * kDampingUp > kLargestDamping) break;
      damping = std::max(damping, kInitialDamping) * kDampingUp;
      factored = false;
      fresh = false;
      continue;
    }
    // Stalled: over the last kStallWindow steps sum K^2 fell by less than
    // half and no vertex became flat (|K| < kFlatDefect): the rest is
    // curvature the constraints cannot remove (the corners of a hull).
    const Eigen::Index flat = (residual.array().abs() < kFlatDefect).count();
    history.push_back({energy, flat});
    if (history.size() > kStallWindow) {
      const auto& then = history[history.size() - 1 - kStallWindow];
      if (energy > 0.5 * then.first && flat <= then.second) break;
    }
    if (flat == rows && history.size() > kFinishWindow &&
        energy > (1.0 - kFinishDecrease) * history[history.size() - 1 - kFinishWindow].first)
      break;
    // A factor whose step gained well is kept; else refactor (with less
    // damping when the fresh one did well).
    fresh = false;
    if (decrease < kReuseDecrease) {
      factored = false;
      damping = std::max(damping / kDampingDown, least_damping);
    }
  }
  result.positions = std::move(current);
  result.residual_after = std::sqrt(residual.squaredNorm() / static_cast<double>(rows));
  return result;
}

}  // namespace

PolishResult polish_defects(const Positions& start, const Positions& reference, const Normals& reference_normals,
                            const Triangles& triangles, const std::vector<bool>& constrained,
                            const std::vector<bool>& pinned, const PolishOptions& options, const Progress& progress) {
  const Eigen::Index n = start.rows();
  if (reference.rows() != n || static_cast<Eigen::Index>(constrained.size()) != n ||
      (!pinned.empty() && static_cast<Eigen::Index>(pinned.size()) != n) ||
      reference_normals.rows() != triangles.rows() ||
      (!options.crease_groups.empty() && static_cast<Eigen::Index>(options.crease_groups.size()) != triangles.rows()))
    throw EngineError(Status::internal_error, "polish_defects: sizes disagree");

  const Eigen::VectorXd defects = angle_defects(start, triangles, constrained);
  const Region region = region_of(triangles, constrained, pinned, defects, options.active_defect);

  // The faces a step can change and those that hold a row's corners. Where
  // they are not the whole mesh (a deformed iterate that is flat but for a
  // few vertices), the polish runs on them alone: every trial step measures
  // its faces and defects, which on the whole of a 1M-face mesh cost more
  // than the steps themselves.
  // With the crease guard on, also the faces across an edge from a face that
  // can change, so that the guard sees every angle a step can open: those
  // touching a reachable vertex.
  const std::vector<bool>& reached = options.crease_growth > 0.0 ? region.reachable : region.rows;
  std::vector<Eigen::Index> faces;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    bool local = false;
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<size_t>(triangles(f, c));
      local = local || region.moves[v] || reached[v];
    }
    if (local) faces.push_back(f);
  }
  GiveUp give_up{options, 0.0, static_cast<double>(n)};
  if (static_cast<Eigen::Index>(faces.size()) == triangles.rows())
    return polish_region(start, reference, reference_normals, triangles, region, defects, options, give_up, progress);

  // The submesh of those faces. Its vertices keep their order (and its faces
  // theirs), so every angle sum, the system and its solution are the ones the
  // whole mesh would give, bit for bit.
  std::vector<int> local_of(static_cast<size_t>(n), -1);
  for (Eigen::Index f : faces)
    for (int c = 0; c < 3; ++c) local_of[static_cast<size_t>(triangles(f, c))] = 0;
  std::vector<Eigen::Index> global_of;
  for (Eigen::Index v = 0; v < n; ++v)
    if (local_of[static_cast<size_t>(v)] == 0) {
      local_of[static_cast<size_t>(v)] = static_cast<int>(global_of.size());
      global_of.push_back(v);
    }
  const auto m = static_cast<Eigen::Index>(global_of.size());
  const auto face_count = static_cast<Eigen::Index>(faces.size());
  Positions local_start(m, 3), local_reference(m, 3);
  Eigen::VectorXd local_defects(m);
  Region local_region{std::vector<bool>(static_cast<size_t>(m)), std::vector<bool>(static_cast<size_t>(m)),
                      std::vector<bool>(static_cast<size_t>(m))};
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index v = global_of[static_cast<size_t>(i)];
    local_start.row(i) = start.row(v);
    local_reference.row(i) = reference.row(v);
    local_defects[i] = defects[v];
    local_region.moves[static_cast<size_t>(i)] = region.moves[static_cast<size_t>(v)];
    local_region.reachable[static_cast<size_t>(i)] = region.reachable[static_cast<size_t>(v)];
    local_region.rows[static_cast<size_t>(i)] = region.rows[static_cast<size_t>(v)];
  }
  Triangles local_triangles(face_count, 3);
  Normals local_normals(face_count, 3);
  for (Eigen::Index i = 0; i < face_count; ++i) {
    const Eigen::Index f = faces[static_cast<size_t>(i)];
    for (int c = 0; c < 3; ++c) local_triangles(i, c) = local_of[static_cast<size_t>(triangles(f, c))];
    local_normals.row(i) = reference_normals.row(f);
  }
  PolishOptions local_options = options;
  if (!options.crease_groups.empty()) {
    local_options.crease_groups.resize(static_cast<size_t>(face_count));
    for (Eigen::Index i = 0; i < face_count; ++i)
      local_options.crease_groups[static_cast<size_t>(i)] =
          options.crease_groups[static_cast<size_t>(faces[static_cast<size_t>(i)])];
  }
  // The vertices outside the submesh keep their moves, which count in the RMS.
  if (give_up.active())
    for (Eigen::Index v = 0; v < n; ++v)
      if (local_of[static_cast<size_t>(v)] < 0) give_up.outside2 += (start.row(v) - reference.row(v)).squaredNorm();
  PolishResult result = polish_region(local_start, local_reference, local_normals, local_triangles, local_region,
                                      std::move(local_defects), local_options, give_up, progress);
  Positions positions = start;
  for (Eigen::Index i = 0; i < m; ++i) positions.row(global_of[static_cast<size_t>(i)]) = result.positions.row(i);
  result.positions = std::move(positions);
  return result;
}

}  // namespace developable

#include "deformation/defect_polish.h"

#include "core/measures.h"
#include "core/submesh.h"
#include "deformation/conjugate_gradients.h"
#include "deformation/move_limit.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

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
// The conjugate gradients' limits (DampedSystem, above options.direct_rows):
// a polish starts with kIterativeSteps iterations a solve, truncated
// conjugate gradients being an inexact Newton step that the
// Levenberg-Marquardt test takes or not like any other; where a kept step
// takes off less than kRefineDecrease of sum K^2, or the stall rule would
// stop, kIterativeGrowth times as many, up to kMostIterativeSteps. 100
// iterations throughout (before) reached a relative residual of 1e-2 to 1 on
// a 100k-face noisy cylinder and spent 60 % of the run in them; starting at
// 10, held-out family runs of 10k-40k faces took 37 % less CPU time and
// ended nearer their twins (docs/method.md, "Scans of any size").
constexpr int kIterativeSteps = 10;
constexpr int kIterativeGrowth = 3;
constexpr int kMostIterativeSteps = 90;
constexpr double kRefineDecrease = 0.1;
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
      : triangles_(triangles), row_of_(row_of) {
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
    // Where each constrained corner's three gradients go: the offsets of
    // J(row, 3u) in the row (u the corner's vertex and its two neighbours),
    // in two bytes, kNotFree for a vertex that does not move. Found once,
    // they spare evaluate a search per gradient (a tenth of a polish).
    Eigen::Index longest = 0;
    for (Eigen::Index r = 0; r < rows; ++r) longest = std::max<Eigen::Index>(longest, sizes[r]);
    if (longest >= kNotFree)
      throw EngineError(Status::out_of_memory, "the angle-defect polish: a vertex with " + std::to_string(longest / 3) +
                                                   " moving vertices around it is beyond its tables (at most 21844)");
    offsets_.assign(static_cast<size_t>(9 * triangles.rows()), kNotFree);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int row = row_of[static_cast<size_t>(triangles(f, c))];
        if (row < 0) continue;
        const int* begin = jacobian_.innerIndexPtr() + jacobian_.outerIndexPtr()[row];
        const int* end = jacobian_.innerIndexPtr() + jacobian_.outerIndexPtr()[row + 1];
        for (int k = 0; k < 3; ++k) {
          const int u = free_of[static_cast<size_t>(triangles(f, (c + k) % 3))];
          if (u >= 0)
            offsets_[static_cast<size_t>(9 * f + 3 * c + k)] =
                static_cast<uint16_t>(std::lower_bound(begin, end, 3 * u) - begin);
        }
      }
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
        double* values = jacobian_.valuePtr() + jacobian_.outerIndexPtr()[row];
        const uint16_t* at = &offsets_[static_cast<size_t>(9 * f + 3 * c)];
        add(values, at[0], -(grad_b + grad_d));
        add(values, at[1], grad_b);
        add(values, at[2], grad_d);
      }
    }
    return residual;
  }

 private:
  static constexpr uint16_t kNotFree = std::numeric_limits<uint16_t>::max();

  static void add(double* values, uint16_t offset, const Eigen::Vector3d& gradient) {
    if (offset == kNotFree) return;
    double* value = values + offset;
    value[0] += gradient[0];
    value[1] += gradient[1];
    value[2] += gradient[2];
  }

  const Triangles& triangles_;
  const std::vector<int>& row_of_;
  RowMatrix jacobian_;
  // Per face, per corner (constrained: a row), the offsets in that row of
  // the corner's vertex and of the next two around the face.
  std::vector<uint16_t> offsets_;
};

// J J^T of a DefectJacobian, its pattern found once: entry (i, j) is the sum
// over the free vertices u that the closed stars of rows i and j share, in
// ascending order, of the three products J(i, 3u + c) J(j, 3u + c), c = 0, 1,
// 2. That is the order and the arithmetic of Eigen's sparse product J *
// J.transpose(), so the values are the same bit for bit; assembled from
// precomputed positions, without the product's transposed copies, sorting
// and allocations (a sixth of a 50k-face run went to them). Only the upper
// triangle is summed; the lower is its copy: (j, i) sums the same products
// (x y is y x in floating point) in the same order.
class NormalMatrix {
 public:
  explicit NormalMatrix(const RowMatrix& jacobian) {
    const Eigen::Index rows = jacobian.rows(), columns = jacobian.cols();
    // The rows each free vertex's three columns appear in, ascending, with
    // the position of its first column's value in J.
    std::vector<int> count(static_cast<size_t>(columns / 3) + 1, 0);
    for (Eigen::Index r = 0; r < rows; ++r)
      for (int k = jacobian.outerIndexPtr()[r]; k < jacobian.outerIndexPtr()[r + 1]; k += 3)
        ++count[static_cast<size_t>(jacobian.innerIndexPtr()[k] / 3) + 1];
    for (size_t u = 1; u < count.size(); ++u) count[u] += count[u - 1];
    vertex_start_ = count;
    row_at_.resize(static_cast<size_t>(count.back()));
    value_at_.resize(static_cast<size_t>(count.back()));
    for (Eigen::Index r = 0; r < rows; ++r)
      for (int k = jacobian.outerIndexPtr()[r]; k < jacobian.outerIndexPtr()[r + 1]; k += 3) {
        const auto slot = static_cast<size_t>(count[static_cast<size_t>(jacobian.innerIndexPtr()[k] / 3)]++);
        row_at_[slot] = static_cast<int>(r);
        value_at_[slot] = k;
      }
    // The pattern, column by column straight into the compressed storage
    // (counted, then filled): (i, r) wherever rows i and r share a free
    // vertex, i.e. the rows holding the free vertices of row r's star
    // (`seen` drops repeats). Symmetric, so column r lists row r's
    // neighbours.
    matrix_.resize(rows, rows);
    std::vector<int> seen(static_cast<size_t>(rows), -1);
    const auto each_neighbour = [&](Eigen::Index r, const auto& take) {
      for (int k = jacobian.outerIndexPtr()[r]; k < jacobian.outerIndexPtr()[r + 1]; k += 3) {
        const auto u = static_cast<size_t>(jacobian.innerIndexPtr()[k] / 3);
        for (int a = vertex_start_[u]; a < vertex_start_[u + 1]; ++a) {
          const int i = row_at_[static_cast<size_t>(a)];
          if (seen[static_cast<size_t>(i)] == r) continue;
          seen[static_cast<size_t>(i)] = static_cast<int>(r);
          take(i);
        }
      }
    };
    int* outer = matrix_.outerIndexPtr();
    for (Eigen::Index r = 0; r < rows; ++r) {
      outer[r + 1] = outer[r];
      each_neighbour(r, [&](int) { ++outer[r + 1]; });
    }
    matrix_.resizeNonZeros(outer[rows]);
    std::fill(seen.begin(), seen.end(), -1);
    int* inner = matrix_.innerIndexPtr();
    for (Eigen::Index r = 0; r < rows; ++r) {
      int next = outer[r];
      each_neighbour(r, [&](int i) { inner[next++] = i; });
      std::sort(inner + outer[r], inner + next);
    }
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    // Where each product of a shared vertex goes, in the order of the sums:
    // its offset in the column of the second row, in two bytes (a column
    // holds a row's two rings). A longer column means a vertex in the stars
    // of 65536 rows, whose products alone would take 4.3e9 entries.
    Eigen::Index longest = 0;
    for (Eigen::Index r = 0; r < rows; ++r) longest = std::max<Eigen::Index>(longest, outer[r + 1] - outer[r]);
    if (longest > Eigen::Index{std::numeric_limits<uint16_t>::max()} + 1)
      throw EngineError(Status::out_of_memory, "the angle-defect polish: a vertex with " + std::to_string(longest) +
                                                   " interior vertices around it is beyond its tables (at most 65536)");
    size_t products = 0;
    for (size_t u = 0; u + 1 < vertex_start_.size(); ++u) {
      const auto count = static_cast<size_t>(vertex_start_[u + 1] - vertex_start_[u]);
      products += count * (count + 1) / 2;
    }
    offset_.reserve(products);
    // The rows of a vertex are ascending: b from a on is the upper triangle.
    for (size_t u = 0; u + 1 < vertex_start_.size(); ++u)
      for (int a = vertex_start_[u]; a < vertex_start_[u + 1]; ++a)
        for (int b = a; b < vertex_start_[u + 1]; ++b) {
          const int column = row_at_[static_cast<size_t>(b)];
          offset_.push_back(static_cast<uint16_t>(position(row_at_[static_cast<size_t>(a)], column) - outer[column]));
        }
    diagonal_.resize(static_cast<size_t>(rows));
    for (Eigen::Index r = 0; r < rows; ++r) diagonal_[static_cast<size_t>(r)] = position(r, r);
    below_.resize(static_cast<size_t>(rows));
  }

  // J J^T + mu m I at J's values, m the mean of J J^T's diagonal; false
  // (the values undefined) when m is not a positive number.
  bool assemble(const RowMatrix& jacobian, double mu) {
    double* values = matrix_.valuePtr();
    // -0 + x is x for every x, so each sum starts as the product's first term.
    std::fill(values, values + matrix_.nonZeros(), -0.0);
    const int* outer = matrix_.outerIndexPtr();
    const double* j = jacobian.valuePtr();
    size_t t = 0;
    for (size_t u = 0; u + 1 < vertex_start_.size(); ++u)
      for (int a = vertex_start_[u]; a < vertex_start_[u + 1]; ++a) {
        const double* x = j + value_at_[static_cast<size_t>(a)];
        for (int b = a; b < vertex_start_[u + 1]; ++b, ++t) {
          const double* y = j + value_at_[static_cast<size_t>(b)];
          double& sum = values[outer[row_at_[static_cast<size_t>(b)]] + offset_[t]];
          sum += x[0] * y[0];
          sum += x[1] * y[1];
          sum += x[2] * y[2];
        }
      }
    // The lower triangle, column by column: column i's entries above its
    // diagonal (rows r < i) go to (i, r), which column r lists after its
    // diagonal in ascending i.
    for (size_t r = 0; r < below_.size(); ++r) below_[r] = diagonal_[r] + 1;
    const int* inner = matrix_.innerIndexPtr();
    for (size_t i = 0; i < diagonal_.size(); ++i)
      for (Eigen::Index k = outer[i]; k < diagonal_[i]; ++k)
        values[below_[static_cast<size_t>(inner[k])]++] = values[k];
    const double scale = matrix_.diagonal().mean();
    if (!(scale > 0.0) || !std::isfinite(scale)) return false;
    for (const Eigen::Index d : diagonal_) values[d] += mu * scale;
    return true;
  }

  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

 private:
  Eigen::Index position(Eigen::Index row, Eigen::Index column) const {
    const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[column];
    const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[column + 1];
    return std::lower_bound(begin, end, static_cast<int>(row)) - matrix_.innerIndexPtr();
  }

  std::vector<int> vertex_start_;  // free vertex -> its first entry in row_at_ / value_at_
  std::vector<int> row_at_;        // the rows holding the vertex, ascending
  std::vector<int> value_at_;      // the position of J(row, 3u) in J's values
  std::vector<uint16_t> offset_;   // each upper product's offset in its column (a 1M-row J J^T has about 11M)
  std::vector<Eigen::Index> diagonal_;
  std::vector<Eigen::Index> below_;  // per column, its next entry below the diagonal (assemble)
  Eigen::SparseMatrix<double> matrix_;
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
  // spare: the cores the conjugate gradients' products may take, or null.
  DampedSystem(Eigen::Index direct_rows, SpareCores* spare) : direct_rows_(direct_rows), spare_(spare) {}

  // Factors (or prepares) `matrix`, which must outlive the system and keep
  // its values until the next compute; false on failure.
  bool compute(const Eigen::SparseMatrix<double>& matrix) {
    rows_ = matrix.rows();
    if (rows_ <= direct_rows_) {
      if (!analysed_) {
        direct_.analyzePattern(matrix);
        analysed_ = true;
      }
      direct_.factorize(matrix);
      return direct_.info() == Eigen::Success;
    }
    iterative_.compute(matrix);
    return true;
  }

  // Whether the last compute chose conjugate gradients.
  bool iterative() const { return rows_ > direct_rows_; }

  // Whether a system computed at one iterate is worth solving again at the
  // next: a factorization is dear; J J^T for conjugate gradients is not, and
  // its stale step failed at every length on noisy scans (docs/method.md,
  // "No stale systems for conjugate gradients").
  bool worth_reusing() const { return !iterative(); }

  // More conjugate-gradient iterations from the next solve on; false when
  // the system is factored or already at kMostIterativeSteps.
  bool refine() {
    if (!iterative() || iterative_steps_ >= kMostIterativeSteps) return false;
    iterative_steps_ = std::min(kIterativeGrowth * iterative_steps_, kMostIterativeSteps);
    return true;
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    if (rows_ <= direct_rows_) return direct_.solve(rhs);
    return iterative_.solve(rhs, iterative_steps_, kIterativeTolerance, spare_);
  }

 private:
  Eigen::Index direct_rows_;
  Eigen::Index rows_ = 0;
  int iterative_steps_ = kIterativeSteps;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct_;
  SpareCores* spare_;
  ConjugateGradients iterative_;
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
// `defects` (read at the rows only), giving up past `give_up`'s bound. One
// method per step of an iteration.
class RegionPolish {
 public:
  RegionPolish(const Positions& start, const Positions& reference, const Normals& reference_normals,
               const Triangles& triangles, const Region& region, const PolishOptions& options, const GiveUp& give_up,
               const Progress& progress)
      : reference_(reference),
        reference_normals_(reference_normals),
        triangles_(triangles),
        region_(region),
        options_(options),
        give_up_(give_up),
        progress_(progress),
        n_(start.rows()),
        free_of_(static_cast<size_t>(n_), -1),
        row_of_(static_cast<size_t>(n_), -1),
        system_(options.direct_rows, options.spare_cores),
        current_(start) {
    for (Eigen::Index v = 0; v < n_; ++v)
      if (region.moves[static_cast<size_t>(v)]) free_of_[static_cast<size_t>(v)] = static_cast<int>(free_count_++);
    for (Eigen::Index v = 0; v < n_; ++v)
      if (region.rows[static_cast<size_t>(v)]) row_of_[static_cast<size_t>(v)] = static_cast<int>(rows_++);
    result_.positions = start;
  }

  PolishResult run(Eigen::VectorXd defects);

 private:
  bool factor(double mu);
  Positions moved(const Eigen::VectorXd& step, double length) const;
  bool unfold(Positions& trial) const {
    return put_back_folded_corners(trial, current_, triangles_, reference_normals_, options_.crease_guard,
                                   kRevertRounds, options_.spare_cores);
  }
  Eigen::VectorXd residual_at(const Eigen::VectorXd& defects) const;
  void pull();
  bool descend();
  bool try_lengths(const Eigen::VectorXd& step);
  void take_trial();
  bool gives_up();
  bool stalls();
  bool settled() const;

  const Positions& reference_;
  const Normals& reference_normals_;
  const Triangles& triangles_;
  const Region& region_;
  const PolishOptions& options_;
  const GiveUp& give_up_;
  const Progress& progress_;
  const Eigen::Index n_;
  std::vector<int> free_of_;  // vertex -> its free number, or -1
  std::vector<int> row_of_;   // vertex -> its row, or -1
  Eigen::Index free_count_ = 0;
  Eigen::Index rows_ = 0;
  std::optional<DefectJacobian> jacobian_;
  std::optional<NormalMatrix> normal_;
  DampedSystem system_;
  PolishResult result_;

  // The iterate and its defects (at the rows), K and sum K^2.
  Positions current_;
  Eigen::VectorXd defects_;
  Eigen::VectorXd residual_;
  double energy_ = 0.0;
  // The trial step last kept by try_lengths, its defects and sum K^2.
  Positions trial_;
  Eigen::VectorXd trial_defects_;
  double trial_energy_ = 0.0;
  // J J^T + damping is factored at one iterate and, where worth reusing
  // (DampedSystem), reused while its steps keep lowering sum K^2 well (the
  // vertices move little, so J changes little); it is refactored at the
  // current iterate when a step gains little, and with more damping when
  // even a fresh factor's steps fail. Conjugate gradients given more
  // iterations (refine) still solve the last system once more. The spreading
  // damping holds until every |K| is below spread_until.
  double least_damping_ = 0.0;
  double damping_ = 0.0;
  bool factored_ = false;
  bool fresh_ = false;
  std::vector<std::pair<double, Eigen::Index>> history_;  // (sum K^2, flat rows) after each kept step
};

// Factors J J^T + mu (relative to its mean diagonal) at the current J.
bool RegionPolish::factor(double mu) {
  if (!normal_->assemble(jacobian_->matrix(), mu)) return false;
  fresh_ = true;
  return system_.compute(normal_->matrix());
}

// `current_` moved by `length` times `step` (free vertices' coordinates),
// each vertex then put back within `options.limit` of its reference.
Positions RegionPolish::moved(const Eigen::VectorXd& step, double length) const {
  Positions trial = current_;
  for (Eigen::Index v = 0; v < n_; ++v) {
    const int u = free_of_[static_cast<size_t>(v)];
    if (u < 0) continue;
    trial.row(v) += length * step.segment<3>(3 * u).transpose();
    trial.row(v) = within_limit(trial.row(v), reference_.row(v), options_.limit);
  }
  return trial;
}

Eigen::VectorXd RegionPolish::residual_at(const Eigen::VectorXd& defects) const {
  Eigen::VectorXd r(rows_);
  for (Eigen::Index v = 0; v < n_; ++v)
    if (row_of_[static_cast<size_t>(v)] >= 0) r[row_of_[static_cast<size_t>(v)]] = defects[v];
  return r;
}

// The projection's steps (PolishOptions::pull_steps).
void RegionPolish::pull() {
  const RowMatrix& J = jacobian_->matrix();
  for (int pull = 0; pull < options_.pull_steps; ++pull) {
    if (!factor(kPullDamping)) break;
    Eigen::VectorXd toward(3 * free_count_);
    for (Eigen::Index v = 0; v < n_; ++v)
      if (const int u = free_of_[static_cast<size_t>(v)]; u >= 0)
        toward.segment<3>(3 * u) = (reference_.row(v) - current_.row(v)).transpose();
    const Eigen::VectorXd step = toward - J.transpose() * system_.solve(residual_ + J * toward);
    if (!step.allFinite()) break;
    Positions trial;
    bool kept = false;
    for (double length = 1.0; length >= std::ldexp(1.0, -kHalvings) && !kept; length *= 0.5) {
      trial = moved(step, length);
      kept = unfold(trial);
    }
    if (!kept) break;
    current_ = std::move(trial);
    defects_ = angle_defects(current_, triangles_, region_.rows, options_.spare_cores);
    residual_ = jacobian_->evaluate(current_, defects_);
    ++result_.iterations;
  }
}

// The full step and its halvings: the first that keeps its faces (unfold)
// and lowers sum K^2 becomes the trial; false if none does.
bool RegionPolish::try_lengths(const Eigen::VectorXd& step) {
  double length = 1.0;
  for (int halving = 0; halving <= kHalvings; ++halving, length *= 0.5) {
    trial_ = moved(step, length);
    // Faces near 90 degrees from their reference turn over at any step
    // length (human_woman), and faces a step would crease (the crease
    // guard): their corners keep their place instead, ring by ring.
    if (!unfold(trial_)) continue;
    trial_defects_ = angle_defects(trial_, triangles_, region_.rows, options_.spare_cores);
    trial_energy_ = residual_at(trial_defects_).squaredNorm();
    if (trial_energy_ < energy_) return true;
  }
  return false;
}

// One Levenberg-Marquardt iteration's search for a kept step: the step of
// the current factor (or of a new one), halved; a stale factor that fails is
// renewed, a fresh one that fails gets more damping. False when the damping
// would exceed kLargestDamping.
bool RegionPolish::descend() {
  while (true) {
    if (!factored_) {
      factored_ = factor(damping_);
      if (!factored_) {
        damping_ *= kDampingUp;
        if (damping_ > kLargestDamping) return false;
        continue;
      }
    }
    const Eigen::VectorXd step = -(jacobian_->matrix().transpose() * system_.solve(residual_));
    if (!step.allFinite()) {
      factored_ = false;
      damping_ *= kDampingUp;
      if (damping_ > kLargestDamping) return false;
      continue;
    }
    if (try_lengths(step)) return true;
    if (fresh_) damping_ *= kDampingUp;
    fresh_ = false;
    factored_ = false;
    if (damping_ > kLargestDamping) return false;
  }
}

// The trial becomes the iterate.
void RegionPolish::take_trial() {
  current_ = std::move(trial_);
  defects_ = std::move(trial_defects_);
  residual_ = jacobian_->evaluate(current_, defects_);
  energy_ = trial_energy_;
  ++result_.iterations;
}

// The give-up bounds after a kept step (PolishOptions::give_up_move,
// late_give_up_move).
bool RegionPolish::gives_up() {
  if (!give_up_.active()) return false;
  result_.largest_move =
      std::max(result_.largest_move, give_up_.rms((current_ - reference_).rowwise().squaredNorm().sum()));
  result_.gave_up = result_.largest_move > give_up_.bound();
  return result_.gave_up;
}

// Every row flat and their RMS below options.settled_defect.
bool RegionPolish::settled() const {
  return options_.settled_defect > 0.0 && system_.iterative() && residual_.lpNorm<Eigen::Infinity>() < kFlatDefect &&
         residual_.squaredNorm() < options_.settled_defect * options_.settled_defect * static_cast<double>(rows_);
}

// The stall rules after a kept step:
// over the last kStallWindow steps sum K^2 fell by less than half and no
// vertex became flat (|K| < kFlatDefect; solved by conjugate gradients, at
// most options.stall_flat_share of the rows): the rest is curvature the
// constraints cannot remove (the corners of a hull); or every row is flat
// and the last kFinishWindow steps took off less than kFinishDecrease.
bool RegionPolish::stalls() {
  const Eigen::Index flat = (residual_.array().abs() < kFlatDefect).count();
  history_.push_back({energy_, flat});
  if (history_.size() > kStallWindow) {
    const auto& then = history_[history_.size() - 1 - kStallWindow];
    const auto slow_gain = system_.iterative()
                               ? static_cast<Eigen::Index>(options_.stall_flat_share * static_cast<double>(rows_))
                               : Eigen::Index{0};
    if (energy_ > 0.5 * then.first && flat <= then.second + slow_gain) return true;
  }
  return flat == rows_ && history_.size() > kFinishWindow &&
         energy_ > (1.0 - kFinishDecrease) * history_[history_.size() - 1 - kFinishWindow].first;
}

PolishResult RegionPolish::run(Eigen::VectorXd defects) {
  if (rows_ == 0 || free_count_ == 0) return std::move(result_);
  jacobian_.emplace(triangles_, row_of_, free_of_, rows_, free_count_);
  normal_.emplace(jacobian_->matrix());
  defects_ = std::move(defects);
  residual_ = jacobian_->evaluate(current_, defects_);
  result_.residual_before = std::sqrt(residual_.squaredNorm() / static_cast<double>(rows_));
  result_.residual_after = result_.residual_before;
  least_damping_ = std::max(kSmallestDamping, options_.spread_damping);
  damping_ = std::max(kInitialDamping, least_damping_);
  pull();
  energy_ = residual_.squaredNorm();
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    if (residual_.lpNorm<Eigen::Infinity>() < options_.target_defect || settled()) break;
    if (least_damping_ > kSmallestDamping && residual_.lpNorm<Eigen::Infinity>() < options_.spread_until) {
      least_damping_ = kSmallestDamping;
      damping_ = kInitialDamping;
      factored_ = false;
    }
    progress_.report(static_cast<double>(iteration) / options_.max_iterations, "polish");
    if (!descend()) break;
    const double decrease = (energy_ - trial_energy_) / energy_;
    take_trial();
    if (gives_up()) break;
    // A step that gains next to nothing at small damping does not mean that
    // no step can: faces that would turn over keep their corners, and the
    // Gauss-Newton step of what is left may be a poor one. The steps of more
    // damping lean toward the gradient and may still descend (human_woman
    // rounded to single precision: its polish stopped at the 8th step; going
    // on, the run ends 55 % flat instead of 53 %, its mean |defect| -3.7 %
    // instead of +1.3 %). Truncated conjugate gradients' steps that gain
    // little get more iterations before anything else.
    const bool tiny = decrease < kStallDecrease;
    const bool stalled = !tiny && stalls();
    if ((tiny || stalled || decrease < kRefineDecrease) && system_.refine()) {
      history_.clear();
      continue;
    }
    if (tiny) {
      if (damping_ * kDampingUp > kLargestDamping) break;
      damping_ = std::max(damping_, kInitialDamping) * kDampingUp;
      factored_ = false;
      fresh_ = false;
      continue;
    }
    if (stalled) break;
    // A factor whose step gained well is kept where worth reusing; else
    // refactor (with less damping when the fresh one did well).
    fresh_ = false;
    if (decrease < kReuseDecrease) damping_ = std::max(damping_ / kDampingDown, least_damping_);
    factored_ = decrease >= kReuseDecrease && system_.worth_reusing();
  }
  result_.positions = std::move(current_);
  result_.residual_after = std::sqrt(residual_.squaredNorm() / static_cast<double>(rows_));
  return std::move(result_);
}

PolishResult polish_region(const Positions& start, const Positions& reference, const Normals& reference_normals,
                           const Triangles& triangles, const Region& region, Eigen::VectorXd defects,
                           const PolishOptions& options, const GiveUp& give_up, const Progress& progress) {
  RegionPolish polish(start, reference, reference_normals, triangles, region, options, give_up, progress);
  return polish.run(std::move(defects));
}

}  // namespace

PolishResult polish_defects(const Positions& start, const Positions& reference, const Normals& reference_normals,
                            const Triangles& triangles, const std::vector<bool>& constrained,
                            const std::vector<bool>& pinned, const PolishOptions& options, const Progress& progress) {
  const Eigen::Index n = start.rows();
  if (reference.rows() != n || static_cast<Eigen::Index>(constrained.size()) != n ||
      (!pinned.empty() && static_cast<Eigen::Index>(pinned.size()) != n) ||
      reference_normals.rows() != triangles.rows())
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
  const std::vector<bool>& reached = options.crease_guard.active() ? region.reachable : region.rows;
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
  const Submesh local = submesh(triangles, n, std::move(faces));
  const Eigen::Index m = local.vertex_count();
  Eigen::VectorXd local_defects(m);
  Region local_region{std::vector<bool>(static_cast<size_t>(m)), std::vector<bool>(static_cast<size_t>(m)),
                      std::vector<bool>(static_cast<size_t>(m))};
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto v = static_cast<size_t>(local.vertices[static_cast<size_t>(i)]);
    local_defects[i] = defects[static_cast<Eigen::Index>(v)];
    local_region.moves[static_cast<size_t>(i)] = region.moves[v];
    local_region.reachable[static_cast<size_t>(i)] = region.reachable[v];
    local_region.rows[static_cast<size_t>(i)] = region.rows[v];
  }
  PolishOptions local_options = options;
  local_options.crease_guard = options.crease_guard.restricted(local.faces, triangles.rows());
  // The vertices outside the submesh keep their moves, which count in the RMS.
  if (give_up.active())
    for (Eigen::Index v = 0; v < n; ++v)
      if (local.local_of[static_cast<size_t>(v)] < 0)
        give_up.outside2 += (start.row(v) - reference.row(v)).squaredNorm();
  PolishResult result =
      polish_region(local.vertex_rows(start), local.vertex_rows(reference), local.face_rows(reference_normals),
                    local.triangles, local_region, std::move(local_defects), local_options, give_up, progress);
  Positions positions = start;
  local.scatter(result.positions, positions);
  result.positions = std::move(positions);
  return result;
}

}  // namespace developable

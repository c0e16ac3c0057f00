#include "pipeline.h"

#include "measures.h"
#include "memory_budget.h"
#include "mesh_input.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <optional>
#include <cmath>
#include <cstdio>
#include <string>

namespace developable {
namespace {

using Clock = std::chrono::steady_clock;

// RMS angle (rad) between the normals and one set of ideal curves above which
// automatic segmentation splits the mesh into patches.
constexpr double kAutoSegmentationError = 0.12;

// Stall rule of the iteration (see run_pipeline): stop when the best score
// gained less than this fraction over this many iterations. On one patch 5 %
// over 10 keeps the same best iterate as 1 % (curved cone, noisy patches)
// and stops 15-20 % sooner; a segmented mesh's median |defect| moves in
// steps (see IterateScore) and keeps improving slowly, hence 1 % over 30.
constexpr size_t kStallIterations = 10;
constexpr double kStallImprovement = 0.05;
constexpr size_t kSegmentedStallIterations = 30;
constexpr double kSegmentedStallImprovement = 0.01;

// One-patch refit runs with automatic target smoothing: when the stall rule
// fires while the best iterate still keeps more than this share of the
// input's score, the run goes on from that iterate with the targets smoothed
// (one round). Smoothing from the start would cost clean bands (the noisy
// 1k cylinder -94.6 % -> -74 %); as a second phase it only runs where the
// first stalled early (the run command's demo band -80 % -> -99 %).
// docs/method.md, "Target smoothing on single patches".
constexpr double kSmoothedPhaseShare = 0.1;

// How much farther (RMS over the vertices) than the first phase's best the
// second phase may move the mesh from the input.
constexpr double kSecondPhaseMove = 2.0;

double rms_move(const Positions& a, const Positions& b) {
  return std::sqrt((a - b).rowwise().squaredNorm().mean());
}

// Rounds of averaging along the rulings in the second phase (automatic
// ruling_smoothing).
constexpr int kRulingRounds = 2;

double elapsed_ms(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

// Root-mean-square angle (rad) between the normals and their targets,
// weighted by area: how far the Gauss image is from its ideal curves.
double curve_fit_error(const Normals& normals, const Normals& targets, const Eigen::VectorXd& areas) {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < normals.rows(); ++f) {
    const double angle = std::atan2(normals.row(f).cross(targets.row(f)).norm(),
                                    normals.row(f).dot(targets.row(f)));
    sum += areas[f] * angle * angle;
  }
  return std::sqrt(sum / std::max(areas.sum(), 1e-300));
}

// Vertices where faces of two or more patches meet.
std::vector<bool> patch_border_vertices(const Triangles& triangles, const std::vector<int>& patch_ids,
                                        Eigen::Index vertex_count) {
  std::vector<int> first_patch(static_cast<size_t>(vertex_count), -1);
  std::vector<bool> border(static_cast<size_t>(vertex_count), false);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<size_t>(triangles(f, c));
      const int patch = patch_ids[static_cast<size_t>(f)];
      if (first_patch[v] < 0) first_patch[v] = patch;
      else if (first_patch[v] != patch) border[v] = true;
    }
  }
  return border;
}

// How good an iterate is, lower is better (rad). On one patch: the paper's
// mean |defect| over the interior vertices. On a segmented mesh: the median
// |defect| over the vertices inside the patches. The curvature of a closed
// surface cannot go (Gauss-Bonnet fixes its total), only gather on the
// seams, so there the mean hardly moves while the share of flat vertices
// grows; the median follows that share (below 1e-3 rad once half the
// vertices are flat) and, unlike the share, also rewards progress above the
// threshold.
class IterateScore {
 public:
  IterateScore(std::vector<bool> scored, bool median) : scored_(std::move(scored)), median_(median) {
    for (bool s : scored_) count_ += s ? 1 : 0;
  }

  double operator()(const Eigen::VectorXd& defects) const {
    if (count_ == 0) return 0.0;
    values_.clear();
    double sum = 0.0;
    for (Eigen::Index v = 0; v < defects.size(); ++v) {
      if (!scored_[static_cast<size_t>(v)]) continue;
      sum += std::abs(defects[v]);
      if (median_) values_.push_back(std::abs(defects[v]));
    }
    if (!median_) return sum / static_cast<double>(count_);
    const auto middle = values_.begin() + static_cast<std::ptrdiff_t>(values_.size() / 2);
    std::nth_element(values_.begin(), middle, values_.end());
    return *middle;
  }

 private:
  std::vector<bool> scored_;
  bool median_;
  size_t count_ = 0;
  mutable std::vector<double> values_;  // scratch, reused across iterations
};

// Moves every vertex farther than `limit` from its start back onto the ball
// of that radius around it (E_allow).
void clamp_to_tolerance(Positions& positions, const Positions& start, double limit) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    const Eigen::RowVector3d move = positions.row(v) - start.row(v);
    const double length = move.norm();
    if (length > limit) positions.row(v) = start.row(v) + move * (limit / length);
  }
}

// Share of the interior vertices whose |defect| is under kFlatDefect, 0..1.
double flat_share(const Eigen::VectorXd& defects, const std::vector<bool>& interior) {
  Eigen::Index flat = 0, count = 0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    ++count;
    if (std::abs(defects[v]) < kFlatDefect) ++flat;
  }
  return count > 0 ? static_cast<double>(flat) / static_cast<double>(count) : 0.0;
}

// Faces whose normal is more than 90 degrees from the input's, or collapsed
// (zero normal) where the input's was not: folds a user would see.
Eigen::Index turned_over_faces(const Normals& normals, const Normals& input_normals) {
  Eigen::Index count = 0;
  for (Eigen::Index f = 0; f < normals.rows(); ++f) {
    if (input_normals.row(f).squaredNorm() == 0.0) continue;
    if (normals.row(f).dot(input_normals.row(f)) < 0.0 || normals.row(f).squaredNorm() == 0.0) ++count;
  }
  return count;
}

// 4 sqrt(3) area / (sum of the squared edge lengths): 1 for an equilateral
// triangle, 0.87 for half a square, toward 0 for slivers.
Eigen::VectorXd triangle_quality(const Positions& positions, const Triangles& triangles) {
  Eigen::VectorXd quality(triangles.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::RowVector3d a = positions.row(triangles(f, 0)), b = positions.row(triangles(f, 1)),
                             c = positions.row(triangles(f, 2));
    const double squares = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
    const double area = 0.5 * (b - a).cross(c - a).norm();
    quality[f] = squares > 0.0 ? 4.0 * std::sqrt(3.0) * area / squares : 0.0;
  }
  return quality;
}

// Thin triangles' normals are unreliable (on noisy tangent developables, where
// a fifth of the faces have a corner under 10 degrees, they are 19 degrees off
// on median): their pull toward the target is scaled down with their quality,
// full from half a square's quality 0.87 / 2 upward.
Eigen::VectorXd sliver_trust(const Positions& positions, const Triangles& triangles) {
  return (2.0 * triangle_quality(positions, triangles)).cwiseMin(1.0);
}

// The faces that `turned_over_faces` counts, in ascending order.
std::vector<Eigen::Index> turned_over_list(const Normals& normals, const Normals& input_normals) {
  std::vector<Eigen::Index> faces;
  for (Eigen::Index f = 0; f < normals.rows(); ++f) {
    if (input_normals.row(f).squaredNorm() == 0.0) continue;
    if (normals.row(f).dot(input_normals.row(f)) < 0.0 || normals.row(f).squaredNorm() == 0.0)
      faces.push_back(f);
  }
  return faces;
}

// Per-face damping of the pull toward the targets where steps turned faces
// over: a face whose step would turn it, and every face sharing a vertex
// with it, has its normal weight cut by kFoldDamping; the cut heals by
// kFoldRecovery per step. Multiplies sliver_trust.
constexpr double kFoldDamping = 0.25;
constexpr double kFoldRecovery = 1.5;
// Retries of a folding step with more damping before it is shortened.
constexpr int kFoldRetries = 2;
// Rounds of putting back the corners of faces that still turn over before
// the whole step is dropped.
constexpr int kFoldRevertRounds = 20;

class FoldDamping {
 public:
  FoldDamping(const Triangles& triangles, const VertexFaces& vertex_faces)
      : triangles_(triangles), vertex_faces_(vertex_faces), damping_(Eigen::VectorXd::Ones(triangles.rows())) {}

  const Eigen::VectorXd& factors() const { return damping_; }
  bool any() const { return damped_; }

  void damp_around(const std::vector<Eigen::Index>& turned) {
    for (Eigen::Index f : turned)
      for (int c = 0; c < 3; ++c) {
        const int v = triangles_(f, c);
        for (const int* g = vertex_faces_.begin(v); g != vertex_faces_.end(v); ++g)
          damping_[*g] = std::min(damping_[*g], 1.0) * kFoldDamping;
      }
    damped_ = true;
  }

  void recover() {
    if (!damped_) return;
    damping_ = (damping_ * kFoldRecovery).cwiseMin(1.0);
    damped_ = damping_.minCoeff() < 1.0;
  }

 private:
  const Triangles& triangles_;
  const VertexFaces& vertex_faces_;
  Eigen::VectorXd damping_;
  bool damped_ = false;
};

// Why iterates were not eligible to be returned (see run_pipeline), for the
// message of a run that returns its input.
struct Rejections {
  int folded = 0, defect_grew = 0, flat_share_fell = 0;
  Eigen::Index fewest_turned_over = -1;
};

std::string unchanged_message(const Rejections& r) {
  if (r.folded == 0 && r.defect_grew == 0 && r.flat_share_fell == 0)
    return "Returned the input unchanged: no iterate lowered its curvature. Try a larger "
           "tolerance or more iterations.";
  std::string reasons, advice;
  auto add = [](std::string& list, const std::string& item) { list += (list.empty() ? "" : ", ") + item; };
  if (r.folded > 0) {
    add(reasons, "turning faces over (at least " + std::to_string(r.fewest_turned_over) + ")");
    add(advice, "a smaller tolerance");
  }
  if (r.defect_grew > 0) {
    add(reasons, "raising the mean |defect|");
    add(advice, "segmentation with more patches");
  }
  if (r.flat_share_fell > 0) {
    add(reasons, "losing flat vertices");
    if (r.folded == 0) add(advice, "a larger tolerance");
  }
  return "Returned the input unchanged: every iterate that lowered the curvature did so by " +
         reasons + ". Try " + advice + ".";
}

// Why a mesh has no interior vertex, naming the likely cause when its
// vertices share positions (a polygon soup).
std::string no_interior_vertex_message(const Positions& positions) {
  std::string message =
      "the mesh has no interior vertex: every vertex is on the boundary, so there is no curvature to reduce";
  const Eigen::Index shared = coincident_vertices(positions);
  if (shared > 0)
    message += "; " + std::to_string(shared) + " of " + std::to_string(positions.rows()) +
               " vertices share a position with another vertex (a polygon soup?): weld them first "
               "(Blender: Merge by Distance)";
  return message;
}

}  // namespace

void check_options(const PipelineOptions& o) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw EngineError(Status::invalid_argument, what);
  };
  require(std::isfinite(o.omega) && o.omega > 0.0, "omega must be a positive number");
  require(std::isfinite(o.tolerance), "tolerance must be a finite number (<= 0 for no limit)");
  require(o.max_iterations >= 1 && o.max_iterations <= 100000,
          "max_iterations must be between 1 and 100000");
  require(o.refit_interval >= 1, "refit_interval must be at least 1");
  require(std::isfinite(o.stop_relative_change) && o.stop_relative_change >= 0.0,
          "stop_relative_change must be a non-negative number");
  require(std::isfinite(o.developable_threshold) && o.developable_threshold >= 0.0,
          "developable_threshold must be a non-negative number");
  require(o.segmentation >= -1 && o.segmentation <= 1, "segmentation must be -1, 0 or 1");
  require(std::isfinite(o.segmentation_options.max_fit_error) &&
              o.segmentation_options.max_fit_error >= 0.0,
          "segment_max_error must be a non-negative number");
  require(o.segmentation_options.target_patches >= 0 &&
              o.segmentation_options.target_patches <= 100000,
          "target_patches must be between 0 and 100000");
  require(o.target_smoothing >= -1 && o.target_smoothing <= 100,
          "target_smoothing must be -1 (automatic) or between 0 and 100");
  require(o.curve_options.grid_resolution == 0 ||
              (o.curve_options.grid_resolution >= 16 && o.curve_options.grid_resolution <= 2048),
          "grid_resolution must be 0 (automatic) or between 16 and 2048");
  require(o.ruling_smoothing >= -1 && o.ruling_smoothing <= 100,
          "ruling_smoothing must be -1 (automatic) or between 0 and 100");
  require(o.threads >= 0 && o.threads <= 256, "threads must be 0 (automatic) or between 1 and 256");
}

VertexFaces check_input(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                        const PipelineOptions& options, const Progress& progress) {
  // Options first: a wild grid_resolution is invalid_argument, not out_of_memory.
  check_options(options);
  check_memory_budget(positions.rows(), triangles.rows(), options);
  progress.report(0.0, "checking input");
  VertexFaces table = validate_mesh(positions, triangles);
  if (!pinned.empty() && static_cast<Eigen::Index>(pinned.size()) != positions.rows())
    throw EngineError(Status::invalid_argument, "the pin mask needs one entry per vertex");
  return table;
}

PatchFaces faces_of_patches(const std::vector<int>& patch_ids, int patch_count) {
  PatchFaces faces(static_cast<size_t>(patch_count));
  for (size_t f = 0; f < patch_ids.size(); ++f)
    faces[static_cast<size_t>(patch_ids[f])].push_back(static_cast<Eigen::Index>(f));
  return faces;
}

namespace {

// A patch's faces are 0 .. n-1 when it has all n of them: its rows need no gathering.
bool whole_mesh(const std::vector<Eigen::Index>& members, Eigen::Index faces) {
  return static_cast<Eigen::Index>(members.size()) == faces;
}

Normals gather_rows(const Normals& rows, const std::vector<Eigen::Index>& members) {
  Normals out(static_cast<Eigen::Index>(members.size()), 3);
  for (size_t i = 0; i < members.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows.row(members[i]);
  return out;
}

}  // namespace

std::vector<PatchCurve> fit_patch_curves(const Normals& normals, const Eigen::VectorXd& areas,
                                         const PatchFaces& patches, const IdealCurveOptions& options) {
  std::vector<PatchCurve> curves;
  for (size_t patch = 0; patch < patches.size(); ++patch) {
    const auto& members = patches[patch];
    if (members.empty()) continue;
    std::vector<SphereCurve> fitted;
    if (whole_mesh(members, normals.rows())) {
      fitted = fit_ideal_curves(normals, areas, options);
    } else {
      Eigen::VectorXd patch_areas(static_cast<Eigen::Index>(members.size()));
      for (size_t i = 0; i < members.size(); ++i)
        patch_areas[static_cast<Eigen::Index>(i)] = areas[members[i]];
      fitted = fit_ideal_curves(gather_rows(normals, members), patch_areas, options);
    }
    for (auto& curve : fitted) curves.push_back({static_cast<int>(patch), std::move(curve)});
  }
  return curves;
}

std::vector<CurveSearch> patch_curve_searches(const std::vector<PatchCurve>& curves, int patch_count) {
  std::vector<std::vector<SphereCurve>> by_patch(static_cast<size_t>(patch_count));
  for (const auto& c : curves) by_patch[static_cast<size_t>(c.patch)].push_back(c.curve);
  std::vector<CurveSearch> searches(static_cast<size_t>(patch_count));
  for (size_t patch = 0; patch < by_patch.size(); ++patch)
    if (!by_patch[patch].empty()) searches[patch] = CurveSearch(by_patch[patch]);
  return searches;
}

Normals patch_target_normals(const Normals& normals, const PatchFaces& patches,
                             const std::vector<CurveSearch>& searches,
                             std::vector<std::vector<int>>* hints, int threads) {
  if (hints != nullptr) hints->resize(patches.size());
  Normals targets(normals.rows(), 3);
  for (size_t patch = 0; patch < patches.size(); ++patch) {
    const auto& members = patches[patch];
    if (members.empty()) continue;
    std::vector<int>* const patch_hints = hints != nullptr ? &(*hints)[patch] : nullptr;
    if (whole_mesh(members, normals.rows())) return searches[patch].nearest(normals, patch_hints, threads);
    const Normals patch_targets =
        searches[patch].nearest(gather_rows(normals, members), patch_hints, threads);
    for (size_t i = 0; i < members.size(); ++i)
      targets.row(members[i]) = patch_targets.row(static_cast<Eigen::Index>(i));
  }
  return targets;
}

PipelineResult run_pipeline(const Positions& positions, const Triangles& triangles,
                            const std::vector<bool>& pinned_input, const PipelineOptions& options,
                            const Progress& progress) {
  const auto start_time = Clock::now();
  const VertexFaces connectivity = check_input(positions, triangles, pinned_input, options, progress);
  const Eigen::Index n = positions.rows();

  PipelineResult result;
  PipelineStats& stats = result.stats;
  stats.vertices = n;
  stats.faces = triangles.rows();
  result.interior = interior_vertices(positions, triangles);
  result.defect_before = angle_defects(positions, triangles, result.interior);
  const DefectStats before = defect_stats(result.defect_before, result.interior);
  stats.interior_vertices = before.interior_count;
  if (before.interior_count == 0)
    throw EngineError(Status::no_interior_vertex, no_interior_vertex_message(positions));
  stats.mean_defect_before = before.mean_abs;
  stats.max_defect_before = before.max_abs;
  stats.average_edge_length = average_edge_length(positions, triangles);
  const double ae = stats.average_edge_length;

  std::vector<bool> pinned = pinned_input.empty() ? std::vector<bool>(static_cast<size_t>(n), false)
                                                  : pinned_input;
  if (options.pin_boundary) {
    const std::vector<bool> boundary = boundary_vertices(positions, triangles);
    for (size_t v = 0; v < pinned.size(); ++v) pinned[v] = pinned[v] || boundary[v];
  }

  // Ideal curves of the whole mesh as one patch, then patches if needed.
  progress.report(0.02, "ideal curve");
  const Normals normals_before = face_normals(positions, triangles);
  const Eigen::VectorXd areas_before = face_areas(positions, triangles);
  result.patch_ids.assign(static_cast<size_t>(triangles.rows()), 0);
  int patch_count = 1;
  // The faces of each patch, and the search structure of each patch's
  // current curves (rebuilt with the curves; see run_pipeline's loop).
  PatchFaces patches;
  std::vector<CurveSearch> searches;
  // Each face's last answer on its patch's curves: where its next search
  // starts. Kept across refits too, as the refit curves are sampled alike.
  std::vector<std::vector<int>> hints;
  // Automatic segmentation: only when one set of ideal curves cannot carry
  // the whole Gauss image, judged by the RMS angle between the normals and
  // their single-patch targets (docs/segmentation.md has the measurements).
  bool segment = options.segmentation == 1;
  if (!segment) {
    patches = faces_of_patches(result.patch_ids, 1);
    result.curves = fit_patch_curves(normals_before, areas_before, patches, options.curve_options);
    searches = patch_curve_searches(result.curves, 1);
    result.target_normals = patch_target_normals(normals_before, patches, searches, &hints, options.threads);
    segment = options.segmentation == -1 &&
              curve_fit_error(normals_before, result.target_normals, areas_before) >
                  kAutoSegmentationError;
  }
  if (segment) {
    result.patch_ids =
        segment_mesh(positions, triangles, normals_before, areas_before, connectivity,
                     options.segmentation_options, progress.sub(0.02, 0.05));
    for (int label : result.patch_ids) patch_count = std::max(patch_count, label + 1);
    progress.report(0.05, "ideal curve");
    patches = faces_of_patches(result.patch_ids, patch_count);
    result.curves = fit_patch_curves(normals_before, areas_before, patches, options.curve_options);
    searches = patch_curve_searches(result.curves, patch_count);
    result.target_normals = patch_target_normals(normals_before, patches, searches, &hints, options.threads);
  }
  stats.patches = patch_count;
  // The refit mode treats a segmented mesh as pieces meeting at seams: it is
  // scored inside its patches, where the curvature should leave (see
  // IterateScore), and its targets are smoothed. The paper mode stays the
  // paper's: E^mean and raw targets whatever the patches.
  const bool piecewise = patch_count > 1 && options.mode == Mode::refit;
  std::vector<bool> scored = result.interior;
  const std::vector<bool> border = patch_border_vertices(triangles, result.patch_ids, n);
  if (options.seams == Seams::pinned)
    for (size_t v = 0; v < pinned.size(); ++v) pinned[v] = pinned[v] || border[v];
  if (piecewise) {
    std::vector<bool> inside = scored;
    bool any_inside = false;
    for (size_t v = 0; v < inside.size(); ++v) {
      inside[v] = inside[v] && !border[v];
      any_inside = any_inside || inside[v];
    }
    if (any_inside) scored = std::move(inside);
  }
  const IterateScore score_of(std::move(scored), piecewise);
  int smoothing_rounds =
      options.target_smoothing >= 0 ? options.target_smoothing : (piecewise ? 1 : 0);
  bool smoothed_phase_pending =
      options.target_smoothing < 0 && !piecewise && options.mode == Mode::refit;
  std::optional<TargetSmoother> smoother;
  // Targets averaged along the rulings (TargetSmoother::smooth_along_rulings).
  int ruling_rounds = std::max(options.ruling_smoothing, 0);
  std::optional<TargetSmoother> ruling_smoother;
  if (ruling_rounds > 0) {
    ruling_smoother.emplace(triangles, result.patch_ids, connectivity);
    result.target_normals = ruling_smoother->smooth_along_rulings(result.target_normals, positions, triangles,
                                                                  areas_before, ruling_rounds);
  }
  if (smoothing_rounds > 0) {
    smoother.emplace(triangles, result.patch_ids, connectivity);
    result.target_normals = smoother->smooth(result.target_normals, areas_before, smoothing_rounds);
  }

  result.positions = positions;
  result.defect_after = result.defect_before;
  stats.mean_defect_after = before.mean_abs;
  stats.max_defect_after = before.max_abs;
  stats.flat_share_before = flat_share(result.defect_before, result.interior);
  stats.flat_share_after = stats.flat_share_before;
  stats.result = ResultKind::unchanged;
  if (before.mean_abs <= options.developable_threshold) {
    stats.stop_reason = StopReason::already_developable;
    stats.result_message = "The mesh is already developable: returned unchanged.";
    stats.time_total_ms = elapsed_ms(start_time);
    progress.report(1.0, "done");
    return result;
  }

  // The system (t_D).
  progress.report(0.08, "factorization");
  const auto decompose_start = Clock::now();
  const Mode mode = options.mode;
  const Formulation formulation = mode == Mode::paper ? Formulation::coupled : options.solver;
  Eigen::VectorXd row_weights = options.use_mls_weights
                                    ? mls_row_weights(positions, triangles, pinned, ae)
                                    : Eigen::VectorXd::Ones(triangles.rows());
  NormalGuidedDeformation deformation(triangles, pinned, std::move(row_weights), options.omega,
                                      mode == Mode::paper ? 1.0 : kRefitCentroidWeight,
                                      formulation, result.target_normals);
  stats.time_decompose_ms = elapsed_ms(decompose_start);
  // Thin triangles pull less (sliver_trust); faces a step would turn over
  // are damped (FoldDamping). Both only in the decoupled formulation, whose
  // matrix does not depend on omega.
  const bool can_damp = formulation == Formulation::decoupled;
  const Eigen::VectorXd trust =
      can_damp ? sliver_trust(positions, triangles) : Eigen::VectorXd::Ones(triangles.rows());
  FoldDamping damping(triangles, connectivity);
  if (can_damp && trust.minCoeff() < 1.0) deformation.set_normal_weights(trust);

  // Iterations (t_I).
  const auto iterate_start = Clock::now();
  const double limit = options.tolerance > 0.0 ? options.tolerance * ae : 0.0;
  Positions current = positions;
  double previous_mean = before.mean_abs;
  const double input_score = score_of(result.defect_before);
  double best_score = input_score;
  bool improved = false;
  Rejections rejected;
  // The curves and targets of the step that made the best iterate (the
  // input's fit while nothing beat the input): what the result reports.
  std::vector<PatchCurve> best_curves = result.curves;
  Normals best_targets = result.target_normals;
  std::vector<double> best_history;
  stats.stop_reason = StopReason::iteration_limit;
  // Face normals of `current`, shared by the fold check, the refit, the
  // projection and the step (the input's at the first iteration).
  Normals normals = normals_before;
  bool refit_next = false;
  bool second_phase = false;
  double first_phase_flat = 0.0, first_phase_move = 0.0;  // the second phase refits on the iterate it restarts from
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    progress.report(0.1 + 0.9 * (iteration - 1) / options.max_iterations, "deformation");
    if (mode == Mode::refit && iteration > 1) {
      // Refitting the curves is the costly part; between refits the normals
      // are only projected again onto the curves they have.
      const bool refit = refit_next || (iteration - 1) % options.refit_interval == 0;
      refit_next = false;
      const Eigen::VectorXd areas =
          refit || smoothing_rounds > 0 || ruling_rounds > 0 ? face_areas(current, triangles) : Eigen::VectorXd();
      if (refit) {
        result.curves = fit_patch_curves(normals, areas, patches, options.curve_options);
        searches = patch_curve_searches(result.curves, patch_count);
      }
      result.target_normals = patch_target_normals(normals, patches, searches, &hints, options.threads);
      if (ruling_smoother)
        result.target_normals = ruling_smoother->smooth_along_rulings(result.target_normals, current, triangles,
                                                                      areas, ruling_rounds);
      if (smoother) result.target_normals = smoother->smooth(result.target_normals, areas, smoothing_rounds);
      const auto refactor_start = Clock::now();
      deformation.set_targets(result.target_normals);
      if (formulation == Formulation::coupled) stats.time_decompose_ms += elapsed_ms(refactor_start);
    }
    // The step, guarded against folds: a step that would turn faces over
    // (against the input's normals) is retried with those faces and their
    // neighbours damped, then shortened toward `current`, which has none.
    auto propose = [&]() {
      Positions next = mode == Mode::refit ? deformation.step(current, normals) : deformation.step(current);
      if (limit > 0.0) clamp_to_tolerance(next, positions, limit);
      return next;
    };
    Positions proposal = propose();
    Normals proposal_normals = face_normals(proposal, triangles);
    std::vector<Eigen::Index> turned_now = turned_over_list(proposal_normals, normals_before);
    for (int retry = 0; retry < kFoldRetries && !turned_now.empty() && can_damp; ++retry) {
      damping.damp_around(turned_now);
      deformation.set_normal_weights(trust.cwiseProduct(damping.factors()));
      proposal = propose();
      proposal_normals = face_normals(proposal, triangles);
      turned_now = turned_over_list(proposal_normals, normals_before);
      ++stats.fold_retries;
    }
    // What still turns over goes back: the corners of those faces keep
    // their place of `current`, ring by ring, until nothing turns over.
    for (int round = 0; !turned_now.empty(); ++round) {
      if (round == kFoldRevertRounds) {
        proposal = current;
        proposal_normals = normals;
        break;
      }
      for (Eigen::Index f : turned_now)
        for (int c = 0; c < 3; ++c) proposal.row(triangles(f, c)) = current.row(triangles(f, c));
      proposal_normals = face_normals(proposal, triangles);
      turned_now = turned_over_list(proposal_normals, normals_before);
      ++stats.fold_retries;
    }
    current = std::move(proposal);
    normals = std::move(proposal_normals);
    if (can_damp && damping.any()) {
      damping.recover();
      deformation.set_normal_weights(trust.cwiseProduct(damping.factors()));
    }
    stats.iterations = iteration;

    const Eigen::VectorXd defects = angle_defects(current, triangles, result.interior);
    const DefectStats now = defect_stats(defects, result.interior);
    const double score = score_of(defects);
    // An iterate may be returned only if it is no worse than the input on
    // any figure the user sees: no face turned over, mean |defect| and the
    // flat share no worse. The score ranks the eligible ones.
    const Eigen::Index turned = turned_over_faces(normals, normals_before);
    const double flat = flat_share(defects, result.interior);
    const bool folded = turned > 0;
    const bool defect_grew = now.mean_abs > before.mean_abs;
    const bool flat_share_fell = flat < stats.flat_share_before;
    if (score < input_score) {
      if (folded) {
        ++rejected.folded;
        if (rejected.fewest_turned_over < 0 || turned < rejected.fewest_turned_over)
          rejected.fewest_turned_over = turned;
      }
      if (defect_grew) ++rejected.defect_grew;
      if (flat_share_fell) ++rejected.flat_share_fell;
    }
    // The second phase may not trade the shape for the score: its iterates
    // must keep the first phase's best flat share and move the mesh (RMS)
    // at most kSecondPhaseMove times as far from the input.
    const bool second_phase_worse =
        second_phase && (flat < first_phase_flat ||
                         rms_move(current, positions) > kSecondPhaseMove * first_phase_move);
    if (!folded && !defect_grew && !flat_share_fell && !second_phase_worse && score < best_score) {
      improved = true;
      best_score = score;
      result.positions = current;
      result.defect_after = defects;
      stats.mean_defect_after = now.mean_abs;
      stats.max_defect_after = now.max_abs;
      stats.flat_share_after = flat;
      best_curves = result.curves;
      best_targets = result.target_normals;
    }
    // The paper's criterion, on its own measure. Not on a segmented mesh:
    // there the mean wanders while curvature moves along the seams, and
    // passes through a near-zero change by chance (at 106 of ~300 useful
    // iterations on human_woman); the stall rule below ends those runs.
    const double change = std::abs(now.mean_abs - previous_mean) / std::max(previous_mean, 1e-300);
    previous_mean = now.mean_abs;
    if ((!piecewise && change < options.stop_relative_change) ||
        now.mean_abs <= options.developable_threshold) {
      stats.stop_reason = StopReason::converged;
      break;
    }
    // Noise keeps the paper's criterion from firing long after the result
    // stopped getting better, while the free boundary slowly drifts: stop
    // when the best score stopped gaining (see kStallImprovement).
    best_history.push_back(best_score);
    const size_t window = piecewise ? kSegmentedStallIterations : kStallIterations;
    const double improvement = piecewise ? kSegmentedStallImprovement : kStallImprovement;
    if (best_history.size() > window &&
        best_history[best_history.size() - 1 - window] - best_score <
            improvement * best_history[best_history.size() - 1 - window]) {
      if (smoothed_phase_pending && best_score > kSmoothedPhaseShare * input_score) {
        smoothed_phase_pending = false;
        second_phase = true;
        if (options.ruling_smoothing < 0) {
          // Targets averaged along the rulings, not across them: the
          // isotropic average of target_smoothing flattened wavy shapes
          // (issue 11; docs/families.md).
          ruling_rounds = kRulingRounds;
          ruling_smoother.emplace(triangles, result.patch_ids, connectivity);
        } else {
          smoothing_rounds = 1;
          smoother.emplace(triangles, result.patch_ids, connectivity);
        }
        first_phase_flat = stats.flat_share_after;
        first_phase_move = std::max(rms_move(result.positions, positions), 0.05 * ae);
        // Restart from the best iterate, with curves fitted on it (not on
        // the last iterate, which may have crumpled).
        current = result.positions;
        normals = face_normals(current, triangles);
        refit_next = true;
        best_history.clear();
        continue;
      }
      stats.stop_reason = StopReason::stalled;
      break;
    }
  }
  result.curves = std::move(best_curves);
  result.target_normals = std::move(best_targets);
  if (improved) {
    stats.result = ResultKind::improved;
    if (stats.max_defect_after > stats.max_defect_before) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "Improved, but the largest |defect| grew from %.3g to %.3g rad.",
                    stats.max_defect_before, stats.max_defect_after);
      stats.result_message = text;
    }
  } else {
    stats.result = ResultKind::unchanged;
    stats.result_message = unchanged_message(rejected);
  }
  stats.time_iterate_ms = elapsed_ms(iterate_start);

  // Pinned vertices keep the caller's exact bits whatever the solver did.
  for (Eigen::Index v = 0; v < n; ++v)
    if (pinned[static_cast<size_t>(v)]) result.positions.row(v) = positions.row(v);
  for (Eigen::Index v = 0; v < n; ++v)
    stats.max_vertex_move = std::max(stats.max_vertex_move, (result.positions.row(v) - positions.row(v)).norm());
  stats.change_percent = 100.0 * (stats.mean_defect_after - stats.mean_defect_before) /
                         stats.mean_defect_before;
  stats.time_total_ms = elapsed_ms(start_time);
  progress.report(1.0, "done");
  return result;
}

}  // namespace developable

// The whole pipeline: check, measure, segment, fit the ideal curves, deform.
//
//   validate_mesh (mesh_input.h)         stage 1
//   measures (measures.h)                stage 2
//   segment_mesh (segmentation.h)        curvature-based patches
//   fit_ideal_curves (ideal_curve.h)     stages 3-6, per patch
//   NormalGuidedDeformation              stage 7, iterated
//   polish_defects (defect_polish.h)     stage 8, with least motion's candidates
//                                        (jet_denoise.h: the smoothed input)
#pragma once

#include "core/measures.h"
#include "core/types.h"
#include "deformation/defect_polish.h"
#include "deformation/deformation.h"
#include "ideal_curve/curve_search.h"
#include "ideal_curve/ideal_curve.h"
#include "ideal_curve/target_smoothing.h"
#include "segmentation/segmentation.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace developable {

// The numeric values of Mode, Seams, StopReason and ResultKind are those of
// DEV_MODE_*, DEV_SEAMS_*, DEV_STOP_* and DEV_RESULT_* in the C ABI
// (developable.h); static_asserts in c_api.cpp keep them equal.
enum class Mode {
  refit = 0,  // refit the ideal curve and targets from the deformed mesh every iteration
  paper = 1,  // one set of targets from the input, the coupled system factored once
};

enum class Seams {
  free = 0,    // one global solve; seams between patches move like any vertex
  pinned = 1,  // the paper's: vertices on patch borders are pinned
};

// Weight of the centroid rows (lambda in deformation.h) in the refit mode;
// the paper mode keeps the paper's 1. docs/method.md has the measurements.
inline constexpr double kRefitCentroidWeight = 0.3;

enum class StopReason { already_developable = 0, converged = 1, iteration_limit = 2, stalled = 3 };

// What run_pipeline returned: a better mesh, or the input (with the reason in
// PipelineStats::result_message).
enum class ResultKind { improved = 0, unchanged = 1 };

// Which generator made the returned mesh (developable.h, DEV_ORIGIN_*).
enum class ResultOrigin {
  input = 0,                  // the input, returned unchanged
  deformation = 1,            // an iterate of the normal-guided deformation
  deformation_polish = 2,     // ... finished by the angle-defect polish
  near_flat_polish = 3,       // ... then its nearly flat vertices polished on their own
  input_polish = 4,           // least motion: the polish of the input itself
  smoothed_input_polish = 5,  // ... of the input with its noise smoothed (jet_denoise.h)
  smoothed_step_polish = 6,   // ... of that after one deformation step
  projected_input = 7,        // ... the input projected onto developable meshes from its smoothing
};

// Figures of the result a user sees worse than the input's (developable.h,
// DEV_WORSE_*), or-ed into PipelineStats::worse_figures.
enum WorseFigure : int {
  worse_mean_defect = 1,
  worse_max_defect = 2,
  worse_flat_share = 4,
  worse_ruled_share = 8,
  worse_turned_faces = 16,
};

// Why run_pipeline returned the input (developable.h, DEV_UNCHANGED_*).
enum class UnchangedReason {
  none = 0,
  already_developable = 1,
  developable_piecewise = 2,
  already_flat = 3,
  no_visible_gain = 4,
  no_better_iterate = 5,
  rejected = 6
};

struct PipelineOptions {
  double omega = 5.0;       // weight of the normal rows, > 0
  double tolerance = 10.0;  // E_allow in multiples of AE; <= 0: no limit
  // Largest vertex move as a fraction of the bounding box's diagonal; the
  // smaller of this and `tolerance` applies; <= 0: no limit.
  double max_move = 0.01;
  int max_iterations = 400;  // >= 1; most runs stall or converge long before
  int refit_interval = 5;    // refit mode: refit the curves every this many
                             // iterations, re-project onto them in between
  Mode mode = Mode::refit;
  Formulation solver = Formulation::decoupled;  // refit mode only; paper mode is coupled
  bool pin_boundary = false;
  bool use_mls_weights = true;
  double stop_relative_change = 1e-5;    // 0.001 %, as in the paper
  double developable_threshold = 1e-10;  // mean |defect| (rad) that counts as developable
  int segmentation = -1;                 // -1 automatic, 0 off, 1 on
  SegmentationOptions segmentation_options;
  Seams seams = Seams::free;
  IdealCurveOptions curve_options;
  // Rounds of target normal smoothing inside each patch (target_smoothing.h);
  // -1 automatic: in the refit mode 1 on a segmented mesh; on one patch 0,
  // and if the run stalls with more than 10 % of its score left
  // (kSmoothedPhaseShare in pipeline.cpp) it goes on from the best iterate
  // with the targets averaged along the rulings (ruling_smoothing below).
  int target_smoothing = -1;
  // Rounds of averaging each target along its ruling within its curve
  // (TargetSmoother::smooth_along_rulings) in every iteration; -1 automatic:
  // none, and 2 (instead of target_smoothing's one isotropic round) in the
  // second phase of a stalled one-patch run.
  int ruling_smoothing = -1;
  // Threads of the target search, of a deformation step's rotations, of an
  // iterate's score beside the next targets and of least motion's candidate
  // polishes; 0: the machine's, at most 8. The result is bit-identical
  // whatever the count.
  int threads = 0;
  // The angle-defect polish after the deformation (defect_polish.h): -1
  // automatic (on in the refit mode, off in the paper mode), 0 off, 1 on.
  int polish = -1;
  // Least motion's candidates include the polish of the input with its
  // noise smoothed (jet_denoise.h), and of that after one deformation step
  // (run_pipeline; docs/method.md, "Smoothed input").
  bool polish_smoothed_input = true;
};

// Throws EngineError(invalid_argument) naming the first option out of range.
void check_options(const PipelineOptions& options);

// The checks of a run's input, in this order, each before anything that
// needs it is allocated: the options (check_options), the memory budget for
// the mesh's counts (check_memory_budget in memory_budget.h:
// out_of_memory), progress 0 "checking input", the mesh (validate_mesh in
// mesh_input.h: its own statuses), and the pin mask's size (empty or one
// entry per vertex: invalid_argument). run_pipeline calls it first.
// Returns validate_mesh's table of the faces around each vertex.
VertexFaces check_input(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                        const PipelineOptions& options, const Progress& progress);

struct PatchCurve {
  int patch = 0;
  SphereCurve curve;
};

struct PipelineStats {
  Eigen::Index vertices = 0, faces = 0, interior_vertices = 0, patches = 0;
  int iterations = 0;
  StopReason stop_reason = StopReason::iteration_limit;
  double average_edge_length = 0.0;                          // AE
  double mean_defect_before = 0.0, mean_defect_after = 0.0;  // E^mean, rad
  double max_defect_before = 0.0, max_defect_after = 0.0;
  double change_percent = 0.0;                // dE^mean, %
  double max_vertex_move = 0.0;               // caller's units
  int fold_retries = 0;                       // extra solves and shortenings of steps that would have folded
  int polish_iterations = 0;                  // steps of the angle-defect polish kept (defect_polish.h)
  ResultOrigin origin = ResultOrigin::input;  // which generator made the returned mesh
  double time_decompose_ms = 0.0, time_iterate_ms = 0.0, time_total_ms = 0.0;  // t_D, t_I, t_T
  double time_polish_ms = 0.0;
  ResultKind result = ResultKind::unchanged;
  UnchangedReason unchanged_reason = UnchangedReason::none;  // with result unchanged
  Eigen::Index faces_turned_over = 0;                        // faces of the result > 90 degrees from the input's
  double flat_share_before = 0.0, flat_share_after = 0.0;    // interior share with |defect| < kFlatDefect
  // Flat, flat and ruled, and crumpled shares of the interior (vertex_shares
  // in measures.h); `flat` equals flat_share_*.
  VertexShares shares_before, shares_after;
  int worse_figures = 0;       // WorseFigure flags of the result against the input; 0 when unchanged
  double move_limit = 0.0;     // the largest move a vertex was allowed (caller's units); 0: no limit
  std::string result_message;  // plain words for the user; empty when improved
};

struct PipelineResult {
  Positions positions;            // deformed; pinned vertices bit-identical to the input
  Eigen::VectorXd defect_before;  // per vertex, rad; 0 off the interior
  Eigen::VectorXd defect_after;
  std::vector<bool> interior;      // where the defect is defined
  Normals target_normals;          // per face, of the step that made `positions` (input: its fit)
  std::vector<int> patch_ids;      // per face
  std::vector<PatchCurve> curves;  // ideal curves behind target_normals, on the unit sphere
  PipelineStats stats;
};

// Runs the pipeline on a mesh.
//   positions, triangles: the caller's mesh (checked by validate_mesh).
//   pinned: empty, or one flag per vertex; pinned vertices never move.
// The result keeps the best eligible iterate, every vertex within E_allow of
// its input position. Eligible: no face turned over (normal > 90 degrees from
// the input's, or collapsed), mean |defect| not above the input's, flat share
// not below it. "Best" is the lowest mean |defect| over the interior
// vertices; on a segmented mesh in the refit mode, the median over those
// inside the patches, because there the curvature is meant to gather on the
// seams. When no iterate is eligible and better, the input is returned with
// stats.result = unchanged and stats.result_message saying why. Automatic
// segmentation (options.segmentation -1) that splits an open mesh of up to
// 10000 interior vertices also runs it as one patch and returns that run if
// it is the more developable (flat share and mean |defect| both at least as
// good, one better; docs/segmentation.md, "second opinion").
// Throws EngineError: check_input's statuses, no_interior_vertex (naming the
// vertices that share a position when the mesh looks like an unwelded
// polygon soup), no_free_vertex, cancelled (via progress), numerical_failure.
PipelineResult run_pipeline(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                            const PipelineOptions& options, const Progress& progress);

// Faces of each patch: entry p lists the faces whose patch id is p, ascending.
using PatchFaces = std::vector<std::vector<Eigen::Index>>;

// Groups the faces by patch. patch_ids: per face in 0 .. patch_count-1.
PatchFaces faces_of_patches(const std::vector<int>& patch_ids, int patch_count);

// The ideal curves of every patch (stages 3-6 per patch).
//   normals, areas: per face; patches: from faces_of_patches.
std::vector<PatchCurve> fit_patch_curves(const Normals& normals, const Eigen::VectorXd& areas,
                                         const PatchFaces& patches, const IdealCurveOptions& options);

// The search structure of each patch's curves (empty for a patch without
// faces), built once per fit and queried by patch_target_normals.
std::vector<CurveSearch> patch_curve_searches(const std::vector<PatchCurve>& curves, int patch_count);

// The target normal of every face: its nearest point on its own patch's curves.
//   normals: per face; patches: from faces_of_patches; searches: from
//   patch_curve_searches, one per patch; hints: null, or the caller's scratch
//   kept between calls (CurveSearch::nearest), one entry per patch;
//   threads: as in CurveSearch::nearest.
Normals patch_target_normals(const Normals& normals, const PatchFaces& patches,
                             const std::vector<CurveSearch>& searches, std::vector<std::vector<int>>* hints = nullptr,
                             int threads = 0);

}  // namespace developable

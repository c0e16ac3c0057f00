// What a run returns: the result mesh, its figures before and after, and why
// it is what it is. The numeric values of StopReason, ResultKind,
// ResultOrigin, WorseFigure and UnchangedReason are those of DEV_STOP_*,
// DEV_RESULT_*, DEV_ORIGIN_*, DEV_WORSE_* and DEV_UNCHANGED_* in the C ABI
// (developable.h); static_asserts in c_api.cpp keep them equal.
#pragma once

#include "core/measures.h"
#include "core/types.h"
#include "ideal_curve/ideal_curve.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace developable {

enum class StopReason { already_developable = 0, converged = 1, iteration_limit = 2, stalled = 3 };

// A better mesh, or the input (with the reason in PipelineStats::result_message).
enum class ResultKind { improved = 0, unchanged = 1 };

// Which generator made the returned mesh.
enum class ResultOrigin {
  input = 0,                  // the input, returned unchanged
  deformation = 1,            // an iterate of the normal-guided deformation
  deformation_polish = 2,     // ... finished by the angle-defect polish
  near_flat_polish = 3,       // ... then its nearly flat vertices polished on their own
  input_polish = 4,           // least motion: the polish of the input itself
  smoothed_input_polish = 5,  // ... of the input with its noise smoothed (jet_denoise.h)
  smoothed_step_polish = 6,   // ... of that after one deformation step
  projected_input = 7,        // ... the input projected onto developable meshes from its smoothing
  thinned_pieces = 8,  // the thinned-pieces generator (thinned_pieces.h): ruled pieces from the thinned Gauss image
  ruled_finish = 9,    // a sheet's choice finished flat and ruled (ruled_finish.h)
};

// Figures of an improved result a user sees worse than the input's, or-ed
// into PipelineStats::worse_figures.
enum WorseFigure : int {
  worse_mean_defect = 1,
  worse_max_defect = 2,
  worse_flat_share = 4,
  worse_ruled_share = 8,
  worse_turned_faces = 16,
};

// Why a run returned the input.
enum class UnchangedReason {
  none = 0,
  already_developable = 1,    // mean |defect| under developable_threshold
  developable_piecewise = 2,  // every vertex inside its pieces flat, each piece a plane, cylinder or cone
  already_flat = 3,           // every interior vertex flat, nothing lowered the curvature further
  no_visible_gain = 4,        // the best result made no vertex flat and did not lower the mean |defect|
  no_better_iterate = 5,      // nothing lowered the curvature
  rejected = 6                // everything that lowered it was inadmissible (selection.h)
};

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
  double max_vertex_move = 0.0;               // the largest move made, caller's units
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
  std::string result_message;  // plain words for the user; empty when improved and nothing got worse
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

}  // namespace developable

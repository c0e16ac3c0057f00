// The options of a run and the one place where each automatic choice (-1)
// becomes a concrete value. The numeric values of Mode and Seams are those of
// DEV_MODE_* and DEV_SEAMS_* in the C ABI (developable.h); static_asserts in
// c_api.cpp keep them equal.
#pragma once

#include "core/types.h"
#include "deformation/deformation.h"
#include "ideal_curve/ideal_curve.h"
#include "segmentation/segmentation.h"

namespace developable {

enum class Mode {
  refit = 0,  // refit the ideal curve and targets from the deformed mesh every few iterations
  paper = 1,  // one set of targets from the input, the coupled system factored once
};

enum class Seams {
  free = 0,    // one global solve; seams between patches move like any vertex
  pinned = 1,  // the paper's: vertices on patch borders are pinned
};

// Weight of the centroid rows (lambda in deformation.h) in the refit mode;
// the paper mode keeps the paper's 1. docs/method.md has the measurements.
inline constexpr double kRefitCentroidWeight = 0.3;

struct PipelineOptions {
  double omega = 5.0;       // weight of the normal rows, > 0
  double tolerance = 10.0;  // E_allow in multiples of AE; <= 0: no limit
  // Largest vertex move as a fraction of the bounding box's diagonal; the
  // smaller of this and `tolerance` applies; <= 0: no limit (move_limit).
  double max_move = 0.01;
  int max_iterations = 400;  // >= 1; most runs stall or converge long before
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
  // -1 automatic (smoothing_rounds).
  int target_smoothing = -1;
  // Threads of the target search, of a deformation step's rotations, of an
  // iterate's score beside the next targets and of least motion's candidate
  // polishes; 0: the machine's, at most 8. The result is bit-identical
  // whatever the count.
  int threads = 0;
  // The angle-defect polish after the deformation (defect_polish.h): -1
  // automatic (polish_enabled), 0 off, 1 on.
  int polish = -1;
  // Least motion's candidates include the polish of the input with its
  // noise smoothed (jet_denoise.h), and of that after one deformation step
  // (least_motion.h; docs/method.md, "Smoothed input").
  bool polish_smoothed_input = true;
};

// Throws EngineError(invalid_argument) naming the first option out of range.
void check_options(const PipelineOptions& options);

// Whether the angle-defect polish runs: polish 1, or automatic (-1) in the
// refit mode; the paper mode stays the paper's.
bool polish_enabled(const PipelineOptions& options);

// The linear system's formulation: the paper mode's is always the coupled one.
Formulation formulation_of(const PipelineOptions& options);

// Rounds of target smoothing (target_smoothing.h) on a run that treats the
// mesh as pieces (`piecewise`: segmented, in the refit mode) or as one patch:
// options.target_smoothing, or automatic: 1 on pieces, 0 on one patch.
int smoothing_rounds(const PipelineOptions& options, bool piecewise);

// The largest distance a vertex may move from its input position, in the
// caller's units (0: no limit): the smaller of tolerance * AE and max_move
// times the bounding box's diagonal, each <= 0 meaning no limit of its own.
// The one conversion of the move limit's two units; every stage that clamps
// gets this value.
//   positions: the input; average_edge: its AE (average_edge_length).
double move_limit(const Positions& positions, const PipelineOptions& options, double average_edge);

}  // namespace developable

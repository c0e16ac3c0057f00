// One patch alternative of a run, from its candidates to its result: the
// deformation (paper, stages 6-7) and its polish (stage 8), least motion's
// candidates, each held to the admissibility rule and ordered by select
// (selection.h); the winner, or the input when none was admissible (with
// the reason).
#pragma once

#include "core/types.h"
#include "pipeline/patches.h"
#include "pipeline/run_context.h"
#include "pipeline/run_result.h"
#include "pipeline/thinned_pieces.h"

namespace developable {

// The result of `input` on `patches`: its mesh, figures, curves and stats.
// Patches marked developable (developable_pieces.h) and an input under
// options.developable_threshold come back unchanged at once; an unchanged
// segmented input whose patches are each flat inside and fit their cones is
// "developable piecewise". Throws what the stages throw
// (cancelled, numerical_failure).
PipelineResult run_patch_alternative(const MeasuredInput& input, Patches patches, const Progress& progress);

// The figures the order reads of a result, from its stats (flat,
// flat-and-ruled, mean and largest |defect|). Not the score, the mean inside
// the patches nor the counts admit reads: a result was admitted by its run's
// judge.
Figures result_figures(const PipelineResult& result);

// The plan's chosen result of a sheet finished flat and ruled (ruled_finish.h):
// `result` of `input` (its patches, and its move limit stats.move_limit:
// crease pieces run within the noise) when it is improved, not a whole
// object, polished (polish_enabled: not in the paper's mode unless asked)
// and worth_ruled_finish by its stats; its mesh and stats measured
// again when the finish is kept, else `result` as it was. After the plan has
// chosen, not as one more candidate: the finish takes the noise off the
// rulings, which moves the input more than least motion's candidates, and
// the order would return those (a noisy cylinder patch on an alternating
// grid: 99.0 % flat and ruled returned over 100 %). Throws what the stages
// throw.
PipelineResult finish_plan_result(const MeasuredInput& input, PipelineResult result, const Progress& progress);

// An alternative of the thinned-pieces generator (thinned_pieces.h) from
// the thinned mesh `thinned` (thin_whole) with the pieces of `source` and
// the thinning's `deformation` (thinned_pieces): its
// pieces as the patches, its mesh as the one candidate, held to the
// admissibility rule (selection.h) like any other and not crumpled (its
// promise: developability not bought by zigzags); the input when either
// turns it away. For a whole object (input.object: its judge measures the
// rulings `crumpled` reads).
// Throws what the stages throw.
PipelineResult run_thinned_alternative(const MeasuredInput& input, const Positions& thinned, PieceSource source,
                                       NormalGuidedDeformation deformation, const Progress& progress);

}  // namespace developable

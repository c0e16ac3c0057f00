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

namespace developable {

// The result of `input` on `patches`: its mesh, figures, curves and stats.
// Patches marked developable (developable_pieces.h) and an input under
// options.developable_threshold come back unchanged at once; an unchanged
// segmented input whose patches are each flat inside and fit their cones is
// "developable piecewise". Throws what the stages throw
// (cancelled, numerical_failure).
PipelineResult run_patch_alternative(const MeasuredInput& input, Patches patches, const Progress& progress);

// The alternative of the thinned-pieces generator (thinned_pieces.h): its
// pieces as the patches, its mesh as the one candidate, held to the
// admissibility rule (selection.h) like any other; the input when it is not
// admissible. Throws what the stages throw.
PipelineResult run_thinned_alternative(const MeasuredInput& input, const Progress& progress);

}  // namespace developable

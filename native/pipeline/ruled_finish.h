// Stage 9 on a sheet's choice (beyond the paper; issue 35): the ruled finish.
// A noisy scan of a sheet polished flat keeps noise on its rulings: flat but
// crumpled vertices whose faces' normals are off any great circle, a surface
// a user sees wavy (a cylinder patch with noise at 20 % of the edge length:
// 100 % flat, 88 % flat and ruled). The ruled polish (ruled_polish.h) with
// its fit to the input drives the defects and the ruling spreads to zero in
// rounds of falling fit weight (a continuation: the first round smooths
// near the input, the later ones make it flat and ruled without leaving the
// shape the first found). docs/method.md, "The ruled finish".
#pragma once

#include "pipeline/judge.h"
#include "pipeline/run_context.h"

namespace developable {

// Finishes `choice` of a sheet's run flat and ruled and keeps the result
// when admissible and ruled_finish_kept (ResultOrigin::ruled_finish); else
// leaves `choice` as it is, without a round where it cannot gain
// (ruled_finish_can_gain). `choice.measured` must carry its flat-and-ruled
// share (Judge::measure_rulings). The caller decides whether it is worth it
// (worth_ruled_finish): the plan, on its chosen result of a sheet
// (finish_plan_result in patch_alternative.h). Throws
// EngineError(cancelled) through `progress`.
void finish_ruled(const PatchRun& run, Judge& judge, Choice& choice, const Progress& progress);

}  // namespace developable

// Least motion's candidates (docs/method.md, "Least motion"): the polish of
// the input itself; of the input with its noise smoothed (jet_denoise.h; on
// pieces cut at creases, piece by piece); of that after one deformation step
// toward targets refit on it; and on one patch or such pieces the input
// projected onto developable meshes from its smoothing without the feature
// guard. Where the fitted curves flatten a wavy shape,
// the deformation moves it far more than the noise, a polish of the input
// only about the noise: with the deformation's own result they go to the
// order (select in selection.h), which returns the one that moved the input
// least of those as developable as the most developable.
#pragma once

#include "pipeline/deformation_run.h"
#include "pipeline/judge.h"
#include "pipeline/polish_run.h"
#include "pipeline/run_context.h"

#include <functional>
#include <optional>

namespace developable {

// The smoothings of the input least motion's starts are made of: with the
// feature guard (the smoothed start and its step) and, on sheets (one patch
// or crease pieces), without (the projection's start); on crease pieces
// piece by piece, each piece's border kept. Each within the move limit.
// They depend on the input alone, so a run can make them while its
// deformation's system is factored.
struct InputSmoothings {
  Positions guarded;
  std::optional<Positions> unguarded;  // on sheets only
};
InputSmoothings smooth_input(const PatchRun& run);

// Whether least motion's smoothed starts are made and polished ahead, beside
// other work (the factorisation, the choice's polish): with smoothed starts
// on, on more than one thread. Else they are made and polished where and
// when the one-by-one order needs them.
bool smooths_ahead(const PipelineOptions& options);

// Runs the candidates, the deformation's result (`choice`, after its own
// polish) among them, and makes the order's winner the choice.
//   polish_choice: the choice's own polish (polish_choice), run here beside
//   the polish of the input, which does not depend on it;
//   deformation: the run's, for the smoothed start's step (taken first; the
//   system is released before any polish runs); deformed: whether
//   the deformation improved the input (else only the polish of the input
//   and the projected start compete); smoothings: smooth_input(run) where
//   already made, else empty (made here where a start needs them).
// A candidate that cannot win is not polished, or gives up: one that starts
// (or, at any step, is) farther (RMS) from the input than the winner so far
// (the order's winner grows no farther as candidates join, unless one more
// developable than its anchor changes the anchor). On one thread that is
// two rounds (the choice's and the input's polishes, then the smoothed
// starts'); on more, every polish runs at once, giving up past the choice's
// move, and the order takes from them what the rounds would have (a polish
// that gave up below the rounds' bound is polished again). Each polish is
// the same whatever thread runs it, and the order does not depend on the
// order the candidates come in, so the result does not depend on the thread
// count.
void compete_least_motion(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                          std::optional<InputSmoothings> smoothings,
                          const std::function<void(const Progress&)>& polish_choice, Judge& judge, Choice& choice,
                          const Progress& progress);

}  // namespace developable

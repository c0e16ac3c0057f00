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

#include "core/concurrent_jobs.h"
#include "pipeline/deformation_run.h"
#include "pipeline/judge.h"
#include "pipeline/polish_run.h"
#include "pipeline/run_context.h"

#include <functional>
#include <memory>
#include <optional>

namespace developable {

// Whether least motion runs ahead (LeastMotionAhead): with smoothed starts
// on, on more than one thread. Else its smoothings are made and its starts
// polished where and when the one-by-one order needs them.
bool runs_ahead(const PipelineOptions& options);

// Least motion's work that depends on the input alone, started ahead of the
// deformation on more than one thread (runs_ahead): on a thread of its
// own, the smoothings and the starts made of them, then, on one patch, the
// polishes of the raw input, of the projected start and of the smoothed
// start, with the options polish_plan gives a deformed run;
// compete_least_motion polishes on the run's threads whichever of them that
// thread has not begun. The
// factorisation and the deformation's iterations leave a core idle (a 1M-face
// sheet: 14 s at 1.2 cores), which the polish of the raw input, least
// motion's longest, takes. Destroyed unused (nothing deformed on pieces; a
// cancel), it stops at its next step.
class LeastMotionAhead {
 public:
  struct Work;

  explicit LeastMotionAhead(const PatchRun& run);
  ~LeastMotionAhead();
  LeastMotionAhead(const LeastMotionAhead&) = delete;
  LeastMotionAhead& operator=(const LeastMotionAhead&) = delete;

  Work& work() { return *work_; }
  // Waits for the ahead thread, its reports passed on to `progress`.
  void join(const Progress& progress) { thread_.join(progress, 1.0); }

 private:
  std::unique_ptr<Work> work_;
  BackgroundJob thread_;  // after work_: stopped and joined before it goes
};

// Runs the candidates, the deformation's result (`choice`, after its own
// polish) among them, and makes the order's winner the choice.
//   polish_choice: the choice's own polish (polish_choice), run here beside
//   the polish of the input, which does not depend on it;
//   deformation: the run's, for the smoothed start's step (taken first; the
//   system is released before the run's own polishes); deformed: whether
//   the deformation improved the input (else only the polish of the input
//   and the projected start compete); ahead: the run's LeastMotionAhead,
//   or null on one thread (the smoothings are then made here).
// A candidate that cannot win is not polished, or gives up: one that starts
// (or, at any step, is) farther (RMS) from the input than the winner so far
// (the order's winner grows no farther as candidates join, unless one more
// developable than its anchor changes the anchor). On one thread that is
// two rounds (the choice's and the input's polishes, then the smoothed
// starts'); ahead, every polish runs as soon as its start is made, giving
// up past the choice's move once that is known, and the order takes from
// them what the rounds would have (a polish that gave up below the rounds'
// bound is polished again). Each polish is the same whatever thread runs it
// and whenever it starts, and the order does not depend on the order the
// candidates come in, so the result does not depend on the thread count.
void compete_least_motion(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                          LeastMotionAhead* ahead, const std::function<void(const Progress&)>& polish_choice,
                          Judge& judge, Choice& choice, const Progress& progress);

}  // namespace developable

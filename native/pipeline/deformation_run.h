// The paper's method on one patch alternative (stages 6-7 iterated): the
// targets, one fold-safe step toward them, the best admissible iterate kept
// by score, until the paper's criterion, the stall rule or the iteration
// limit stops it. Its system stays for least motion's smoothed start
// (step_from).
#pragma once

#include "core/types.h"
#include "deformation/anderson_acceleration.h"
#include "deformation/deformation.h"
#include "pipeline/fold_safe_step.h"
#include "pipeline/judge.h"
#include "pipeline/run_context.h"
#include "pipeline/target_field.h"

#include <optional>
#include <vector>

namespace developable {

// The stall rule: a run stops when the best score gained less than
// `improvement` (a fraction) over the last `window` iterations.
class StallRule {
 public:
  StallRule(size_t window, double improvement) : window_(window), improvement_(improvement) {}

  // Records the best score after an iteration; true when the run stalled.
  bool stalled(double best_score);

 private:
  size_t window_;
  double improvement_;
  std::vector<double> history_;
};

// The stall rule of a run: on one patch 5 % over 10 iterations keeps the same
// best iterate as 1 % (curved cone, noisy patches) and stops 15-20 % sooner; a
// segmented mesh's median |defect| moves in steps (IterateScore) and keeps
// improving slowly, hence 1 % over 30.
StallRule stall_rule(bool piecewise);

class DeformationRun {
 public:
  // Builds the system toward `targets`' first targets (t_D in stats),
  // reporting "factorization" at the start of `progress`. The references
  // must outlive this.
  DeformationRun(const PatchRun& run, TargetField targets, PipelineStats& stats, const Progress& progress);

  // The iterations: every admissible iterate that scores below the choice's
  // best score becomes the choice (ResultOrigin::deformation, with the
  // curves and targets of its step). Sets stats' iterations, stop reason,
  // fold retries and t_I. Once: the acceleration's history goes at its end.
  void iterate(Judge& judge, Choice& choice, const Progress& progress);

  // One fold-safe step from `start` toward targets refit on it (least
  // motion's smoothed start); `start` is moved.
  void step_from(Positions& start);

  // Frees the system and the fold-safe step once no step will follow
  // (NormalGuidedDeformation::release); the chosen curves and targets stay.
  // A step after it (iterate, step_from) throws EngineError(internal_error).
  void release() {
    step_.reset();
    deformation_.release();
  }

  // The curves and targets of the step that made the choice (the input's
  // fit while the choice is the input).
  const std::vector<PatchCurve>& chosen_curves() const { return chosen_curves_; }
  const Normals& chosen_targets() const { return chosen_targets_; }

 private:
  // One fold-safe step of `current`; accelerated, its mix replaces it when
  // the mix turns no face over and creases no edge.
  void advance(Positions& current, Normals& normals);

  const PatchRun& run_;
  PipelineStats& stats_;
  TargetField targets_;
  Clock::time_point decompose_start_;
  NormalGuidedDeformation deformation_;
  std::optional<FoldSafeStep> step_;  // empty after release()
  std::optional<AndersonAcceleration> acceleration_;
  std::vector<PatchCurve> chosen_curves_;
  Normals chosen_targets_;
};

}  // namespace developable

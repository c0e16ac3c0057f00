// Stage 8 on a run's choice: the angle defects driven to zero from the best
// iterate (or from the input when the deformation found nothing better),
// then the nearly flat vertices polished on their own while that gains flat
// vertices; and the options least motion's candidates are polished with.
#pragma once

#include "core/measures.h"
#include "deformation/defect_polish.h"
#include "pipeline/judge.h"
#include "pipeline/run_context.h"

namespace developable {

// The run's polishes, decided once the deformation has run.
struct PolishPlan {
  PolishOptions result;      // the choice's polish and its nearly flat rounds
  PolishOptions candidates;  // least motion's polishes of the input's smoothings
  PolishOptions raw_input;   // least motion's polish of the input itself: as candidates, settled deeper
  // Whether least motion's candidates compete: one patch, or pieces whose
  // deformation improved the input; at every size (docs/method.md, "Scans
  // of any size": up to 2026-12-05 they stopped at 25000 scored vertices,
  // and a noisy 100k-face cylinder came back 32 times the noise from its
  // twin, a segmented random-curve tangent developable 55-97 times).
  bool least_motion = false;
};

// The polishes of `run` after a deformation that `deformed` (improved) the
// input or not.
PolishPlan polish_plan(const PatchRun& run, bool deformed);

// Polishes the choice (polish_defects from its positions, within the move
// limit of the input) and keeps the result when admissible and better
// scoring (ResultOrigin::deformation_polish, or input_polish when the choice
// was the input). Then, on an improved choice, the vertices under
// kNearFlatDefect are polished on their own, round after round, each round
// kept while it gains flat vertices and stays as developable as the choice
// before the first (ResultOrigin::near_flat_polish).
void polish_choice(const PatchRun& run, const PolishPlan& plan, Judge& judge, Choice& choice, const Progress& progress);

}  // namespace developable

#include "pipeline/polish_run.h"

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

// The polish works on the vertices whose |defect| is above PolishOptions'
// default (1e-4 rad, a tenth of the flat threshold), and above this share
// of the input's mean |defect| if that is lower: a run can then remove 99.5 %
// of the mean even when the input is nearly flat.
constexpr double kPolishActiveShare = 0.005;
// The second polish works on the scored vertices whose |defect| is below
// this (rad; ten times the flat threshold) and leaves the rest to take up
// the curvature. On human_woman 0.003 / 0.01 / 0.03 / 0.1 gave 68 / 73 / 76
// / 67 % flat; 0.01 also gains on spot and the torus, where 0.03 does not
// (docs/method.md, "Nearly flat vertices").
constexpr double kNearFlatDefect = 0.01;
// The second polish leaves more vertices below kNearFlatDefect than it
// started with; it is run again on them, up to kNearFlatRounds times, while
// a round is kept and gains at least kNearFlatRoundGain of flat share
// (the flat slack: less is within what rounding moves). human_woman 60.8 ->
// 62.9 -> 64.6 -> 64.8 % flat (docs/method.md, "Rounds").
constexpr int kNearFlatRounds = 4;
constexpr double kNearFlatRoundGain = kFlatSlack;
// The polishes of the input (raw or smoothed: least motion's candidates,
// and the polish of a run whose deformation found nothing better) keep at
// least this Levenberg-Marquardt damping until every defect they work on is
// below the flat threshold (PolishOptions::spread_damping): Gauss-Newton's
// minimum-norm steps fix a noisy input's defects by moving a few vertices
// out of the surface, 2-3 times the noise; damped, the steps spread the
// motion. Tuning seeds 0-2, mean log Hausdorff ratio to the twin 0.120 /
// 0.064 / 0.042 / 0.082 at 1e-12 / 1e-4 / 1e-3 / 1e-2 held to the end, 0.055
// with 1e-3 released at the flat threshold (docs/method.md, "Damped polishes
// of the input").
constexpr double kInputPolishDamping = 1e-3;
// Every polish but one solves its damped systems by conjugate gradients
// above this many rows: least motion's candidates and a deformed result's
// (the choice's polish of the raw input, where nothing was deformed, above
// PolishOptions' 20000). From 17k rows conjugate gradients were 1.2-4 times
// faster on all five noisy meshes measured; factored up to 10000 rows the
// held-out runs of 10k-20k faces ended farther from their twins (mean log
// ratio 0.017 -> 0.039). A deformed result's polish factored up to 20000
// rows made 20-40k-face sheets the slowest (a noisy 38k-face cylinder
// 19.7 s, its 100k twin 4 s): solved so, held-out runs of 10k-50k faces took
// 457 CPU s instead of 781, 7 of 94 changed, none farther from its twin
// (docs/method.md, "A deformed result's polish by conjugate gradients").
constexpr int kDirectRows = 3000;
// A polish solved by conjugate gradients stops once its rows are flat and
// their RMS |K| is below this share of the input's mean |defect|
// (PolishOptions::settled_defect): the order's slack on the mean
// (kDefectSlack), so a polish stopped so is as developable as any other
// result (as_developable). A noisy 100k-face cylinder's winning polish: 55
// -> 7 steps, as near its twin (docs/method.md, "Scans of any size").
constexpr double kSettledShare = kDefectSlack;
// A polish of the raw input (least motion's, or the choice's where nothing
// was deformed) settles at half of it. Stopped at the whole slack it moved
// the least (RMS) and won with single vertices 2.3 times as far out as the
// smoothed starts' (held-out seeds 102-103: mean log distance to the twin
// 0.089 -> 0.107); settled deeper it goes on as before and loses to them as
// before.
constexpr double kRawInputSettledShare = 0.5 * kDefectSlack;
// The choice's polishes solved by conjugate gradients (the deformation's
// result and its nearly flat rounds) also stall where ten steps made at most
// this share of their rows flat (PolishOptions::stall_flat_share): ten
// such windows gain less than the order's flat slack (kFlatSlack). A 100k-face
// random-curve tangent developable's nearly flat round took 96 steps (5.4 s
// of its 11 s), the last 60 for 0.07 % of its rows. Least motion's
// candidates keep the strict rule: where they stop decides the order among
// polishes a few per cent apart in motion, and stopped so, 3 of 12 noisy
// 100k-face sheets went to another candidate, one 1.10 -> 1.42 times the
// noise from its twin (docs/method.md, "Scans of any size").
constexpr double kChoiceStallFlatShare = 0.1 * kFlatSlack;

// The vertices of `scored` whose |defect| in `defects` is under
// kNearFlatDefect; empty when none is at or above it (nothing to let go).
std::vector<bool> nearly_flat_vertices(const std::vector<bool>& scored, const Eigen::VectorXd& defects) {
  std::vector<bool> nearly_flat = scored;
  bool some_curved = false;
  for (size_t v = 0; v < nearly_flat.size(); ++v) {
    if (nearly_flat[v] && std::abs(defects[static_cast<Eigen::Index>(v)]) >= kNearFlatDefect) {
      nearly_flat[v] = false;
      some_curved = true;
    }
  }
  return some_curved ? nearly_flat : std::vector<bool>();
}

// The nearly flat rounds: where the polish leaves vertices of |defect| at or
// above kNearFlatDefect (the corners of a closed object), Sigma K^2 is
// theirs and its steps compromise; a second polish drives only the scored
// vertices below it to zero and lets the others take up the curvature
// (human_woman 59 -> 73 % flat, penguin 24 -> 55 %). Every round is held to
// the choice as it was before the first, so the slacks do not add up.
void polish_nearly_flat(const PatchRun& run, const PolishOptions& options, Judge& judge, Choice& choice,
                        const Progress& progress) {
  const MeasuredInput& input = run.input;
  Figures bar = choice.measured.figures;
  bar.max = allowed_largest_defect(bar.max, input.before.max_abs);
  for (int round = 0; round < kNearFlatRounds; ++round) {
    const std::vector<bool> nearly_flat = nearly_flat_vertices(run.scored, choice.measured.defects);
    if (nearly_flat.empty()) break;
    const Progress round_share =
        progress.sub(static_cast<double>(round) / kNearFlatRounds, static_cast<double>(round + 1) / kNearFlatRounds);
    const PolishResult finished = polish_defects(choice.positions, input.positions, input.normals, input.triangles,
                                                 nearly_flat, run.pinned, options, round_share);
    if (finished.iterations == 0) break;
    const Measured now = judge.measure(finished.positions, face_normals(finished.positions, input.triangles));
    if (!judge.admissible(now) || now.figures.flat <= choice.measured.figures.flat ||
        !as_developable(now.figures, bar, judge.input().figures, input.object))
      break;
    const double gain = now.figures.flat - choice.measured.figures.flat;
    choice.keep(finished.positions, now, ResultOrigin::near_flat_polish);
    choice.polish_iterations += finished.iterations;
    if (gain < kNearFlatRoundGain) break;
  }
}

// `options` as a polish of the raw input: damped while it spreads the
// noise's defects (kInputPolishDamping), settled at half the slack
// (kRawInputSettledShare of `input_mean`, the input's mean |defect|).
PolishOptions of_raw_input(PolishOptions options, double input_mean) {
  options.spread_damping = kInputPolishDamping;
  options.settled_defect = kRawInputSettledShare * input_mean;
  return options;
}

}  // namespace

PolishPlan polish_plan(const PatchRun& run, bool deformed) {
  const MeasuredInput& input = run.input;
  const double input_mean = input.before.mean_abs;
  PolishOptions result;
  result.limit = input.limit;
  result.spare_cores = input.spare_cores;
  result.settled_defect = kSettledShare * input_mean;
  // The crease guard goes on with the polish of a deformed result, and on
  // one patch with every polish. The polish of a segmented input (no better
  // iterate) is only judged by it (admit): as a guard of its steps it let
  // wingnut, which came back unchanged, trade 4.9 % more mean |defect| and
  // 0.51 % of its size for flat vertices.
  const bool guarded = deformed || !run.piecewise;
  if (guarded) result.crease_guard = run.crease_guard;
  result.active_defect = std::min(result.active_defect, kPolishActiveShare * input_mean);
  result.stall_flat_share = kChoiceStallFlatShare;
  // Without a better iterate the polish starts from the input: it is the
  // polish of the raw input.
  if (deformed)
    result.direct_rows = kDirectRows;
  else
    result = of_raw_input(std::move(result), input_mean);
  // Least motion's candidates: the smoothings' polishes, damped as the
  // input's, settled at the whole slack; the raw input's as above.
  PolishOptions candidates = result;
  candidates.stall_flat_share = 0.0;  // least motion's candidates keep the strict rule
  candidates.spread_damping = kInputPolishDamping;
  candidates.direct_rows = kDirectRows;
  candidates.settled_defect = kSettledShare * input_mean;
  PolishOptions raw_input = of_raw_input(candidates, input_mean);
  return {std::move(result), std::move(candidates), std::move(raw_input), guarded};
}

void polish_choice(const PatchRun& run, const PolishPlan& plan, Judge& judge, Choice& choice,
                   const Progress& progress) {
  const MeasuredInput& input = run.input;
  const bool deformed = choice.improved;
  const PolishResult polished = polish_defects(choice.positions, input.positions, input.normals, input.triangles,
                                               run.scored, run.pinned, plan.result, progress.sub(0.0, 0.5));
  if (polished.iterations > 0) {
    const Normals polished_normals = face_normals(polished.positions, input.triangles);
    const Measured now = judge.measure(polished.positions, polished_normals);
    // Unguarded (a segmented input's), it is held to the crease guard all the
    // same (admit): split twice as finely as the automatic count, penguin's
    // came back 57 % flat with 133 edges inside its patches grown by up to
    // 60 degrees, mountain's 94 % flat with 704 grown by more than 20.
    if (judge.admissible(now) && now.figures.score < choice.best_score) {
      choice.keep(polished.positions, now, deformed ? ResultOrigin::deformation_polish : ResultOrigin::input_polish);
      choice.polish_iterations = polished.iterations;
    }
  }
  // It finishes an improved result (boat and wingnut, which come back
  // unchanged, would pay seconds for nothing).
  if (choice.improved) polish_nearly_flat(run, plan.result, judge, choice, progress.sub(0.5, 1.0));
}

}  // namespace developable

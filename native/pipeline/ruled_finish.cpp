#include "pipeline/ruled_finish.h"

#include "core/measures.h"
#include "deformation/defect_polish.h"
#include "deformation/ruled_polish.h"

#include <iterator>

namespace developable {
namespace {

// The fit weights of the rounds (RuledPolishOptions::fit_weight). One round
// at the last weight leaves noisy sheets up to 1.7 times the noise from
// their twins (Hausdorff), at the first flat and ruled on 90-94 % of their
// vertices; the rounds: 98-100 % and below the input's distance
// (docs/method.md, "The ruled finish").
constexpr double kFitWeights[] = {0.3, 0.1, 0.05};
// Steps per round: the rounds that made noisy sheets flat and ruled took
// 11-101; capped at 40 no figure of them changed, and a round that crawls
// (a tangent developable on slivers: 192 steps, 2.9 s, then not kept) stops.
constexpr int kRoundSteps = 40;

}  // namespace

void finish_ruled(const PatchRun& run, Judge& judge, Choice& choice, const Progress& progress) {
  const MeasuredInput& input = run.input;
  const Figures start = choice.measured.figures;
  RuledPolishOptions options;
  options.limit = input.limit;
  options.spare_cores = input.spare_cores;
  options.crease_guard = run.crease_guard;
  options.max_iterations = kRoundSteps;
  const Motion choice_motion = motion_of(choice.positions, input.positions);
  const auto within_reach = [&](const Positions& p) {
    return motion_of(p, input.positions).largest <= kFinishReach * choice_motion.largest;
  };
  // Flat and ruled by the polish's own measure: its objective without the fit.
  RuledPolishOptions unfitted = options;
  unfitted.fit_weight = 0.0;
  const auto objective = [&](const Positions& p) {
    return ruled_polish_objective(p, input.positions, input.triangles, run.scored, unfitted);
  };
  if (!ruled_finish_can_gain(objective(choice.positions), objective(input.positions))) return;
  Positions positions = choice.positions;
  int iterations = 0;
  const double rounds = static_cast<double>(std::size(kFitWeights)) + 1.0;  // and the exact polish
  for (size_t k = 0; k < std::size(kFitWeights); ++k) {
    options.fit_weight = kFitWeights[k];
    RuledPolishResult round = polish_ruled(positions, input.positions, input.normals, input.triangles, run.scored,
                                           run.pinned, options, progress.sub(k / rounds, (k + 1) / rounds));
    positions = std::move(round.positions);
    iterations += round.iterations;
    // Past the reach (ruled_finish_kept) it gives up: the later rounds fit
    // the input more loosely.
    if (!within_reach(positions)) return;
  }
  if (iterations == 0) return;
  // The ruled polish stops once a vertex is within a share of the flat
  // threshold; the angle-defect polish then makes the defects still above it
  // exact (a noisy Moebius strip unfolded with 0.15 % strain without it,
  // under 0.1 % with it). Its Gauss-Newton steps may push single vertices
  // out (a noisy cylinder patch: 1.5 times the choice's farthest move): then
  // the ruled polish's result stands.
  PolishOptions exact;
  exact.active_defect = kFlatDefect;
  exact.limit = input.limit;
  exact.spare_cores = input.spare_cores;
  exact.crease_guard = run.crease_guard;
  PolishResult polished = polish_defects(positions, input.positions, input.normals, input.triangles, run.scored,
                                         run.pinned, exact, progress.sub((rounds - 1.0) / rounds, 1.0));
  if (within_reach(polished.positions)) {
    positions = std::move(polished.positions);
    iterations += polished.iterations;
  }
  const Normals normals = face_normals(positions, input.triangles);
  Measured finished = judge.measure(positions, normals);
  judge.measure_rulings(finished, positions, normals);
  if (!judge.admissible(finished) || !ruled_finish_kept(finished.figures, motion_of(positions, input.positions), start,
                                                        choice_motion, judge.input().figures))
    return;
  choice.keep(positions, std::move(finished), ResultOrigin::ruled_finish);
  choice.polish_iterations += iterations;
}

}  // namespace developable

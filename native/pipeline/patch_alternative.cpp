#include "pipeline/patch_alternative.h"

#include "core/concurrent_jobs.h"
#include "pipeline/deformation_run.h"
#include "pipeline/judge.h"
#include "pipeline/least_motion.h"
#include "pipeline/messages.h"
#include "pipeline/polish_run.h"
#include "pipeline/ruled_finish.h"
#include "pipeline/selection.h"
#include "pipeline/target_field.h"
#include "pipeline/thinned_pieces.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace developable {
namespace {

// The judge of a run: the input's figures, scored on the run's vertices (the
// median inside the patches on pieces, the mean elsewhere).
Judge judge_of(const PatchRun& run) {
  const MeasuredInput& input = run.input;
  const IterateScore score(run.scored, run.piecewise);
  Measured measured;
  measured.defects = input.measured.defect_before;
  measured.figures.flat = input.measured.stats.flat_share_before;
  measured.figures.ruled = input.measured.stats.shares_before.ruled;
  measured.figures.mean = input.before.mean_abs;
  measured.figures.max = input.before.max_abs;
  measured.figures.score = score(measured.defects);
  measured.figures.mean_inside = score.mean(measured.defects);
  return Judge(input.triangles, input.measured.interior, input.connectivity, input.normals, score, std::move(measured),
               input.closed, input.object, run.crease_guard);
}

// A mesh made of planes, cylinders and cones, its curvature on the seams
// between them (a gear, a box, a torus of aligned rings), is as developable as
// its pieces get: the generic advice (a larger tolerance) would send the user
// looking for what is not there. Every patch must also fit its cone as it
// stands, not only be flat inside: a patch of a smooth surface too narrow to
// have more than a few inside vertices can be flat there by chance.
bool developable_as_split(const PatchRun& run) {
  const MeasuredInput& input = run.input;
  for (Eigen::Index v = 0; v < input.positions.rows(); ++v)
    if (run.scored[static_cast<size_t>(v)] && !(std::abs(input.measured.defect_before[v]) < kFlatDefect)) return false;
  return patches_fit_cones(run.patch_ids, run.patch_count, input.normals, input.areas);
}

// The result `choice` (or the input, for `reason`) and its stats.
void finish(const PatchRun& run, const Choice& choice, UnchangedReason reason, const Rejections& rejected,
            PipelineResult& result, const Progress& progress) {
  const MeasuredInput& input = run.input;
  PipelineStats& stats = result.stats;
  const bool improved = choice.improved;
  result.positions = choice.positions;
  result.defect_after = choice.measured.defects;
  stats.mean_defect_after = choice.measured.figures.mean;
  stats.max_defect_after = choice.measured.figures.max;
  stats.flat_share_after = choice.measured.figures.flat;
  stats.polish_iterations = choice.polish_iterations;
  stats.origin = choice.origin;
  stats.result = improved ? ResultKind::improved : ResultKind::unchanged;
  stats.unchanged_reason = improved ? UnchangedReason::none : reason;
  // Pinned vertices keep the caller's exact bits whatever the solvers did.
  for (Eigen::Index v = 0; v < input.positions.rows(); ++v)
    if (run.pinned[static_cast<size_t>(v)]) result.positions.row(v) = input.positions.row(v);
  stats.max_vertex_move = improved ? motion_of(result.positions, input.positions).largest : 0.0;
  const Normals result_normals = face_normals(result.positions, input.triangles);
  stats.faces_turned_over = static_cast<Eigen::Index>(turned_over_faces(result_normals, input.normals).size());
  stats.shares_after = improved ? vertex_shares(result.defect_after,
                                                ruling_spreads(result.positions, input.triangles, result_normals,
                                                               input.connectivity, result.interior),
                                                result.interior)
                                : stats.shares_before;
  stats.worse_figures = improved ? worse_figures(stats) : 0;
  stats.change_percent = stats.mean_defect_before > 0.0
                             ? 100.0 * (stats.mean_defect_after - stats.mean_defect_before) / stats.mean_defect_before
                             : 0.0;
  stats.result_message = result_message(stats, rejected);
  stats.time_total_ms = elapsed_ms(input.start_time);
  progress.report(1.0, "done");
}

}  // namespace

PipelineResult run_patch_alternative(const MeasuredInput& input, Patches patches, const Progress& progress) {
  const PatchRun run = patch_run(input, patches);
  PipelineResult result = input.measured;
  PipelineStats& stats = result.stats;
  stats.patches = patches.count;
  result.patch_ids = patches.ids;
  const bool developable = patches.developable;
  TargetField targets(std::move(patches), input.positions, input.triangles, input.areas, input.connectivity,
                      input.options, run.piecewise);
  result.curves = targets.curves();
  result.target_normals = targets.targets();
  Judge judge = judge_of(run);
  Choice choice = Choice::input(input, judge.input());
  if (input.before.mean_abs <= input.options.developable_threshold || developable) {
    stats.stop_reason = StopReason::already_developable;
    finish(run, choice, developable ? UnchangedReason::developable_piecewise : UnchangedReason::already_developable,
           Rejections{}, result, progress);
    return result;
  }

  // Least motion's smoothings and the polishes of its starts that depend on
  // the input alone start on a core of their own while the deformation runs.
  std::optional<LeastMotionAhead> ahead;
  if (polish_enabled(input.options) && runs_ahead(input.options)) ahead.emplace(run);
  DeformationRun deformation(run, std::move(targets), stats, progress.sub(0.08, 0.1));
  deformation.iterate(judge, choice, progress);
  if (polish_enabled(input.options)) {
    const auto polish_start = Clock::now();
    const bool deformed = choice.improved;
    const PolishPlan plan = polish_plan(run, deformed);
    const auto polish = [&](const Progress& share) { polish_choice(run, plan, judge, choice, share); };
    if (plan.least_motion) {
      compete_least_motion(run, plan, deformation, deformed, ahead ? &*ahead : nullptr, polish, judge, choice,
                           progress.sub(0.95, 1.0));
    } else {
      ahead.reset();
      polish(progress.sub(0.95, 1.0));
    }
    stats.time_polish_ms = elapsed_ms(polish_start);
  }
  result.curves = deformation.chosen_curves();
  result.target_normals = deformation.chosen_targets();

  Rejections rejected = judge.rejected();
  if (!choice.improved && run.piecewise) rejected.developable_patches = developable_as_split(run);
  finish(run, choice, unchanged_reason(rejected, stats.flat_share_before), rejected, result, progress);
  return result;
}

PipelineResult run_thinned_alternative(const MeasuredInput& input, const Positions& thinned, PieceSource source,
                                       NormalGuidedDeformation deformation, const Progress& progress) {
  ThinnedPieces candidate = thinned_pieces(input, thinned, source, std::move(deformation), progress.sub(0.0, 0.95));
  Patches patches =
      fitted_patches(std::move(candidate.pieces), candidate.count, input.normals, input.areas, input.options);
  const PatchRun run = patch_run(input, patches);
  PipelineResult result = input.measured;
  result.stats.patches = patches.count;
  result.patch_ids = patches.ids;
  result.curves = patches.curves;
  result.target_normals = patches.targets;
  Judge judge = judge_of(run);
  Choice choice = Choice::input(input, judge.input());
  const Normals normals = face_normals(candidate.positions, input.triangles);
  // An object's judge has measured the rulings (Figures::crumpled).
  const Measured now = judge.measure(candidate.positions, normals);
  if (judge.admissible(now) && now.figures.score < choice.best_score && !crumpled(now.figures, judge.input().figures)) {
    choice.keep(candidate.positions, now, ResultOrigin::thinned_pieces);
    choice.polish_iterations = candidate.polish_iterations;
  }
  const Rejections rejected = judge.rejected();
  finish(run, choice, unchanged_reason(rejected, result.stats.flat_share_before), rejected, result,
         progress.sub(0.95, 1.0));
  return result;
}

Figures result_figures(const PipelineResult& result) {
  Figures f;
  f.flat = result.stats.flat_share_after;
  f.ruled = result.stats.shares_after.ruled;
  f.mean = result.stats.mean_defect_after;
  f.max = result.stats.max_defect_after;
  return f;
}

PipelineResult finish_plan_result(const MeasuredInput& input, PipelineResult result, const Progress& progress) {
  if (input.object || result.stats.result != ResultKind::improved || !polish_enabled(input.options)) return result;
  if (!worth_ruled_finish(result_figures(result))) return result;
  const auto finish_start = Clock::now();
  MeasuredInput within = input;
  within.limit = result.stats.move_limit;
  Patches patches;
  patches.ids = result.patch_ids;
  patches.count = static_cast<int>(result.stats.patches);
  const PatchRun run = patch_run(within, patches);
  Judge judge = judge_of(run);
  const Normals normals = face_normals(result.positions, input.triangles);
  Choice choice = Choice::input(within, judge.input());
  Measured measured = judge.measure(result.positions, normals);
  judge.measure_rulings(measured, result.positions, normals);
  choice.keep(result.positions, std::move(measured), result.stats.origin);
  choice.polish_iterations = result.stats.polish_iterations;
  finish_ruled(run, judge, choice, progress);
  if (choice.origin == ResultOrigin::ruled_finish)
    finish(run, choice, UnchangedReason::none, Rejections{}, result, progress);
  result.stats.time_polish_ms += elapsed_ms(finish_start);
  result.stats.time_total_ms = elapsed_ms(input.start_time);
  return result;
}

}  // namespace developable

#include "pipeline/deformation_run.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "deformation/move_limit.h"

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

constexpr size_t kStallIterations = 10;
constexpr double kStallImprovement = 0.05;
constexpr size_t kSegmentedStallIterations = 30;
constexpr double kSegmentedStallImprovement = 0.01;

// Anderson acceleration of the iterations (anderson_acceleration.h): how
// many earlier iterates it mixes, and from how many scored vertices on. The
// 100k- and 1M-face noisy cones and cylinder: 52-62 iterations -> 19-25, at
// an equal or lower mean |defect|; memory 3 took 24 on the 100k cone. Below
// the limit the run has least motion's candidates, whose choice the
// deformation's result only enters: there acceleration changed 13 of the
// 470 tuning family runs, the mean log Hausdorff ratio to the twin 0.0429 ->
// 0.0443, no better (docs/method.md, "Acceleration").
constexpr int kAccelerationMemory = 5;
constexpr std::ptrdiff_t kAcceleratedVertices = 25000;

// From this many faces on, an iterate is scored on another thread while the
// next targets are found. The noisy cone of 1k faces takes 0.75 ms per
// iteration either way; smaller meshes iterate in tens of microseconds,
// where starting a thread would cost more than it saves.
constexpr Eigen::Index kScoreBesideTargetsFaces = 2000;

NormalGuidedDeformation system_of(const PatchRun& run, const Normals& targets) {
  const MeasuredInput& input = run.input;
  const PipelineOptions& options = input.options;
  Eigen::VectorXd row_weights = options.use_mls_weights ? mls_row_weights(input.positions, input.triangles, run.pinned,
                                                                          input.measured.stats.average_edge_length)
                                                        : Eigen::VectorXd::Ones(input.triangles.rows());
  return NormalGuidedDeformation(input.triangles, run.pinned, std::move(row_weights), options.omega,
                                 options.mode == Mode::paper ? 1.0 : kRefitCentroidWeight, formulation_of(options),
                                 targets, options.threads);
}

}  // namespace

bool StallRule::stalled(double best_score) {
  history_.push_back(best_score);
  if (history_.size() <= window_) return false;
  const double then = history_[history_.size() - 1 - window_];
  // <=: a score of 0 (a box's sides, every vertex inside them exactly flat)
  // cannot gain, and ran to the iteration limit with <.
  return then - best_score <= improvement_ * then;
}

StallRule stall_rule(bool piecewise) {
  return piecewise ? StallRule(kSegmentedStallIterations, kSegmentedStallImprovement)
                   : StallRule(kStallIterations, kStallImprovement);
}

DeformationRun::DeformationRun(const PatchRun& run, TargetField targets, PipelineStats& stats, const Progress& progress)
    : run_(run),
      stats_(stats),
      targets_(std::move(targets)),
      decompose_start_((progress.report(0.0, "factorization"), Clock::now())),
      deformation_(system_of(run, targets_.targets())),
      step_(std::in_place, deformation_, run.input.positions, run.input.normals, run.input.triangles,
            run.input.connectivity, formulation_of(run.input.options) == Formulation::decoupled, run.input.limit,
            run.input.options.mode, run.crease_guard),
      chosen_curves_(targets_.curves()),
      chosen_targets_(targets_.targets()) {
  stats_.time_decompose_ms = elapsed_ms(decompose_start_);
  // Large one-patch meshes' refit iterations are accelerated (a segmented
  // run's curvature moves along its seams, where acceleration was not
  // measured).
  if (run.input.options.mode == Mode::refit && !run.piecewise && run.scored_count > kAcceleratedVertices)
    acceleration_.emplace(kAccelerationMemory);
}

void DeformationRun::advance(Positions& current, Normals& normals) {
  if (!step_) throw EngineError(Status::internal_error, "deformation run: a step after release");
  if (!acceleration_) {
    stats_.fold_retries += step_->advance(current, normals);
    return;
  }
  const Positions previous = current;
  stats_.fold_retries += step_->advance(current, normals);
  std::optional<Positions> mixed = acceleration_->next(previous, current);
  if (!mixed) return;
  clamp_moves(*mixed, run_.input.positions, run_.input.limit);
  Normals mixed_normals = face_normals(*mixed, run_.input.triangles);
  if (mixed->allFinite() && step_->accepts(mixed_normals)) {
    current = std::move(*mixed);
    normals = std::move(mixed_normals);
  } else {
    acceleration_->reset();  // the plain step stands
  }
}

void DeformationRun::iterate(Judge& judge, Choice& choice, const Progress& progress) {
  const MeasuredInput& input = run_.input;
  const PipelineOptions& options = input.options;
  const bool refit = options.mode == Mode::refit;
  const auto iterate_start = Clock::now();
  StallRule stall = stall_rule(run_.piecewise);
  Positions current = input.positions;
  Normals normals = input.normals;  // of `current`: shared by the fold check, the refit and the step
  double previous_mean = input.before.mean_abs;
  // The curves of the targets the deformation pulls toward (the targets
  // themselves are the deformation's).
  std::vector<PatchCurve> step_curves = targets_.curves();
  // Whether `targets_` already holds the next iteration's targets (see below).
  bool targets_ahead = false;
  const int score_threads = input.triangles.rows() >= kScoreBesideTargetsFaces ? options.threads : 1;
  stats_.stop_reason = StopReason::iteration_limit;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    progress.report(0.1 + 0.85 * (iteration - 1) / options.max_iterations, "deformation");
    if (refit && iteration > 1) {
      if (!targets_ahead) targets_.update(current, normals, iteration);
      const auto refactor_start = Clock::now();
      deformation_.set_targets(targets_.targets());
      if (formulation_of(options) == Formulation::coupled) stats_.time_decompose_ms += elapsed_ms(refactor_start);
      step_curves = targets_.curves();
    }
    advance(current, normals);
    stats_.iterations = iteration;
    // The iterate is scored while the next iteration's targets are found
    // (both only read it). A run that stops now has found them for nothing.
    Measured now;
    targets_ahead = refit && iteration < options.max_iterations;
    if (targets_ahead) {
      run_concurrently({[&](const Progress&) { targets_.update(current, normals, iteration + 1); },
                        [&](const Progress&) { now = judge.measure(current, normals, Judge::Detail::iterate); }},
                       score_threads, progress);
    } else {
      now = judge.measure(current, normals, Judge::Detail::iterate);
    }
    if (judge.admissible(now) && now.figures.score < choice.best_score) {
      choice.keep(current, now, ResultOrigin::deformation);
      chosen_curves_ = step_curves;
      chosen_targets_ = deformation_.targets();
    }
    // The paper's criterion, on its own measure. Not on a segmented mesh:
    // there the mean wanders while curvature moves along the seams, and
    // passes through a near-zero change by chance (at 106 of ~300 useful
    // iterations on human_woman); the stall rule ends those runs.
    const double change = std::abs(now.figures.mean - previous_mean) / std::max(previous_mean, 1e-300);
    previous_mean = now.figures.mean;
    if ((!run_.piecewise && change < options.stop_relative_change) ||
        now.figures.mean <= options.developable_threshold) {
      stats_.stop_reason = StopReason::converged;
      break;
    }
    // Noise keeps the paper's criterion from firing long after the result
    // stopped getting better, while the free boundary slowly drifts.
    if (stall.stalled(choice.best_score)) {
      stats_.stop_reason = StopReason::stalled;
      break;
    }
  }
  // The history is of no use after the iterations (step_from takes a plain
  // step): its memory goes before least motion's candidates are polished
  // (five differences of positions and steps, 240 bytes a vertex).
  acceleration_.reset();
  // The iterate kept competes with candidates (select): its rulings too, and
  // on an object they are held to the rule (admit) now that they are read.
  if (choice.origin == ResultOrigin::deformation) {
    judge.complete(choice.measured, choice.positions, face_normals(choice.positions, input.triangles));
    if (!judge.admissible(choice.measured)) choice = Choice::input(input, judge.input());
  }
  stats_.time_iterate_ms = elapsed_ms(iterate_start);
}

void DeformationRun::step_from(Positions& start) {
  if (!step_) throw EngineError(Status::internal_error, "deformation run: a step after release");
  Normals start_normals = face_normals(start, run_.input.triangles);
  targets_.refit(start, start_normals);
  deformation_.set_targets(targets_.targets());
  stats_.fold_retries += step_->advance(start, start_normals);
}

}  // namespace developable

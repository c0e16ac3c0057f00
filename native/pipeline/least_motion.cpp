#include "pipeline/least_motion.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "deformation/jet_denoise.h"
#include "deformation/move_limit.h"

#include <array>
#include <atomic>
#include <future>
#include <limits>
#include <optional>
#include <vector>

namespace developable {
namespace {

// A result that moved the input this many times as far (RMS) as the
// smoothing did has changed the shape, not removed the noise, and its
// normals can be smoother than the shape's own (a wavy cylinder flattened:
// 0.019 rad against the twin's 0.024). The roughness test then takes the
// smoothed input's roughness as its reference where that is higher (seeds
// 0-9 and 100-102: two runs change, 7.6 -> 0.95 and 9.9 -> 1.06 times the
// noise from the twin).
constexpr double kShapeChangeMove = 4.0;
// Where the smoothing moved the input by less than this share of what the
// result moved it (RMS), the raw input stands for both smoothed starts: the
// polishes would compete on a difference of motion that small (a noise-free
// mesh paid two polishes more for it), and a smoothing that moves so little
// can still cut a wave its quadrics do not follow (a wavy generalized cone:
// 2.04 times the noise from its twin from the smoothed start, 1.01 from the
// raw one).
constexpr double kSameStartShare = 0.05;
// The projected candidate: the input projected onto the developable meshes
// (PolishOptions::pull_steps, kProjectionSteps Gauss-Newton steps, then at
// most kProjectionPolishSteps polish steps) from its smoothing without the
// feature guard (JetDenoiseOptions::feature_angle_deg = kProjectionSmoothing).
// A vertex whose angle sum hardly depends on its height (a valence-4 vertex
// of an alternating grid, a sliver's corner) is pushed out by the polishes
// from the noisy input, 1.5-2.5 times the noise; projected from the smooth
// start it stays near the surface. The smoothing may cut a crease, which the
// projection does not restore, so this candidate must also move no vertex
// farther than the choice. Tuning seeds 0-9: mean log Hausdorff ratio to the
// twin 0.043 -> 0.019 (docs/method.md, "Projected smoothed input").
constexpr int kProjectionSteps = 5;
constexpr int kProjectionPolishSteps = 25;
constexpr double kProjectionSmoothing = 90.0;

// A start of a candidate polish.
struct Start {
  Positions positions;  // none for the polish of the input, which starts from the input itself
  ResultOrigin origin;  // of its polish, should it win
  double move;          // RMS from the input
  PolishResult polished;
  bool projected = false;  // polished as the projection of the input (kProjectionSteps)
};

// The candidates so far (each admissible) and the order among them.
class Contest {
 public:
  Contest(const MeasuredInput& input, const Figures& input_figures) : input_(input), input_figures_(input_figures) {}

  // The smoothed input's roughness (rad), the reference where it is higher
  // than the deformation's result's (see kShapeChangeMove).
  void set_shape_roughness(double roughness) { shape_roughness_ = roughness; }

  void add(Choice candidate, bool at_most_as_far) {
    Contestant c;
    c.figures = candidate.measured.figures;
    c.motion = motion_of(candidate.positions, input_.positions);
    c.roughness =
        normal_roughness(face_normals(candidate.positions, input_.triangles), input_.triangles, input_.connectivity);
    c.at_most_as_far = at_most_as_far;
    contestants_.push_back(c);
    candidates_.push_back(std::move(candidate));
  }

  // The winner so far (select), -1 for none.
  // The roughness reference is the first candidate's, the deformation's
  // result (its steps take the noise off the normals, which a polish of the
  // input keeps: the run command's demo band, 1.7 against 2.8 degrees, the
  // input's 3.2), or the smoothed shape's where that is higher.
  int winner() const {
    if (contestants_.empty()) return -1;
    return select(contestants_, input_figures_, std::max(shape_roughness_, contestants_.front().roughness),
                  input_.object);
  }

  // The winner's RMS move: a candidate farther cannot win; infinity without one.
  double bound() const {
    const int w = winner();
    return w < 0 ? std::numeric_limits<double>::infinity() : contestants_[static_cast<size_t>(w)].motion.rms;
  }

  Choice& candidate(int index) { return candidates_[static_cast<size_t>(index)]; }

 private:
  const MeasuredInput& input_;
  const Figures& input_figures_;
  std::vector<Contestant> contestants_;
  std::vector<Choice> candidates_;
  double shape_roughness_ = 0.0;
};

// The groups the smoothed starts are smoothed in (JetDenoiseOptions::
// face_groups): on pieces cut at creases each piece on its own, its borders
// kept; else none (one patch, or a segmented object's patches, whose
// borders are not creases).
std::vector<int> smoothing_groups(const PatchRun& run) {
  return run.piecewise && run.sheets ? run.patch_ids : std::vector<int>{};
}

// The smoothings of the input least motion's starts are made of: with the
// feature guard (the smoothed start and its step) and, on sheets (one patch
// or crease pieces), without (the projection's start); on crease pieces
// piece by piece, each piece's border kept. Each within the move limit.
// They depend on the input alone (LeastMotionAhead makes them beside the
// deformation).
struct InputSmoothings {
  Positions guarded;
  std::optional<Positions> unguarded;  // on sheets only
};

InputSmoothings smooth_input(const PatchRun& run) {
  const MeasuredInput& input = run.input;
  std::vector<double> guards{kJetFeatureAngle};
  if (run.sheets) guards.push_back(kProjectionSmoothing);
  std::vector<Positions> smoothings =
      jet_denoise(input.positions, input.triangles, input.connectivity, run.pinned, guards, smoothing_groups(run));
  InputSmoothings out;
  out.guarded = std::move(smoothings.front());
  clamp_moves(out.guarded, input.positions, input.limit);
  if (run.sheets) {
    out.unguarded = std::move(smoothings.back());
    clamp_moves(*out.unguarded, input.positions, input.limit);
  }
  return out;
}

// The projection's start: the unguarded smoothing, its turned sliver faces
// given back the input's corners.
Positions projection_start(const PatchRun& run, Positions start) {
  const MeasuredInput& input = run.input;
  // As many rounds as it takes: the input folds nothing.
  put_back_folded_corners(start, input.positions, input.triangles, input.normals,
                          CreaseGuard(input.triangles, input.normals, {}, 0.0),
                          static_cast<int>(input.positions.rows()));
  return start;
}

// The smoothed starts: the guarded smoothing and, where the deformation
// improved the input, that smoothing after one of its steps toward targets
// refit on it (`stepped`, where the step moved it); on sheets the
// projection's start. The order then
// decides which of them can win (enter_starts).
struct SmoothedStarts {
  std::vector<Start> starts;
  double smoothing_move = 0.0;  // RMS from the input
  // The guarded smoothing, for its roughness: the first start where one is
  // made of it, else kept here (not copied: 12 MB at 1M faces).
  std::optional<Positions> unstarted_smoothing;
  const Positions& smoothing() const { return unstarted_smoothing ? *unstarted_smoothing : starts.front().positions; }
};

SmoothedStarts smoothed_starts(const PatchRun& run, InputSmoothings smoothings, std::optional<Positions> stepped) {
  const MeasuredInput& input = run.input;
  SmoothedStarts out;
  out.smoothing_move = motion_of(smoothings.guarded, input.positions).rms;
  if (stepped) {
    // A step that left the smoothing as it was (where the fold-safe step's
    // reverts do not end, it takes none) is not polished: it would tie with
    // the smoothed start, which comes first in the order and wins ties.
    const bool moved = *stepped != smoothings.guarded;
    out.starts.push_back({std::move(smoothings.guarded), ResultOrigin::smoothed_input_polish, out.smoothing_move, {}});
    if (moved) {
      const double stepped_move = motion_of(*stepped, input.positions).rms;
      out.starts.push_back({std::move(*stepped), ResultOrigin::smoothed_step_polish, stepped_move, {}});
    }
  } else {
    out.unstarted_smoothing = std::move(smoothings.guarded);
  }
  // The projection, on sheets (one patch, or pieces cut at creases, smoothed
  // each on its own; a segmented object's patch borders are not its
  // creases, and its corners are cut by that smoothing: it won on none of
  // the shared meshes and cost human_woman 0.7 s).
  if (smoothings.unguarded) {
    Positions projected = projection_start(run, std::move(*smoothings.unguarded));
    const double projected_move = motion_of(projected, input.positions).rms;
    out.starts.push_back({std::move(projected), ResultOrigin::projected_input, projected_move, {}, true});
  }
  return out;
}

// Which smoothed starts take part, against the choice (after its polish):
// those where the smoothing moves the input enough against the choice's
// move; and the smoothed shape's roughness as the reference where the
// choice moved far more than the smoothing. Returns the flags, one per
// start.
std::vector<bool> enter_starts(const PatchRun& run, const SmoothedStarts& smoothed, Contest& contest) {
  const MeasuredInput& input = run.input;
  if (contest.bound() > kShapeChangeMove * smoothed.smoothing_move)
    contest.set_shape_roughness(
        normal_roughness(face_normals(smoothed.smoothing(), input.triangles), input.triangles, input.connectivity));
  const double bound = contest.bound();
  const bool same_start = smoothed.smoothing_move < kSameStartShare * bound;
  std::vector<bool> entered;
  for (const Start& start : smoothed.starts)
    entered.push_back(start.projected ? start.move >= kSameStartShare * bound : !same_start);
  return entered;
}

// A start's polish: the projection's steps first where it is the projected
// one.
PolishResult polish_start(const PatchRun& run, const Start& start, PolishOptions options, const Progress& progress) {
  const MeasuredInput& input = run.input;
  if (start.projected) {
    options.pull_steps = kProjectionSteps;
    options.active_defect = 0.0;
    options.max_iterations = kProjectionSteps + kProjectionPolishSteps;
  }
  const Positions& from = start.origin == ResultOrigin::input_polish ? input.positions : start.positions;
  return polish_defects(from, input.positions, input.normals, input.triangles, run.scored, run.pinned, options,
                        progress);
}

}  // namespace

// Least motion's polishes that depend on the input alone, each taken once
// by whichever thread comes to it first (the ahead thread or the run's).
struct LeastMotionAhead::Work {
  // With the options polish_plan gives a deformed run.
  Work(const PatchRun& run, bool polishes_ahead) : run(run), polishes_ahead(polishes_ahead) {
    PolishPlan plan = polish_plan(run, true);
    input_options = std::move(plan.raw_input);
    input_options.late_give_up_move = &deformed_only_move;
    smoothed_options = plan.candidates;
    smoothed_options.late_give_up_move = &deformed_only_move;
    late_options = std::move(plan.candidates);
    late_options.late_give_up_move = &choice_move;
  }

  // The choice's move, once its polish has run: every polish here gives up
  // past it (those dropped at once).
  void set_choice_move(double move) {
    choice_move = move;
    double unknown = kNotKnown;
    deformed_only_move.compare_exchange_strong(unknown, move);
  }

  // Where nothing was deformed the choice's polish is the polish of the
  // input (with the choice's options) and the smoothed start is no
  // candidate: neither polish is begun from here on, and one begun gives up
  // at its next step.
  void drop_deformed_only() {
    taken[raw_input] = true;
    taken[smoothed] = true;
    deformed_only_move = kDropped;
  }

  // The early polishes, in the order they are taken (the longest first).
  enum Polish { raw_input, projected, smoothed, count };

  // Polishes `polish` unless another thread took it (or it is dropped).
  void take(Polish polish, const Progress& progress) {
    if (taken[polish].exchange(true)) return;
    switch (polish) {
      case raw_input:
        input_start.polished = polish_start(run, input_start, input_options, progress);
        break;
      case projected:
        if (projected_start) projected_start->polished = polish_start(run, *projected_start, late_options, progress);
        break;
      case smoothed:
        smoothed_start->polished = polish_start(run, *smoothed_start, smoothed_options, progress);
        break;
      default:
        break;
    }
  }

  // The ahead thread: the smoothings and the starts made of them, then
  // every polish not yet taken.
  void run_ahead(const Progress& progress) {
    try {
      InputSmoothings smoothings = smooth_input(run);
      const MeasuredInput& input = run.input;
      smoothed_start = Start{std::move(smoothings.guarded), ResultOrigin::smoothed_input_polish, 0.0, {}};
      smoothed_start->move = motion_of(smoothed_start->positions, input.positions).rms;
      if (smoothings.unguarded) {
        Positions start = projection_start(run, std::move(*smoothings.unguarded));
        const double move = motion_of(start, input.positions).rms;
        projected_start = Start{std::move(start), ResultOrigin::projected_input, move, {}, true};
      }
    } catch (...) {
      starts_made.set_exception(std::current_exception());
      throw;
    }
    starts_made.set_value();
    if (polishes_ahead)
      for (int k = 0; k < count; ++k) take(static_cast<Polish>(k), progress);
  }

  // The give-up bounds' values that are no move (PolishOptions::late_give_up_move):
  // not known yet, and dropped (every move is past it: the polish gives up at
  // its next step).
  static constexpr double kNotKnown = 0.0;
  static constexpr double kDropped = std::numeric_limits<double>::min();

  const PatchRun& run;
  const bool polishes_ahead;  // else the ahead thread only smooths
  std::atomic<double> choice_move{kNotKnown};
  // The bound of the polishes only a deformed run makes candidates of (the
  // raw input's and the smoothed start's): the choice's move, or kDropped.
  std::atomic<double> deformed_only_move{kNotKnown};
  PolishOptions input_options;     // the raw input's
  PolishOptions smoothed_options;  // the smoothed start's
  PolishOptions late_options;      // the projected and stepped starts'

  Start input_start{{}, ResultOrigin::input_polish, 0.0, {}};
  std::optional<Start> smoothed_start;   // the guarded smoothing
  std::optional<Start> projected_start;  // on sheets
  std::promise<void> starts_made;
  std::shared_future<void> starts_ready = starts_made.get_future().share();
  std::array<std::atomic<bool>, count> taken{};
};

// On one patch least motion runs whatever the deformation does; on pieces
// only where it improved the input (polish_plan), so there the polishes
// wait for it (a whole object's, polished ahead for nothing where its
// deformation failed, cost the 82k-face blob 8 CPU s).
LeastMotionAhead::LeastMotionAhead(const PatchRun& run)
    : work_(std::make_unique<Work>(run, !run.piecewise)),
      thread_([work = work_.get()](const Progress& progress) { work->run_ahead(progress); }, run.input.spare_cores) {}

LeastMotionAhead::~LeastMotionAhead() = default;

namespace {

// The candidates, their polishes run: the choice, the polish of the input
// (where `input` is not null) and the smoothed starts; then the order's
// winner is the choice. Polished against the choice's move
// (PolishOptions::late_give_up_move), a start's polish is the one the
// one-by-one rounds would have given it, or went past their bound and loses
// as it would have, unless that bound is the larger and it gave up between
// them (where the input's polish, more developable than the choice, moved
// farther): that one is polished again here.
void judge_candidates(const PatchRun& run, const PolishPlan& plan, Judge& judge, Choice& choice, const Start* input,
                      std::optional<SmoothedStarts> starts, bool polished_ahead, const Progress& progress) {
  const MeasuredInput& input_mesh = run.input;
  Contest contest(input_mesh, judge.input().figures);
  if (choice.improved) contest.add(choice, false);
  // A polish that went past the bound it was given, or as far as the winner
  // so far (PolishResult::largest_move), cannot win; nor a start as far.
  const auto judge_candidate = [&](const Start& start, double given_bound) {
    const PolishResult& polished = start.polished;
    if (polished.iterations == 0 || (!start.projected && start.move >= contest.bound()) ||
        polished.largest_move > given_bound || polished.largest_move > contest.bound())
      return;
    const Measured now = judge.measure(polished.positions, face_normals(polished.positions, input_mesh.triangles));
    if (!judge.admissible(now)) return;
    Choice candidate = choice;
    candidate.keep(polished.positions, now, start.origin);
    candidate.polish_iterations = polished.iterations;
    contest.add(std::move(candidate), start.projected);
  };
  // Which smoothed starts take part is decided against the choice alone;
  // the polish of the input then sets the bound they must stay within.
  // Nothing to compete with when even the polish of the input found nothing
  // better.
  if (!choice.improved) starts.reset();
  std::vector<bool> entered;
  if (starts) entered = enter_starts(run, *starts, contest);
  if (input) judge_candidate(*input, std::numeric_limits<double>::infinity());
  if (starts) {
    // The smoothed starts, polished beside each other against the winner so
    // far: one already farther is not polished (the benchmark's noise-free
    // wavy cone spent 300 ms polishing two that lost so), and a polish gives
    // up once it is farther.
    PolishOptions bound_options = plan.candidates;
    bound_options.give_up_move = contest.bound();
    std::vector<Job> polishes;
    for (size_t k = 0; k < starts->starts.size(); ++k) {
      Start& start = starts->starts[k];
      if (!entered[k] || (!start.projected && start.move >= bound_options.give_up_move)) {
        start.polished = PolishResult{};
        continue;
      }
      if (polished_ahead && !(start.polished.gave_up && start.polished.largest_move <= bound_options.give_up_move))
        continue;
      polishes.push_back(
          [&](const Progress& share) { start.polished = polish_start(run, start, bound_options, share); });
    }
    run_concurrently(polishes, input_mesh.options.threads, progress, input_mesh.spare_cores);
    for (const Start& start : starts->starts) judge_candidate(start, bound_options.give_up_move);
  }
  const int winner = contest.winner();
  if (winner >= 0) choice = std::move(contest.candidate(winner));
}

// One thread: the choice's and the input's polishes, then the smoothed
// starts' against the winner so far.
void compete_in_rounds(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                       const std::function<void(const Progress&)>& polish_choice, Judge& judge, Choice& choice,
                       const Progress& progress) {
  const MeasuredInput& input = run.input;
  const bool smoothed_candidates = input.options.polish_smoothed_input;
  std::optional<InputSmoothings> smoothings;
  // A deformed result's smoothed start takes its step first, so that the
  // deformation's system goes before any polish runs.
  std::optional<Positions> stepped;
  if (smoothed_candidates && deformed) {
    smoothings = smooth_input(run);
    stepped = smoothings->guarded;
    deformation.step_from(*stepped);
  }
  deformation.release();
  // The polish of the input gives up past the choice's move once the
  // choice's polishes have set it (PolishOptions::late_give_up_move); where
  // nothing was deformed the choice's polish is the polish of the input.
  std::atomic<double> choice_move{0.0};
  PolishOptions input_options = plan.raw_input;
  input_options.late_give_up_move = &choice_move;
  Start input_start{{}, ResultOrigin::input_polish, 0.0, {}};
  std::vector<Job> first{[&](const Progress& share) {
    polish_choice(share);
    choice_move = motion_of(choice.positions, input.positions).rms;
  }};
  if (deformed)
    first.push_back(
        [&](const Progress& share) { input_start.polished = polish_start(run, input_start, input_options, share); });
  run_concurrently(first, input.options.threads, progress.sub(0.0, 0.6), input.spare_cores);
  std::optional<SmoothedStarts> starts;
  if (smoothed_candidates && choice.improved) {
    if (!smoothings) smoothings = smooth_input(run);
    starts = smoothed_starts(run, std::move(*smoothings), std::move(stepped));
  }
  judge_candidates(run, plan, judge, choice, deformed ? &input_start : nullptr, std::move(starts), false,
                   progress.sub(0.6, 1.0));
}

// More threads: the polishes least motion made ahead (or makes now where no
// thread took them yet) beside the choice's and the stepped start's.
void compete_ahead(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                   LeastMotionAhead& ahead, const std::function<void(const Progress&)>& polish_choice, Judge& judge,
                   Choice& choice, const Progress& progress) {
  const MeasuredInput& input = run.input;
  LeastMotionAhead::Work& work = ahead.work();
  if (!deformed) work.drop_deformed_only();
  work.starts_ready.get();
  std::optional<Start> stepped;
  if (deformed) {
    Positions positions = work.smoothed_start->positions;
    deformation.step_from(positions);
    // A step that left the smoothing as it was (where the fold-safe step's
    // reverts do not end, it takes none) is not polished: it would tie with
    // the smoothed start, which comes first in the order and wins ties.
    if (positions != work.smoothed_start->positions) {
      const double move = motion_of(positions, input.positions).rms;
      stepped = Start{std::move(positions), ResultOrigin::smoothed_step_polish, move, {}};
    }
  }
  deformation.release();
  std::vector<Job> jobs;
  jobs.push_back([&](const Progress& share) {
    polish_choice(share);
    work.set_choice_move(motion_of(choice.positions, input.positions).rms);
  });
  if (stepped)
    jobs.push_back(
        [&](const Progress& share) { stepped->polished = polish_start(run, *stepped, work.late_options, share); });
  for (int k = 0; k < LeastMotionAhead::Work::count; ++k)
    jobs.push_back(
        [&work, k](const Progress& share) { work.take(static_cast<LeastMotionAhead::Work::Polish>(k), share); });
  // The ahead thread keeps its core while its polishes run.
  const auto cores = static_cast<int>(thread_count(input.options.threads));
  const int threads = work.polishes_ahead ? std::max(1, cores - 1) : cores;
  run_concurrently(jobs, threads, progress.sub(0.0, 0.9), input.spare_cores);
  ahead.join(progress.sub(0.0, 0.9));

  SmoothedStarts smoothed;
  smoothed.smoothing_move = work.smoothed_start->move;
  if (deformed) {
    smoothed.starts.push_back(std::move(*work.smoothed_start));
    if (stepped) smoothed.starts.push_back(std::move(*stepped));
  } else {
    smoothed.unstarted_smoothing = std::move(work.smoothed_start->positions);
  }
  if (work.projected_start) smoothed.starts.push_back(std::move(*work.projected_start));
  judge_candidates(run, plan, judge, choice, deformed ? &work.input_start : nullptr, std::move(smoothed), true,
                   progress.sub(0.9, 1.0));
}

}  // namespace

bool runs_ahead(const PipelineOptions& options) {
  return options.polish_smoothed_input && thread_count(options.threads) > 1;
}

void compete_least_motion(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                          LeastMotionAhead* ahead, const std::function<void(const Progress&)>& polish_choice,
                          Judge& judge, Choice& choice, const Progress& progress) {
  if (ahead)
    compete_ahead(run, plan, deformation, deformed, *ahead, polish_choice, judge, choice, progress);
  else
    compete_in_rounds(run, plan, deformation, deformed, polish_choice, judge, choice, progress);
}

}  // namespace developable

#include "pipeline/least_motion.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "deformation/jet_denoise.h"
#include "deformation/move_limit.h"

#include <atomic>
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
  Positions positions;
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

// The input smoothed without the feature guard (smoothing_groups), within
// the limit, its turned sliver faces given back the input's corners.
Positions projection_start(const PatchRun& run) {
  const MeasuredInput& input = run.input;
  JetDenoiseOptions unguarded;
  unguarded.feature_angle_deg = kProjectionSmoothing;
  unguarded.face_groups = smoothing_groups(run);
  Positions start = jet_denoise(input.positions, input.triangles, input.connectivity, run.pinned, unguarded);
  clamp_moves(start, input.positions, input.limit);
  // As many rounds as it takes: the input folds nothing.
  put_back_folded_corners(start, input.positions, input.triangles, input.normals,
                          CreaseGuard(input.triangles, input.normals, {}, 0.0),
                          static_cast<int>(input.positions.rows()));
  return start;
}

// The input with its noise smoothed (jet_denoise, within the limit) and,
// given the deformation (a deformed result's), that smoothing after one of
// its steps toward targets refit on it.
struct SmoothedInput {
  Positions smoothed;
  std::optional<Positions> stepped;
};

SmoothedInput smoothed_input(const PatchRun& run, DeformationRun* deformation) {
  const MeasuredInput& input = run.input;
  SmoothedInput out;
  JetDenoiseOptions options;
  options.face_groups = smoothing_groups(run);
  out.smoothed = jet_denoise(input.positions, input.triangles, input.connectivity, run.pinned, options);
  clamp_moves(out.smoothed, input.positions, input.limit);
  if (deformation) {
    out.stepped = out.smoothed;
    deformation->step_from(*out.stepped);
  }
  return out;
}

// The smoothed starts (after the polish of the input and the choice's own):
// the smoothing, its step, the projection's start, each where it can win.
void add_smoothed_starts(const PatchRun& run, SmoothedInput smoothed, Contest& contest, std::vector<Start>& starts) {
  const MeasuredInput& input = run.input;
  const double smoothing_move = motion_of(smoothed.smoothed, input.positions).rms;
  if (contest.bound() > kShapeChangeMove * smoothing_move)
    contest.set_shape_roughness(
        normal_roughness(face_normals(smoothed.smoothed, input.triangles), input.triangles, input.connectivity));
  const bool same_start = smoothing_move < kSameStartShare * contest.bound();
  // Where the deformation found nothing better (no step), only the projected
  // start: the guarded ones cost a 28k-face irregular mesh 4 s, and without
  // them 7 of the 611 family runs of seeds 0-9 and 100-102 changed, the mean
  // log ratio to the twin by 0.0002.
  if (!same_start && smoothed.stepped) {
    starts.push_back({std::move(smoothed.smoothed), ResultOrigin::smoothed_input_polish, smoothing_move, {}});
    const double stepped_move = motion_of(*smoothed.stepped, input.positions).rms;
    starts.push_back({std::move(*smoothed.stepped), ResultOrigin::smoothed_step_polish, stepped_move, {}});
  }
  // The projection, on sheets (one patch, or pieces cut at creases, smoothed
  // each on its own; a segmented object's patch borders are not its
  // creases, and its corners are cut by that smoothing: it won on none of
  // the shared meshes and cost human_woman 0.7 s) and where the smoothing
  // moves the input enough.
  if (run.sheets) {
    Positions projected = projection_start(run);
    const double projected_move = motion_of(projected, input.positions).rms;
    if (projected_move >= kSameStartShare * contest.bound())
      starts.push_back({std::move(projected), ResultOrigin::projected_input, projected_move, {}, true});
  }
}

}  // namespace

void compete_least_motion(const PatchRun& run, const PolishPlan& plan, DeformationRun& deformation, bool deformed,
                          const std::function<void(const Progress&)>& polish_choice, Judge& judge, Choice& choice,
                          const Progress& progress) {
  const MeasuredInput& input = run.input;
  // A deformed result's smoothed starts are made first, so that the
  // deformation's system (its factor: 360 MB of a 1M-face sheet's peak) goes
  // before any polish runs; the step is wasted only where the smoothing
  // turns out to move the input too little to compete (same_start).
  std::optional<SmoothedInput> smoothed;
  if (input.options.polish_smoothed_input && deformed) smoothed = smoothed_input(run, &deformation);
  deformation.release();
  std::vector<Start> starts;
  starts.push_back({input.positions, ResultOrigin::input_polish, 0.0, {}});
  if (deformed) {
    // The polish of the input gives up past the choice's move once the
    // choice's polishes have set it (PolishOptions::late_give_up_move).
    std::atomic<double> choice_move{0.0};
    PolishOptions input_options = plan.candidates;
    input_options.late_give_up_move = &choice_move;
    run_concurrently({[&](const Progress& share) {
                        polish_choice(share);
                        choice_move = motion_of(choice.positions, input.positions).rms;
                      },
                      [&](const Progress& share) {
                        starts[0].polished =
                            polish_defects(input.positions, input.positions, input.normals, input.triangles, run.scored,
                                           run.pinned, input_options, share);
                      }},
                     input.options.threads, progress.sub(0.0, 0.6));
  } else {
    // The choice's polish is the polish of the input.
    polish_choice(progress.sub(0.0, 0.6));
  }
  Contest contest(input, judge.input().figures);
  if (choice.improved) contest.add(choice, false);
  // Nothing to compete with when even the polish of the input found nothing better.
  if (input.options.polish_smoothed_input && choice.improved)
    add_smoothed_starts(run, smoothed ? std::move(*smoothed) : smoothed_input(run, nullptr), contest, starts);
  // A start as far as the winner so far, or a polish that went as far at any
  // step (PolishResult::largest_move), cannot win.
  const auto judge_candidate = [&](const Start& start) {
    const PolishResult& polished = start.polished;
    if (polished.iterations == 0 || (!start.projected && start.move >= contest.bound()) ||
        polished.largest_move > contest.bound())
      return;
    const Measured now = judge.measure(polished.positions, face_normals(polished.positions, input.triangles));
    if (!judge.admissible(now)) return;
    Choice candidate = choice;
    candidate.keep(polished.positions, now, start.origin);
    candidate.polish_iterations = polished.iterations;
    contest.add(std::move(candidate), start.projected);
  };
  judge_candidate(starts[0]);
  // The smoothed starts, polished beside each other against the winner so
  // far: one already farther is not polished (the benchmark's noise-free
  // wavy cone spent 300 ms polishing two that lost so), and a polish gives
  // up once it is farther.
  PolishOptions smoothed_options = plan.candidates;
  smoothed_options.give_up_move = contest.bound();
  PolishOptions projection_options = smoothed_options;
  projection_options.pull_steps = kProjectionSteps;
  projection_options.active_defect = 0.0;
  projection_options.max_iterations = kProjectionSteps + kProjectionPolishSteps;
  std::vector<Job> polishes;
  for (size_t k = 1; k < starts.size(); ++k) {
    if (!starts[k].projected && starts[k].move >= contest.bound()) continue;
    polishes.push_back([&, k](const Progress& share) {
      starts[k].polished =
          polish_defects(starts[k].positions, input.positions, input.normals, input.triangles, run.scored, run.pinned,
                         starts[k].projected ? projection_options : smoothed_options, share);
    });
  }
  run_concurrently(polishes, input.options.threads, progress.sub(0.6, 1.0));
  for (size_t k = 1; k < starts.size(); ++k) judge_candidate(starts[k]);
  const int winner = contest.winner();
  if (winner >= 0) choice = std::move(contest.candidate(winner));
}

}  // namespace developable

#include "pipeline/plan.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "pipeline/judge.h"
#include "pipeline/messages.h"
#include "pipeline/patch_alternative.h"
#include "pipeline/patches.h"
#include "pipeline/selection.h"
#include "segmentation/crease_pieces.h"
#include "segmentation/crease_strength.h"
#include "segmentation/developable_pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace developable {

bool splits_automatically(bool object, double one_patch_fit_error) {
  return object || one_patch_fit_error > kAutoSegmentationError;
}

bool wants_second_opinion(const PipelineOptions& options, int patch_count, bool object, Eigen::Index interior_vertices,
                          double mean_defect) {
  return options.segmentation == -1 && patch_count > 1 && !object && interior_vertices <= kSecondOpinionVertices &&
         mean_defect > options.developable_threshold;
}

bool splits_finer(const PipelineStats& automatic) {
  const UnchangedReason reason = automatic.unchanged_reason;
  return automatic.result == ResultKind::unchanged &&
         (reason == UnchangedReason::rejected || reason == UnchangedReason::no_better_iterate ||
          reason == UnchangedReason::no_visible_gain);
}

bool takes_crease_pieces(int wanted_patches, int count, double worst_fit, double border_defect, double inside_defect) {
  return wanted_patches <= 0 && count >= 2 && worst_fit <= kCreasePieceFit &&
         border_defect >= kBorderCurvature * inside_defect;
}

double crease_defect_excess(const std::vector<double>& defects, const std::vector<double>& gains, double noise) {
  double squares = 0.0, gain = 0.0;
  for (const double k : defects) squares += k * k;
  for (const double g : gains) gain += g;
  if (squares == 0.0) return 0.0;
  const double expected = noise * noise * gain;
  return expected > 0.0 ? squares / expected : std::numeric_limits<double>::infinity();
}

bool crease_pieces_compete(double defect_excess) { return !(defect_excess >= kCreaseDefectExcess); }

bool one_sheet_within_noise(const Figures& other, const Figures& input, double other_rms_motion, double noise) {
  Figures developable;
  developable.flat = 1.0;
  return as_developable(other, developable, input, false) && other_rms_motion <= kCreaseMoveNoise * noise;
}

bool others_compete(bool crease_pieces_improved, bool one_sheet) { return !crease_pieces_improved || one_sheet; }

double crease_move_limit(double limit, double noise) {
  const double within = kCreaseMoveNoise * noise;
  return limit > 0.0 ? std::min(limit, within) : within;
}

namespace {

// The pieces the curvature already cuts the mesh into, each flat inside (a
// lobster-back elbow's mitres, which segmentation's cone fits cut across), as
// patches marked developable; none when the input is developable already or
// its curvature does not part it so.
std::optional<Patches> developable_pieces_of(const MeasuredInput& input) {
  if (input.before.mean_abs <= input.options.developable_threshold) return std::nullopt;
  std::optional<std::vector<int>> pieces = developable_pieces(
      input.triangles, input.connectivity, input.measured.interior, input.measured.defect_before, kFlatDefect);
  if (!pieces) return std::nullopt;
  const int count = 1 + *std::max_element(pieces->begin(), pieces->end());
  Patches patches = fitted_patches(std::move(*pieces), count, input.normals, input.areas, input.options);
  patches.developable = true;
  return patches;
}

// Mean |defect| (rad) of the interior vertices on the pieces' borders and of
// those inside them.
std::pair<double, double> border_and_inside_defects(const MeasuredInput& input, const std::vector<int>& ids) {
  const std::vector<bool> border = patch_border_vertices(input.triangles, ids, input.positions.rows());
  double sums[2] = {0.0, 0.0};
  Eigen::Index counts[2] = {0, 0};
  for (Eigen::Index v = 0; v < input.positions.rows(); ++v) {
    if (!input.measured.interior[static_cast<size_t>(v)]) continue;
    const int k = border[static_cast<size_t>(v)] ? 0 : 1;
    sums[k] += std::abs(input.measured.defect_before[v]);
    ++counts[k];
  }
  return {counts[0] > 0 ? sums[0] / static_cast<double>(counts[0]) : 0.0,
          counts[1] > 0 ? sums[1] / static_cast<double>(counts[1]) : 0.0};
}

// crease_defect_excess of the interior vertices on the pieces' borders.
double border_defect_excess(const MeasuredInput& input, const std::vector<int>& ids, double noise) {
  const std::vector<bool> border = patch_border_vertices(input.triangles, ids, input.positions.rows());
  std::vector<double> defects, gains;
  for (Eigen::Index v = 0; v < input.positions.rows(); ++v) {
    if (!input.measured.interior[static_cast<size_t>(v)] || !border[static_cast<size_t>(v)]) continue;
    defects.push_back(input.measured.defect_before[v]);
    gains.push_back(angle_defect_noise_gain(input.positions, input.triangles, input.normals, input.connectivity, v));
  }
  return crease_defect_excess(defects, gains, noise);
}

// The pieces the crease lines of a noisy mesh part it into (a mitred elbow,
// a tee, a reducer with noise on every vertex), as patches, when the plan
// takes them (takes_crease_pieces); none when the input is developable
// already. `noise`: the noise their run's move limit is set by; `excess`:
// their borders' crease_defect_excess.
std::optional<Patches> crease_pieces_of(const MeasuredInput& input, const Progress& progress, double& noise,
                                        double& excess) {
  const PipelineOptions& options = input.options;
  if (input.before.mean_abs <= options.developable_threshold || options.segmentation_options.target_patches > 0)
    return std::nullopt;
  progress.report(0.0, "crease lines");
  CreasePieces pieces =
      crease_pieces(input.positions, input.triangles, input.normals, input.areas, input.connectivity, options.threads);
  const double worst = pieces.fit.empty() ? 0.0 : *std::max_element(pieces.fit.begin(), pieces.fit.end());
  const auto [border, inside] = border_and_inside_defects(input, pieces.ids);
  if (!takes_crease_pieces(options.segmentation_options.target_patches, pieces.count, worst, border, inside))
    return std::nullopt;
  noise = std::max(pieces.cone_noise, kNoiseFloor * input.measured.stats.average_edge_length);
  excess = border_defect_excess(input, pieces.ids, noise);
  Patches patches = fitted_patches(std::move(pieces.ids), pieces.count, input.normals, input.areas, options);
  patches.creased = true;
  return patches;
}

// What the rule reads of the input (result_figures: of a result).
Figures figures_of(const MeasuredInput& input) {
  Figures f;
  f.flat = input.measured.stats.flat_share_before;
  f.ruled = input.measured.stats.shares_before.ruled;
  f.mean = input.before.mean_abs;
  f.max = input.before.max_abs;
  return f;
}

// Of the results of the alternatives, the one the order (select) returns:
// an improved one over the input returned unchanged; on a whole object one
// not crumpled over crumpled ones; of those the one that moved the input
// least of those as developable as the most developable; the first when none
// improved.
PipelineResult& preferred(const MeasuredInput& input, const std::vector<PipelineResult*>& results) {
  const Figures input_figures = figures_of(input);
  std::vector<PipelineResult*> improved;
  for (PipelineResult* r : results)
    if (r->stats.result == ResultKind::improved) improved.push_back(r);
  if (input.object) {
    std::vector<PipelineResult*> not_crumpled;
    for (PipelineResult* r : improved)
      if (!crumpled(result_figures(*r), input_figures)) not_crumpled.push_back(r);
    if (!not_crumpled.empty()) improved = std::move(not_crumpled);
  }
  if (improved.empty()) return *results.front();
  if (improved.size() == 1) return *improved.front();
  std::vector<Contestant> contestants;
  for (PipelineResult* r : improved)
    contestants.push_back({result_figures(*r), motion_of(r->positions, input.positions)});
  // Each result passed its own run's roughness test: no second one here (a
  // one-patch polish of a noisy input is rougher than a split run's result
  // and far more developable: a generalized cone on an irregular
  // triangulation, 100 % flat as one patch, 93 % in three).
  const int winner = select(contestants, input_figures, std::numeric_limits<double>::infinity(), input.object);
  return *improved[static_cast<size_t>(std::max(winner, 0))];
}

Patches segmented(const MeasuredInput& input, const PipelineOptions& options, const Progress& progress) {
  return segmented_patches(input.positions, input.triangles, input.normals, input.areas, input.connectivity, options,
                           progress);
}

// The segmented run of a whole object, and, where it came back unchanged
// (splits_finer), the run on twice as many patches if that improved. On 17
// random closed objects of devkit/objects.py that came back unchanged (seeds
// 0-9), 7 improve so (tori 4 -> 35 %, 6 -> 42 % flat, a limb 6 -> 48 %, a blob
// 54 -> 72 %); boat, wingnut and penguin stay unchanged and their messages
// say the finer split was tried (docs/segmentation.md).
PipelineResult split_finer_if_unchanged(const MeasuredInput& input, Patches patches, const Progress& progress) {
  PipelineResult automatic = run_patch_alternative(input, std::move(patches), progress.sub(0.05, 0.55));
  if (!splits_finer(automatic.stats)) {
    progress.report(1.0, "done");
    return automatic;
  }
  PipelineOptions finer_options = input.options;
  finer_options.segmentation_options.target_patches = 2 * static_cast<int>(automatic.stats.patches);
  const Progress later = progress.sub(0.55, 1.0);
  PipelineResult finer = run_patch_alternative(input, segmented(input, finer_options, later), later);
  PipelineResult& chosen = finer.stats.result == ResultKind::improved ? finer : automatic;
  if (&chosen == &automatic)
    chosen.stats.result_message = finer_split_also_unchanged(chosen.stats.result_message, finer.stats.patches);
  chosen.stats.time_total_ms = elapsed_ms(input.start_time);
  return std::move(chosen);
}

// A whole object (is_object) split automatically: the segmented run (with its finer
// split) beside the thinned-pieces generator's two candidates (thinned
// pieces from creases and from the segmentation of the thinned mesh,
// thinned_pieces.h), the one order choosing, on an object by the
// flat-and-ruled share first (torus 11.4 -> 62 %, bunny 44.7 -> 68 %,
// human_woman 33.6 -> 44.6 % flat and ruled, its crumpled share 31 -> 1.4 %;
// docs/segmentation.md, "Thinned pieces").
PipelineResult object_alternatives(const MeasuredInput& input, Patches patches, const Progress& progress) {
  PipelineResult split = split_finer_if_unchanged(input, std::move(patches), progress.sub(0.0, 0.5));
  // A mesh developable as it stands, or piecewise (a torus of cone frusta),
  // has nothing to gain: it comes back as it is.
  const UnchangedReason reason = split.stats.unchanged_reason;
  // Without a move limit the generator has none to thin within: its stages
  // return the input (thinned_pieces.h), which never beats the split run, so
  // neither its factorisation nor its candidates are worth making.
  if ((split.stats.result == ResultKind::unchanged &&
       (reason == UnchangedReason::developable_piecewise || reason == UnchangedReason::already_developable)) ||
      !(input.limit > 0.0)) {
    progress.report(1.0, "done");
    return split;
  }
  NormalGuidedDeformation thinning = thinning_deformation(input);
  const Positions thinned = thin_whole(input, thinning, progress.sub(0.5, 0.6));
  // The two candidates side by side (each the same whatever thread runs it):
  // human_woman's generator 13 s of CPU, two thirds of it their polishes.
  // They share the thinning's factor, freed once both have thinned their
  // pieces (a 1M-face rounded box: 3.1 GB side by side with one each).
  NormalGuidedDeformation for_creases = thinning.sharing_factor(), for_cones = thinning.sharing_factor();
  thinning.release();
  PipelineResult creases, cones;
  run_concurrently(
      {[&](const Progress& share) {
         creases = run_thinned_alternative(input, thinned, PieceSource::creases, std::move(for_creases), share);
       },
       [&](const Progress& share) {
         cones = run_thinned_alternative(input, thinned, PieceSource::segmentation, std::move(for_cones), share);
       }},
      input.options.threads, progress.sub(0.6, 1.0), input.spare_cores);
  PipelineResult& chosen = preferred(input, {&split, &creases, &cones});
  chosen.stats.time_total_ms = elapsed_ms(input.start_time);
  return std::move(chosen);
}

// The plan's alternatives after the crease pieces: one patch when one set
// of curves carries the mesh, else the segmentation's patches (with the
// second opinion or the finer split).
PipelineResult run_without_crease_pieces(const MeasuredInput& input, const Progress& progress) {
  const PipelineOptions& options = input.options;
  Patches single;
  if (options.segmentation == -1 && !input.object) {
    single = one_patch(input.normals, input.areas, options);
    if (!splits_automatically(input.object, curve_fit_error(input.normals, single.targets, input.areas)))
      return run_patch_alternative(input, std::move(single), progress);
  }
  Patches patches = segmented(input, options, progress);
  if (wants_second_opinion(options, patches.count, input.object, input.measured.stats.interior_vertices,
                           input.before.mean_abs)) {
    PipelineResult split = run_patch_alternative(input, std::move(patches), progress.sub(0.05, 0.55));
    PipelineResult whole = run_patch_alternative(input, std::move(single), progress.sub(0.55, 1.0));
    PipelineResult& chosen = preferred(input, {&split, &whole});
    chosen.stats.time_total_ms = elapsed_ms(input.start_time);
    return std::move(chosen);
  }
  if (!input.object || options.segmentation_options.target_patches > 0)
    return run_patch_alternative(input, std::move(patches), progress);
  return object_alternatives(input, std::move(patches), progress);
}

}  // namespace

PipelineResult run_plan(const MeasuredInput& input, const Progress& progress) {
  const PipelineOptions& options = input.options;
  if (options.segmentation == 0)
    return run_patch_alternative(input, one_patch(input.normals, input.areas, options), progress);
  if (std::optional<Patches> pieces = developable_pieces_of(input))
    return run_patch_alternative(input, std::move(*pieces), progress);
  double noise = 0.0, excess = 0.0;
  if (std::optional<Patches> pieces = crease_pieces_of(input, progress, noise, excess)) {
    MeasuredInput within = input;
    within.limit = crease_move_limit(input.limit, noise);
    within.measured.stats.move_limit = within.limit;
    if (!crease_pieces_compete(excess)) return run_patch_alternative(within, std::move(*pieces), progress);
    PipelineResult creased = run_patch_alternative(within, std::move(*pieces), progress.sub(0.0, 0.5));
    PipelineResult other = run_without_crease_pieces(input, progress.sub(0.5, 1.0));
    const bool sheet = other.stats.result == ResultKind::improved &&
                       one_sheet_within_noise(result_figures(other), figures_of(input),
                                              motion_of(other.positions, input.positions).rms, noise);
    PipelineResult& chosen = others_compete(creased.stats.result == ResultKind::improved, sheet)
                                 ? preferred(input, {&other, &creased})
                                 : creased;
    chosen.stats.time_total_ms = elapsed_ms(input.start_time);
    return std::move(chosen);
  }
  return run_without_crease_pieces(input, progress);
}

}  // namespace developable

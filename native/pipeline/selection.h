// What a run may return, and which of its candidates it returns: pure rules
// on the figures of candidate meshes, no mesh needed (tests/unit/
// selection_test.cpp holds every slack and ordering). A candidate is a mesh
// one of the generators made (the deformation and its polish, least motion's
// polishes; ResultOrigin); the plan's patch alternatives are compared by
// more_developable. docs/method.md, "The rule", has the measurements behind
// each slack.
#pragma once

#include "pipeline/run_result.h"

#include <Eigen/Core>

namespace developable {

// How much a closed mesh's mean |defect| may grow (fraction) in exchange for
// flat patches: Gauss-Bonnet keeps its total, so flattening the patches
// gathers it on the seams, where the signs of neighbouring defects no longer
// cancel (the 1280-face sphere: 0 -> 32 % flat for +3.6 %).
inline constexpr double kClosedMeshGrowth = 0.05;

// A result must score at least this fraction below the input: less is
// rounding, not an improvement (the benchmark's noise-free wavy cone of 100k
// faces, flat from the start, was "improved" by 2e-14 of its mean |defect|
// while its largest |defect| grew).
inline constexpr double kLeastGain = 1e-6;

// "As developable" (as_developable): a flat share at most this much lower,
// a mean |defect| at most this fraction of the input's mean higher (else
// fish_low_resolution would trade -10.5 % for +1.7 %).
inline constexpr double kFlatSlack = 0.01;
inline constexpr double kDefectSlack = 0.01;

// A second try (the nearly flat polish, the second opinion's one-patch run)
// may end with a largest |defect| this fraction above the larger of the
// result it competes with and the input's (allowed_largest_defect).
inline constexpr double kLargestDefectGrowth = 0.05;

// Least motion prefers a candidate whose normals are at most this much
// rougher (normal_roughness) than the reference: the polish keeps the noise
// of the normals the deformation removes (the run command's demo band: 2.8
// against 1.7 degrees, the input's 3.2).
inline constexpr double kLeastMoveRoughness = 1.25;

// What the rule reads of a candidate mesh, measured against the user's input.
struct Figures {
  double flat = 0.0;        // share of the interior vertices with |defect| < kFlatDefect, 0..1
  double mean = 0.0;        // mean |defect| over the interior (rad)
  double max = 0.0;         // largest |defect| over the interior (rad)
  double score = 0.0;       // the run's score (IterateScore, rad): lower is better
  Eigen::Index turned = 0;  // faces turned over against the input's normals
};

// Which admissibility conditions a candidate breaks.
struct Admission {
  bool folded = false;           // a face turned over
  bool defect_grew = false;      // mean |defect| above the input's (beyond kClosedMeshGrowth on a closed mesh)
  bool flat_share_fell = false;  // fewer flat vertices than the input
  bool ok() const { return !folded && !defect_grew && !flat_share_fell; }
};

// The admissibility rule: a candidate may be returned only if no figure the
// user sees is worse than the input's: no face turned over, the mean
// |defect| not above the input's (a closed mesh's up to kClosedMeshGrowth
// above), the flat share not below it. (Every generator keeps its vertices
// within the move limit and, where a crease guard holds, its patches
// uncreased; the generators check those themselves.)
Admission admit(const Figures& candidate, const Figures& input, bool closed);

// Whether a result shows its gain on a figure the user sees: more flat
// vertices, or a mean |defect| lower by kLeastGain of the input's. The score
// may fall where neither moves (a segmented mesh's median inside the
// patches: a capped cone's apex moved, no vertex flat).
bool visible_gain(const Figures& result, const Figures& input);

// Whether `candidate` is as developable as `current`, both results of one
// input: its flat share at most kFlatSlack lower, its mean |defect| at most
// kDefectSlack of the input's mean higher, its largest |defect| no larger
// than both current's and the input's.
bool as_developable(const Figures& candidate, const Figures& current, const Figures& input);

// The largest |defect| a second try may end with: kLargestDefectGrowth above
// the larger of the result it competes with and the input's.
double allowed_largest_defect(double competing, double input);

// How far a candidate moved the input: RMS over the vertices, and its
// largest vertex move (caller's units).
struct Motion {
  double rms = 0.0, largest = 0.0;
};

// Least motion's order: whether `candidate` moved the input less than
// `current` (RMS), and, with `at_most_as_far`, no vertex farther than
// current's largest move.
bool moves_less(const Motion& candidate, const Motion& current, bool at_most_as_far);

// Whether normals of roughness `roughness` (normal_roughness, rad) are smooth
// enough against `reference`: at most kLeastMoveRoughness times it.
bool smooth_enough(double roughness, double reference);

// Of two results of one input (their stats), whether `a` is the more
// developable: an improved result beats the input returned unchanged; of two
// improved ones `a` needs a flat share and a mean |defect| both at least as
// good as `b`'s, one of them better, and a largest |defect| within
// allowed_largest_defect of `b`'s and the input's.
bool more_developable(const PipelineStats& a, const PipelineStats& b);

// Why candidates better than the input were not returned, counted as they
// are judged: the reasons an unchanged run's message names.
struct Rejections {
  int folded = 0, defect_grew = 0, flat_share_fell = 0;
  // A polish of a segmented input (not crease-guarded) creased an edge
  // inside a patch.
  int creased = 0;
  Eigen::Index fewest_turned_over = -1;
  // The best result made no vertex flat and did not lower the mean |defect|.
  bool no_visible_gain = false;
  // Every patch is developable as it stands: nothing was there to gain.
  bool developable_patches = false;

  // Counts what `admission` broke of a candidate that scored `score` below
  // the input's `input_score`, with `turned` faces turned over.
  void record(const Admission& admission, double score, double input_score, Eigen::Index turned);
};

// Why an unchanged run returned its input, from its rejections and the
// input's flat share (0..1).
UnchangedReason unchanged_reason(const Rejections& rejections, double flat_share_before);

// The WorseFigure flags of an improved result's stats against the input's.
int worse_figures(const PipelineStats& stats);

}  // namespace developable

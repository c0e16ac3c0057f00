// The thinned-pieces generator (beyond the paper; issue 35): a closed,
// doubly curved object made developable as ruled pieces meeting at seams,
// instead of flat by triangle-scale zigzags.
//
//   1. thinning: the deformation step (deformation.h, decoupled) toward the
//      local Gauss-image thinning targets (ideal_curve/gauss_thinning.h, no
//      pieces), kThinningIterations steps, the cone shrinking from
//      kThinningConeStart to kThinningConeEnd, every vertex within
//      kThinningLimitShare of the move limit; a step's faces that turn over or
//      collapse keep their corners (ring by ring);
//   2. pieces, from one of two sources (PieceSource), each a candidate:
//      the thinned normals split where they jump by more than kPieceCrease
//      (segmentation/normal_jump_pieces.h), small pieces merged where no edge of
//      their border is creased beyond the crease guard over the input; or
//      the segmentation (segmentation.h) of the thinned mesh, whose cone fits
//      find the ruled bands the thinning made. An edge inside a piece
//      creased beyond the guard over the input (a crease that ends inside a
//      piece) has the corners of its faces put back where the input has
//      them, ring by ring, so that no piece holds one;
//   3. thinning again inside the pieces (kPieceThinningIterations steps, no
//      edge inside a piece creased beyond the run's crease guard);
//   4. the ruled polish (deformation/ruled_polish.h) of the vertices inside
//      the pieces: flat and ruled together, within the move limit of the
//      input, no face turned over, no edge inside a piece creased beyond the
//      guard. (The angle-defect polish here makes the pieces flat by
//      zigzags again: spot 32.7 % flat, 15.1 % flat and ruled, 17.6 %
//      crumpled; held by a guard on the ruling spread it hardly moves: 22.9 %
//      flat and ruled against 22.7 % before it.)
//   5. the pieces still curved inside (under kCurvedPieceShare of their
//      inside vertices flat and ruled, at least kCurvedPieceInside of them)
//      split in two where their normals fit two cones
//      (segmentation/curved_pieces.h), and stages 3-4 again on the new pieces
//      from where the polish left them, once.
// Every step keeps no face turned over or collapsed. Each candidate
// competes under the one rule (selection.h) through run_thinned_alternative
// (patch_alternative.h); docs/segmentation.md, "Thinned pieces", has the
// figures.
#pragma once

#include "core/types.h"
#include "deformation/deformation.h"
#include "pipeline/run_context.h"

#include <vector>

namespace developable {

inline constexpr int kThinningIterations = 100;
inline constexpr int kPieceThinningIterations = 60;
inline constexpr double kThinningConeStart = 25.0 * M_PI / 180.0;
inline constexpr double kThinningConeEnd = 5.0 * M_PI / 180.0;
inline constexpr double kThinningConeShrink = 0.95;  // per step
// The neighbourhood of the thinning targets, in average edge lengths.
inline constexpr double kThinningRadius = 3.0;
// The thinning stays within this share of the move limit, leaving the polish room.
inline constexpr double kThinningLimitShare = 0.9;
// Where the thinned normals jump by more than this a seam runs (rad). At most
// the segmented crease guard (kSegmentedCreaseGrowth), so that no edge
// inside a piece starts creased beyond it.
inline constexpr double kPieceCrease = 20.0 * M_PI / 180.0;

// Steps of the ruled polish (ruled_polish.h) of each candidate: on
// human_woman 60 give 44.6 % of the interior flat and ruled in 10.9 s, 200
// (to its stall) 45.0 % in 15.8 s.
inline constexpr int kThinnedPolishIterations = 60;

// The ruled polish's robust scale eps (RuledPolishOptions::robust) on the
// pieces: a vertex whose group of residuals is far above it gives up sooner
// than with the default 0.01 (at the thresholds a group is about 0.02), and
// the steps go to the vertices that can be made flat and ruled. Chosen on
// the shared meshes (human_woman 43.5 -> 48.3 % flat and ruled, bunny, hand
// +2 points, spot, sphere, torus within a point) and held out on the objects
// of seeds 100-111: mean +1.6 points, 25 of 56 better, 9 worse
// (docs/segmentation.md, "The ruled polish's give-up scale").
inline constexpr double kThinnedPolishRobust = 0.003;

// Stage 5: a piece with at least kCurvedPieceInside inside vertices, fewer
// than kCurvedPieceShare of them flat and ruled after the polish, is split in
// two. Chosen on the objects of seeds 0-9 (devkit/objects.py) and held out on
// seeds 100-119 and the shared meshes (docs/segmentation.md, "Pieces still
// curved inside").
inline constexpr double kCurvedPieceShare = 0.9;
inline constexpr int kCurvedPieceInside = 20;

// Where the pieces come from.
enum class PieceSource {
  creases,       // normal_jump_pieces of the thinned normals (kPieceCrease)
  segmentation,  // the segmentation (segmentation.h) of the thinned mesh
};

// The thinned mesh and its pieces.
struct ThinnedPieces {
  Positions positions;      // within input.limit of the input; the input when limit <= 0
  std::vector<int> pieces;  // per face, 0 .. count-1
  int count = 0;
  int polish_iterations = 0;
};

// The deformation of stages 1 and 3 (decoupled, every row weight 1, the
// refit mode's centroid weight, the input's pins), factored once: its
// matrix does not depend on the targets, so thin_whole and both candidates'
// stage 3 step with it or with a copy sharing its factor
// (NormalGuidedDeformation::sharing_factor). At 1M faces each factor took
// about 1 GB and the two candidates held one each side by side.
// Throws EngineError(numerical_failure) when the factorisation fails.
NormalGuidedDeformation thinning_deformation(const MeasuredInput& input);

// Stage 1 on `input` (closed or open; pins kept) with `deformation`
// (thinning_deformation's; its targets change): the thinned mesh, within
// kThinningLimitShare of input.limit; the input when input.limit <= 0.
// progress: 0..1 of the caller's range. Throws EngineError(cancelled)
// through `progress`, EngineError(numerical_failure) when a solve fails.
Positions thin_whole(const MeasuredInput& input, NormalGuidedDeformation& deformation, const Progress& progress);

// Stages 2-5 from `thinned` (thin_whole's) with the pieces of `source`,
// stage 3 with `deformation` (thin_whole's or one sharing its factor),
// released before stage 4 (stage 5 factors a thinning of its own). With no move limit (input.limit <= 0) it returns
// `thinned` as one piece. Throws as thin_whole.
ThinnedPieces thinned_pieces(const MeasuredInput& input, const Positions& thinned, PieceSource source,
                             NormalGuidedDeformation deformation, const Progress& progress);

}  // namespace developable

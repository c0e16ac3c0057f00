// plan.h: which patch alternatives a run makes, on synthetic figures.
#include "pipeline/plan.h"

#include "segmentation/crease_pieces.h"

#include <gtest/gtest.h>

#include <cmath>

namespace developable {
namespace {

// Closed meshes always split; open ones when one set of curves misses the
// normals by more than kAutoSegmentationError (0.12 rad).
TEST(Plan, AutomaticSegmentationSplitsClosedMeshesAndMisfits) {
  EXPECT_TRUE(splits_automatically(true, 0.0));
  EXPECT_FALSE(splits_automatically(false, 0.12));
  EXPECT_TRUE(splits_automatically(false, 0.1201));
}

// The second opinion: automatic, split, open, up to 10000 interior vertices,
// curvature to lose.
TEST(Plan, SecondOpinionOnSmallOpenMeshesTheAutomaticSegmentationSplit) {
  PipelineOptions automatic;
  EXPECT_TRUE(wants_second_opinion(automatic, 3, false, 10000, 0.1));
  EXPECT_FALSE(wants_second_opinion(automatic, 3, false, 10001, 0.1));
  EXPECT_FALSE(wants_second_opinion(automatic, 1, false, 100, 0.1));
  EXPECT_FALSE(wants_second_opinion(automatic, 3, true, 100, 0.1));
  EXPECT_FALSE(wants_second_opinion(automatic, 3, false, 100, automatic.developable_threshold));
  PipelineOptions forced;
  forced.segmentation = 1;
  EXPECT_FALSE(wants_second_opinion(forced, 3, false, 100, 0.1));
}

// A finer split after an unchanged run that found nothing admissible, nothing
// better or nothing visible; not after one that was developable already.
TEST(Plan, FinerSplitOnlyWhereTheAutomaticRunFailed) {
  PipelineStats s;
  s.result = ResultKind::unchanged;
  for (UnchangedReason r :
       {UnchangedReason::rejected, UnchangedReason::no_better_iterate, UnchangedReason::no_visible_gain}) {
    s.unchanged_reason = r;
    EXPECT_TRUE(splits_finer(s));
  }
  for (UnchangedReason r :
       {UnchangedReason::already_developable, UnchangedReason::developable_piecewise, UnchangedReason::already_flat}) {
    s.unchanged_reason = r;
    EXPECT_FALSE(splits_finer(s));
  }
  s.result = ResultKind::improved;
  s.unchanged_reason = UnchangedReason::none;
  EXPECT_FALSE(splits_finer(s));
}

// Crease pieces: no count of the caller's, two pieces or more, each within
// the noise of its cone, the curvature on their borders.
TEST(Plan, CreasePiecesTakenWhenTheyFitTheirConesAndHoldTheCurvature) {
  EXPECT_TRUE(takes_crease_pieces(0, 2, kCreasePieceFit, 2.0, 1.0));
  EXPECT_TRUE(takes_crease_pieces(0, 6, 0.3, 50.0, 0.01));
  EXPECT_FALSE(takes_crease_pieces(3, 2, 0.5, 2.0, 1.0));  // the caller wants 3 patches
  EXPECT_FALSE(takes_crease_pieces(0, 1, 0.5, 2.0, 1.0));  // one sheet
  EXPECT_FALSE(takes_crease_pieces(0, 2, std::nextafter(kCreasePieceFit, 2.0), 2.0, 1.0));  // a piece fits no cone
  EXPECT_FALSE(takes_crease_pieces(0, 2, 0.5, 1.999, 1.0));  // curvature inside the pieces
  EXPECT_FALSE(takes_crease_pieces(0, 8, 0.7, 0.44, 1.0));   // a transition's tangent seams
}

// The move limit on crease pieces: kCreaseMoveNoise times the noise, or the
// caller's limit where that is smaller; no caller's limit (0): the noise's.
TEST(Plan, CreasePiecesMoveWithinTheNoise) {
  EXPECT_DOUBLE_EQ(crease_move_limit(1.0, 0.01), kCreaseMoveNoise * 0.01);
  EXPECT_DOUBLE_EQ(crease_move_limit(0.001, 0.01), 0.001);
  EXPECT_DOUBLE_EQ(crease_move_limit(0.0, 0.01), kCreaseMoveNoise * 0.01);
}

}  // namespace
}  // namespace developable

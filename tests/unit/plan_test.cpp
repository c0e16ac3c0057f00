// plan.h: which patch alternatives a run makes, on synthetic figures.
#include "pipeline/plan.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace developable

// selection.h: the admissibility rule and the orders between candidates, on
// synthetic figures (no mesh). Each test names the slack or ordering it
// holds; changing one makes it fail.
#include "pipeline/selection.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

Figures figures(double flat, double mean, double max, double score = 0.0, Eigen::Index turned = 0) {
  Figures f;
  f.flat = flat;
  f.mean = mean;
  f.max = max;
  f.score = score;
  f.turned = turned;
  return f;
}

const Figures kInput = figures(0.2, 0.01, 0.5, 0.01);

// No face turned over, the mean |defect| not above the input's (a closed
// mesh's up to 5 % above), the flat share not below it.
TEST(Selection, AdmitHoldsEveryFigureTheUserSeesToTheInput) {
  EXPECT_TRUE(admit(figures(0.2, 0.01, 9.0), kInput, false).ok());  // equal is enough; max is not held
  const Admission folded = admit(figures(0.9, 0.001, 0.1, 0.0, 1), kInput, false);
  EXPECT_TRUE(folded.folded && !folded.defect_grew && !folded.flat_share_fell);
  EXPECT_TRUE(admit(figures(0.9, 0.0101, 0.1), kInput, false).defect_grew);
  EXPECT_TRUE(admit(figures(0.19, 0.001, 0.1), kInput, false).flat_share_fell);
  // kClosedMeshGrowth: 5 % more mean |defect| on a closed mesh, not 5.1 %.
  EXPECT_TRUE(admit(figures(0.9, 0.0105, 0.1), kInput, true).ok());
  EXPECT_TRUE(admit(figures(0.9, 0.01051, 0.1), kInput, true).defect_grew);
}

// A gain the user sees: more flat vertices, or a mean |defect| lower by a
// millionth of the input's (kLeastGain).
TEST(Selection, VisibleGainIsMoreFlatVerticesOrALowerMean) {
  EXPECT_TRUE(visible_gain(figures(0.21, 0.01, 0.5), kInput));
  EXPECT_TRUE(visible_gain(figures(0.2, 0.01 * (1 - 2e-6), 0.5), kInput));
  EXPECT_FALSE(visible_gain(figures(0.2, 0.01 * (1 - 0.5e-6), 0.5), kInput));
  EXPECT_FALSE(visible_gain(figures(0.2, 0.01, 0.1, 0.001), kInput));  // the score alone is no gain
}

// As developable: a flat share at most kFlatSlack (1 point) lower, a mean at
// most kDefectSlack (1 %) of the input's mean higher, a largest |defect| no
// larger than both the other's and the input's.
TEST(Selection, AsDevelopableAllowsOnePointOfFlatShareAndOnePercentOfTheInputsMean) {
  const Figures current = figures(0.90, 0.002, 0.3);
  EXPECT_TRUE(as_developable(figures(0.89, 0.002 + 0.0001, 0.3), current, kInput));
  EXPECT_FALSE(as_developable(figures(0.889, 0.002, 0.3), current, kInput));
  EXPECT_FALSE(as_developable(figures(0.95, 0.002 + 0.000101, 0.3), current, kInput));
  EXPECT_TRUE(as_developable(figures(0.95, 0.001, 0.5), current, kInput));  // the input's largest bounds
  EXPECT_FALSE(as_developable(figures(0.95, 0.001, 0.51), current, kInput));
  // Not symmetric: the other way round the slack is the other's.
  EXPECT_TRUE(as_developable(current, figures(0.905, 0.002, 0.3), kInput));
}

// A second try's largest |defect|: 5 % above the larger of the competing and
// the input's.
TEST(Selection, AllowedLargestDefectIsFivePercentAboveTheLarger) {
  EXPECT_DOUBLE_EQ(allowed_largest_defect(2.0, 1.0), 2.1);
  EXPECT_DOUBLE_EQ(allowed_largest_defect(1.0, 2.0), 2.1);
}

// Least motion: less RMS motion, and with at_most_as_far no vertex farther.
TEST(Selection, MovesLessComparesTheRmsMotionAndOptionallyTheLargest) {
  const Motion current{1.0, 3.0};
  EXPECT_TRUE(moves_less({0.9, 5.0}, current, false));
  EXPECT_FALSE(moves_less({0.9, 5.0}, current, true));
  EXPECT_TRUE(moves_less({0.9, 3.0}, current, true));
  EXPECT_FALSE(moves_less({1.0, 1.0}, current, false));  // strictly less
}

// Normals at most kLeastMoveRoughness (1.25) times as rough as the reference.
TEST(Selection, SmoothEnoughIsAtMostAQuarterRougher) {
  EXPECT_TRUE(smooth_enough(1.25, 1.0));
  EXPECT_FALSE(smooth_enough(1.2501, 1.0));
}

PipelineStats stats(ResultKind result, double flat, double mean, double max, double max_before = 1.0) {
  PipelineStats s;
  s.result = result;
  s.flat_share_after = flat;
  s.mean_defect_after = mean;
  s.max_defect_after = max;
  s.max_defect_before = max_before;
  return s;
}

// Of two alternatives: improved beats unchanged; else both flat share and
// mean at least as good, one better, the largest within 5 % of the larger of
// the other's and the input's.
TEST(Selection, MoreDevelopableNeedsBothFiguresAtLeastAsGoodAndOneBetter) {
  const PipelineStats unchanged = stats(ResultKind::unchanged, 0.9, 0.001, 0.1);
  const PipelineStats improved = stats(ResultKind::improved, 0.5, 0.01, 0.5);
  EXPECT_TRUE(more_developable(improved, unchanged));
  EXPECT_FALSE(more_developable(unchanged, improved));
  const PipelineStats b = stats(ResultKind::improved, 0.8, 0.002, 1.0);
  EXPECT_TRUE(more_developable(stats(ResultKind::improved, 0.8, 0.0019, 1.05), b));
  EXPECT_FALSE(more_developable(stats(ResultKind::improved, 0.8, 0.0019, 1.051), b));
  EXPECT_FALSE(more_developable(stats(ResultKind::improved, 0.8, 0.002, 1.0), b));   // nothing better
  EXPECT_FALSE(more_developable(stats(ResultKind::improved, 0.9, 0.0021, 1.0), b));  // one worse
}

// Rejections count only candidates that scored better than the input; the
// reason of an unchanged run follows from them.
TEST(Selection, RejectionsAndTheUnchangedReason) {
  Rejections r;
  r.record(admit(figures(0.1, 0.02, 0.1, 0.02, 3), kInput, false), 0.02, 0.01, 3);  // scored worse: not counted
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::no_better_iterate);
  EXPECT_EQ(unchanged_reason(r, 1.0), UnchangedReason::already_flat);
  r.record(admit(figures(0.9, 0.001, 0.1, 0.001, 3), kInput, false), 0.001, 0.01, 3);
  r.record(admit(figures(0.9, 0.001, 0.1, 0.001, 2), kInput, false), 0.001, 0.01, 2);
  EXPECT_EQ(r.folded, 2);
  EXPECT_EQ(r.fewest_turned_over, 2);
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::rejected);
  r.no_visible_gain = true;
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::no_visible_gain);
  r.developable_patches = true;
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::developable_piecewise);
}

TEST(Selection, WorseFiguresFlagEveryFigureThatGotWorse) {
  PipelineStats s = stats(ResultKind::improved, 0.5, 0.02, 2.0);
  s.flat_share_before = 0.6;
  s.mean_defect_before = 0.01;
  s.shares_before.ruled = 0.3;
  s.shares_after.ruled = 0.2;
  s.faces_turned_over = 1;
  EXPECT_EQ(worse_figures(s),
            worse_mean_defect | worse_max_defect | worse_flat_share | worse_ruled_share | worse_turned_faces);
  s = stats(ResultKind::improved, 0.7, 0.005, 0.5);
  s.flat_share_before = 0.6;
  s.mean_defect_before = 0.01;
  EXPECT_EQ(worse_figures(s), 0);
}

}  // namespace
}  // namespace developable

// selection.h: the admissibility rule and the order between candidates, on
// synthetic figures (no mesh). Each test names the slack or order it holds;
// changing one makes it fail.
#include "pipeline/selection.h"

#include <gtest/gtest.h>

#include <cmath>

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

// No face turned over, no crease, the mean |defect| not above the input's (a
// closed mesh's up to 5 % above), the flat share not below it, a gain.
TEST(Selection, AdmitHoldsEveryFigureTheUserSeesToTheInputAndWantsAGain) {
  EXPECT_TRUE(admit(figures(0.21, 0.01, 9.0, 0.001), kInput, false, false).ok());  // the largest |defect| is not held
  const Admission folded = admit(figures(0.9, 0.001, 0.1, 0.001, 1), kInput, false, false);
  EXPECT_TRUE(folded.folded && !folded.creased && !folded.defect_grew && !folded.flat_share_fell &&
              !folded.no_score_gain && !folded.no_visible_gain);
  Figures creased = figures(0.9, 0.001, 0.1, 0.001);
  creased.creased = 2;
  EXPECT_TRUE(admit(creased, kInput, false, false).creased);
  EXPECT_TRUE(admit(figures(0.9, 0.0101, 0.1, 0.001), kInput, false, false).defect_grew);
  EXPECT_TRUE(admit(figures(0.19, 0.001, 0.1, 0.001), kInput, false, false).flat_share_fell);
  // kClosedMeshGrowth: 5 % more mean |defect| on a closed mesh, not 5.1 %.
  EXPECT_TRUE(admit(figures(0.9, 0.0105, 0.1, 0.001), kInput, true, false).ok());
  EXPECT_TRUE(admit(figures(0.9, 0.01051, 0.1, 0.001), kInput, true, false).defect_grew);
  // The gain: a score kLeastGain (1e-6) below the input's, and a visible one.
  EXPECT_TRUE(admit(figures(0.9, 0.001, 0.1, 0.01 * (1 - 0.5e-6)), kInput, false, false).no_score_gain);
  EXPECT_FALSE(admit(figures(0.9, 0.001, 0.1, 0.01 * (1 - 2e-6)), kInput, false, false).no_score_gain);
  const Admission score_only =
      admit(figures(0.2, 0.01, 0.1, 0.001), kInput, false, false);  // the score alone is no gain
  EXPECT_TRUE(score_only.no_visible_gain && !score_only.no_score_gain && !score_only.ok());
}

// On a whole object the mean |defect| held is the one inside the pieces: the
// curvature may gather on the seams (the mean over every vertex grows) as long
// as it leaves the pieces; a sheet is held over every vertex.
TEST(Selection, AdmitHoldsAnObjectsMeanInsideItsPieces) {
  Figures input = kInput;
  input.mean_inside = 0.008;
  Figures gathered = figures(0.6, 0.02, 2.0, 0.001);  // twice the input's mean, on the seams
  gathered.mean_inside = 0.002;
  EXPECT_TRUE(admit(gathered, input, true, true).ok());
  EXPECT_TRUE(admit(gathered, input, true, false).defect_grew);
  Figures inside_grew = figures(0.6, 0.009, 0.5, 0.001);  // lower over every vertex, higher inside
  inside_grew.mean_inside = 0.008 * 1.051;
  EXPECT_TRUE(admit(inside_grew, input, true, true).defect_grew);
  EXPECT_TRUE(admit(inside_grew, input, true, false).ok());
  inside_grew.mean_inside = 0.008 * 1.049;  // kClosedMeshGrowth holds inside as it did over every vertex
  EXPECT_TRUE(admit(inside_grew, input, true, true).ok());
  EXPECT_TRUE(admit(inside_grew, input, false, true).defect_grew);  // an open object: no growth
}

// On a whole object whose rulings were read, the flat-and-ruled share may not
// fall below the input's (Blender's torus: its flat rings zigzagged, 16.7 % ->
// 0 flat and ruled, for a lower mean); unread (a deformation iterate) or on a
// sheet it is not held.
TEST(Selection, AdmitHoldsAnObjectsFlatAndRuledShareWhereItWasRead) {
  Figures input = figures(0.167, 0.042, 0.07, 0.04);
  input.ruled = 0.167;
  Figures zigzag = figures(0.167, 0.035, 0.06, 0.03);
  zigzag.ruled = 0.0;
  EXPECT_TRUE(admit(zigzag, input, true, true).ok());  // unread
  zigzag.ruled_read = true;
  const Admission a = admit(zigzag, input, true, true);
  EXPECT_TRUE(a.ruled_share_fell && !a.flat_share_fell && !a.defect_grew && !a.no_visible_gain);
  EXPECT_FALSE(admit(zigzag, input, true, false).ruled_share_fell);  // not an object
  zigzag.ruled = 0.167;
  EXPECT_TRUE(admit(zigzag, input, true, true).ok());
}

// Crumpled: more than kCrumpleSlack (3 points) of the interior vertices more
// flat-but-not-ruled than the input.
TEST(Selection, CrumpledIsMoreThanThreePointsMoreFlatButNotRuledThanTheInput) {
  Figures input = figures(0.2, 0.01, 0.5);
  input.ruled = 0.19;  // 1 % crumpled
  Figures result = figures(0.7, 0.01, 0.5);
  result.ruled = 0.7 - 0.0399;
  EXPECT_FALSE(crumpled(result, input));
  result.ruled = 0.7 - 0.0401;
  EXPECT_TRUE(crumpled(result, input));
}

// A gain the user sees: more flat vertices, or a mean |defect| lower by
// more than the order's slack on it (kDefectSlack, 1 % of the input's).
TEST(Selection, VisibleGainIsMoreFlatVerticesOrALowerMean) {
  EXPECT_TRUE(visible_gain(figures(0.21, 0.01, 0.5), kInput));
  EXPECT_TRUE(visible_gain(figures(0.2, 0.01 * (1 - 0.02), 0.5), kInput));
  EXPECT_FALSE(visible_gain(figures(0.2, 0.01 * (1 - 0.005), 0.5), kInput));
}

// As developable: a flat share at most kFlatSlack (1 point) lower, a mean at
// most kDefectSlack (1 %) of the input's mean higher, a largest |defect| at
// most 5 % above the larger of the other's and the input's.
TEST(Selection, AsDevelopableAllowsOnePointOfFlatShareOnePercentOfTheMeanFivePercentOfTheLargest) {
  const Figures other = figures(0.90, 0.002, 0.6);
  EXPECT_TRUE(as_developable(figures(0.89, 0.002 + 0.0001, 0.6), other, kInput, false));
  EXPECT_FALSE(as_developable(figures(0.889, 0.002, 0.6), other, kInput, false));
  EXPECT_FALSE(as_developable(figures(0.95, 0.002 + 0.000101, 0.6), other, kInput, false));
  EXPECT_TRUE(as_developable(figures(0.95, 0.001, 0.63), other, kInput, false));
  EXPECT_FALSE(as_developable(figures(0.95, 0.001, 0.631), other, kInput, false));
  const Figures small = figures(0.90, 0.002, 0.1);  // the input's largest (0.5) bounds
  EXPECT_TRUE(as_developable(figures(0.95, 0.001, 0.525), small, kInput, false));
  EXPECT_FALSE(as_developable(figures(0.95, 0.001, 0.526), small, kInput, false));
  // Not symmetric: the other way round the slack is the other's.
  EXPECT_TRUE(as_developable(other, figures(0.905, 0.002, 0.6), kInput, false));
  EXPECT_FALSE(as_developable(figures(0.905, 0.002, 0.6), figures(0.92, 0.002, 0.6), kInput, false));
}

TEST(Selection, AllowedLargestDefectIsFivePercentAboveTheLarger) {
  EXPECT_DOUBLE_EQ(allowed_largest_defect(2.0, 1.0), 2.1);
  EXPECT_DOUBLE_EQ(allowed_largest_defect(1.0, 2.0), 2.1);
}

// The developability order: the flat share first, then the mean |defect|.
TEST(Selection, MoreDevelopableIsMoreFlatVerticesThenALowerMean) {
  EXPECT_TRUE(more_developable(figures(0.91, 0.5, 9.0), figures(0.90, 0.001, 0.1), false));
  EXPECT_TRUE(more_developable(figures(0.90, 0.0009, 9.0), figures(0.90, 0.001, 0.1), false));
  EXPECT_FALSE(more_developable(figures(0.90, 0.001, 0.1), figures(0.90, 0.001, 0.1), false));
}

Figures ruled(double flat, double flat_and_ruled, double mean) {
  Figures f = figures(flat, mean, 0.5);
  f.ruled = flat_and_ruled;
  return f;
}

// A whole object: closed, or an open surface whose curvature sums to at
// least pi (kObjectCurvature); a branching one (negative sum) is not.
TEST(Selection, AWholeObjectIsClosedOrWrapsAroundSomething) {
  EXPECT_TRUE(is_object(true, 0.0));   // a torus
  EXPECT_TRUE(is_object(false, 6.2));  // a hand open at the wrist
  EXPECT_TRUE(is_object(false, M_PI));
  EXPECT_FALSE(is_object(false, M_PI - 1e-9));
  EXPECT_FALSE(is_object(false, 0.26));         // a noisy sheet
  EXPECT_FALSE(is_object(false, -2.0 * M_PI));  // a tee of tubes
}

// On a whole object the flat-and-ruled share comes first: a crumpled vertex
// (flat, not ruled) is not developable. On an open sheet it is not read.
TEST(Selection, OnAClosedMeshTheFlatAndRuledShareComesFirst) {
  const Figures crumpled = ruled(0.65, 0.34, 0.06);  // human_woman's flat-by-zigzag result
  const Figures pieces = ruled(0.46, 0.45, 0.057);   // its thinned pieces
  EXPECT_TRUE(more_developable(pieces, crumpled, true));
  EXPECT_FALSE(more_developable(crumpled, pieces, true));
  EXPECT_TRUE(more_developable(crumpled, pieces, false));
  EXPECT_TRUE(more_developable(ruled(0.6, 0.45, 0.05), ruled(0.5, 0.45, 0.05), true));  // then the flat share
  // As developable: one point of flat-and-ruled share, on a closed mesh only.
  EXPECT_TRUE(as_developable(ruled(0.46, 0.44, 0.057), pieces, kInput, true));
  EXPECT_FALSE(as_developable(ruled(0.46, 0.439, 0.057), pieces, kInput, true));
  EXPECT_TRUE(as_developable(ruled(0.46, 0.0, 0.057), pieces, kInput, false));
  // The order: the ruled result is the anchor on a closed mesh, the flat one elsewhere.
  Contestant a, b;
  a.figures = crumpled;
  a.motion = {1.0, 1.0};
  b.figures = pieces;
  b.motion = {2.0, 2.0};
  EXPECT_EQ(select({a, b}, kInput, 1.0, true), 1);
  EXPECT_EQ(select({a, b}, kInput, 1.0, false), 0);
}

// The ruled finish runs on a choice with more than kFlatSlack crumpled
// (flat but not ruled) vertices.
TEST(Selection, TheRuledFinishIsWorthItBeyondOnePointCrumpled) {
  Figures choice = figures(1.0, 1e-9, 1e-8);
  choice.ruled = 0.995;
  EXPECT_FALSE(worth_ruled_finish(choice));
  choice.ruled = 0.985;
  EXPECT_TRUE(worth_ruled_finish(choice));
}

// It can gain only where the ruled polish's measure of flat and ruled is
// lower at the choice than at the input.
TEST(Selection, TheRuledFinishCanGainWhereTheChoiceMeasuresBetterThanTheInput) {
  EXPECT_TRUE(ruled_finish_can_gain(0.1, 0.3));
  EXPECT_FALSE(ruled_finish_can_gain(0.39, 0.27));
  EXPECT_FALSE(ruled_finish_can_gain(0.3, 0.3));
}

// Kept: more than one point more flat and ruled, gained by more than the
// flat share fell, the largest |defect| within 5 % of the choice's and the
// input's larger, no vertex farther than kFinishReach (1.25) times the
// choice's largest move.
TEST(Selection, TheRuledFinishIsKeptWhenMoreRuledAsFlatAndWithinReach) {
  Figures choice = figures(1.0, 1e-9, 1e-8), finished = figures(0.995, 5e-5, 3e-4);
  choice.ruled = 0.88;
  finished.ruled = 0.99;
  const Motion moved{0.010, 0.030};
  EXPECT_TRUE(ruled_finish_kept(finished, {0.012, 0.0375}, choice, moved, kInput));
  EXPECT_FALSE(ruled_finish_kept(finished, {0.012, 0.0376}, choice, moved, kInput));  // beyond the reach
  Figures less_flat = finished;
  less_flat.flat = 0.895;  // 10.5 points less flat for 11 more flat and ruled: kept
  EXPECT_TRUE(ruled_finish_kept(less_flat, {0.012, 0.03}, choice, moved, kInput));
  less_flat.flat = 0.889;  // 11.1 points less flat: curved vertices for crumpled ones
  EXPECT_FALSE(ruled_finish_kept(less_flat, {0.012, 0.03}, choice, moved, kInput));
  Figures spiked = finished;
  spiked.max = 0.526;  // above 1.05 times the input's 0.5
  EXPECT_FALSE(ruled_finish_kept(spiked, {0.012, 0.03}, choice, moved, kInput));
  Figures hardly_ruled = finished;
  hardly_ruled.ruled = 0.889;  // under one point more flat and ruled: within rounding
  EXPECT_FALSE(ruled_finish_kept(hardly_ruled, {0.012, 0.03}, choice, moved, kInput));
}

TEST(Selection, MovesLessComparesTheRmsMotion) {
  EXPECT_TRUE(moves_less({0.9, 5.0}, {1.0, 3.0}));
  EXPECT_FALSE(moves_less({1.0, 1.0}, {1.0, 3.0}));  // strictly less; the largest move does not count
}

TEST(Selection, SmoothEnoughIsAtMostAQuarterRougher) {
  EXPECT_TRUE(smooth_enough(1.25, 1.0));
  EXPECT_FALSE(smooth_enough(1.2501, 1.0));
}

Contestant contestant(double flat, double mean, double max, double rms, double largest, double roughness,
                      bool at_most_as_far = false) {
  Contestant c;
  c.figures = figures(flat, mean, max);
  c.motion = {rms, largest};
  c.roughness = roughness;
  c.at_most_as_far = at_most_as_far;
  return c;
}

// The order: of the contestants smooth enough against the reference, the
// anchor is the most developable; of those as developable as it the one that
// moved least wins; it does not depend on the order they come in.
TEST(Selection, SelectReturnsTheLeastMovingOfThoseAsDevelopableAsTheMostDevelopable) {
  const double reference = 0.010;
  EXPECT_EQ(select({}, kInput, reference, false), -1);
  const Contestant deformed = contestant(0.99, 1e-5, 0.1, 2.0, 6.0, 0.010);
  const Contestant polished_input = contestant(0.985, 2e-5, 0.1, 1.0, 4.0, 0.012);
  const Contestant rough = contestant(0.99, 1e-5, 0.1, 0.5, 2.0, 0.013);      // 1.3 times the reference
  const Contestant less_flat = contestant(0.97, 1e-5, 0.1, 0.1, 1.0, 0.010);  // 2 points below the anchor
  EXPECT_EQ(select({deformed, polished_input}, kInput, reference, false), 1);
  EXPECT_EQ(select({polished_input, deformed}, kInput, reference, false), 0);
  EXPECT_EQ(select({deformed, rough}, kInput, reference, false), 0);
  EXPECT_EQ(select({deformed, rough}, kInput, 0.011, false), 1);
  EXPECT_EQ(select({rough}, kInput, reference, false), -1);  // too rough to take part at all
  EXPECT_EQ(select({deformed, less_flat}, kInput, reference, false), 0);
  EXPECT_EQ(select({less_flat, deformed}, kInput, reference, false), 1);
  // A rough contestant is not the anchor, however developable.
  EXPECT_EQ(select({less_flat, contestant(1.0, 0.0, 0.1, 3.0, 6.0, 0.02)}, kInput, reference, false), 0);
  // A chain does not drift: c is as developable as b, b as a, but c is not as
  // developable as a, the anchor.
  const Contestant a = contestant(0.995, 1e-5, 0.1, 3.0, 6.0, 0.01);
  const Contestant b = contestant(0.988, 1e-5, 0.1, 2.0, 6.0, 0.01);
  const Contestant c = contestant(0.980, 1e-5, 0.1, 1.0, 6.0, 0.01);
  EXPECT_EQ(select({a, b, c}, kInput, reference, false), 1);
  EXPECT_EQ(select({c, b, a}, kInput, reference, false), 1);
  // at_most_as_far: no vertex farther than every other contestant's farthest.
  const Contestant projected = contestant(0.99, 1e-6, 0.1, 1.0, 5.0, 0.01, true);
  EXPECT_EQ(select({deformed, projected}, kInput, reference, false), 1);
  EXPECT_EQ(select({deformed, polished_input, projected}, kInput, reference, false),
            1);  // 5 > 4: out, polished_input wins
  EXPECT_EQ(
      select({deformed, contestant(0.99, 1e-6, 0.1, 0.5, 4.0, 0.01, true), polished_input}, kInput, reference, false),
      1);  // 4 is no farther: it takes part, and moved least
  // Ties in motion go to the anchor, then to the first.
  EXPECT_EQ(select({contestant(0.98, 1e-5, 0.1, 1.0, 1.0, 0.01), deformed, contestant(0.99, 1e-5, 0.1, 1.0, 1.0, 0.01)},
                   kInput, reference, false),
            0);
}

// Rejections count only candidates that scored better than the input; the
// reason of an unchanged run follows from them.
TEST(Selection, RejectionsAndTheUnchangedReason) {
  Rejections r;
  r.record(admit(figures(0.1, 0.02, 0.1, 0.02, 3), kInput, false, false), 0.02, 0.01, 3);  // scored worse: not counted
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::no_better_iterate);
  EXPECT_EQ(unchanged_reason(r, 1.0), UnchangedReason::already_flat);
  r.record(admit(figures(0.9, 0.001, 0.1, 0.001, 3), kInput, false, false), 0.001, 0.01, 3);
  r.record(admit(figures(0.9, 0.001, 0.1, 0.001, 2), kInput, false, false), 0.001, 0.01, 2);
  EXPECT_EQ(r.folded, 2);
  EXPECT_EQ(r.fewest_turned_over, 2);
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::rejected);
  r.record(admit(figures(0.2, 0.01, 0.1, 0.01 * (1 - 0.5e-6)), kInput, false, false), 0.01 * (1 - 0.5e-6), 0.01, 0);
  EXPECT_EQ(r.no_visible_gain, 0);  // a score gain within rounding is no gain at all
  r.record(admit(figures(0.2, 0.01, 0.1, 0.001), kInput, false, false), 0.001, 0.01,
           0);  // broke nothing, gained nothing
  EXPECT_EQ(r.no_visible_gain, 1);
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::no_visible_gain);
  r.developable_patches = true;
  EXPECT_EQ(unchanged_reason(r, 0.2), UnchangedReason::developable_piecewise);
}

// An input flat at every vertex whose results broke nothing but gained within
// the order's slack is already flat, not a result that "made no vertex flat".
TEST(Selection, AFlatInputWithoutAVisibleGainIsAlreadyFlat) {
  Rejections r;
  r.record(admit(figures(1.0, 0.01 * (1 - 0.003), 0.1, 0.001), figures(1.0, 0.01, 0.1, 0.01), false, false), 0.001,
           0.01, 0);
  EXPECT_EQ(r.no_visible_gain, 1);
  EXPECT_EQ(unchanged_reason(r, 1.0), UnchangedReason::already_flat);
  EXPECT_EQ(unchanged_reason(r, 0.99), UnchangedReason::no_visible_gain);
}

TEST(Selection, WorseFiguresFlagEveryFigureThatGotWorse) {
  PipelineStats s;
  s.flat_share_before = 0.6;
  s.flat_share_after = 0.5;
  s.mean_defect_before = 0.01;
  s.mean_defect_after = 0.02;
  s.max_defect_before = 1.0;
  s.max_defect_after = 2.0;
  s.shares_before.ruled = 0.3;
  s.shares_after.ruled = 0.2;
  s.faces_turned_over = 1;
  EXPECT_EQ(worse_figures(s),
            worse_mean_defect | worse_max_defect | worse_flat_share | worse_ruled_share | worse_turned_faces);
  s.flat_share_after = 0.7;
  s.mean_defect_after = 0.005;
  s.max_defect_after = 0.5;
  s.shares_after.ruled = 0.4;
  s.faces_turned_over = 0;
  EXPECT_EQ(worse_figures(s), 0);
}

}  // namespace
}  // namespace developable

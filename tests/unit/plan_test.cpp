// plan.h: which patch alternatives a run makes, on synthetic figures.
#include "pipeline/plan.h"

#include "core/measures.h"
#include "crease_meshes.h"
#include "segmentation/crease_pieces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

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

// The excess of the border defects over a fold's noise: their squares over
// noise^2 times their gains; 0 without defects, infinite without gains.
TEST(Plan, CreaseDefectExcessIsTheDefectsOverWhatTheNoiseGives) {
  EXPECT_DOUBLE_EQ(crease_defect_excess({0.1, -0.1}, {1.0, 1.0}, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(crease_defect_excess({0.2, 0.0}, {1.0, 3.0}, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(crease_defect_excess({}, {}, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(crease_defect_excess({0.0}, {0.0}, 0.1), 0.0);
  EXPECT_EQ(crease_defect_excess({0.1}, {0.0}, 0.1), std::numeric_limits<double>::infinity());
}

// Below kCreaseDefectExcess the crease pieces compete with the other
// alternatives; at and above it they are the result; NaN competes.
TEST(Plan, CreasePiecesCompeteUnlessTheirBordersHoldCurvatureBeyondTheNoise) {
  EXPECT_TRUE(crease_pieces_compete(1.0));
  EXPECT_TRUE(crease_pieces_compete(std::nextafter(kCreaseDefectExcess, 0.0)));
  EXPECT_FALSE(crease_pieces_compete(kCreaseDefectExcess));
  EXPECT_FALSE(crease_pieces_compete(300.0));
  EXPECT_TRUE(crease_pieces_compete(std::numeric_limits<double>::quiet_NaN()));
}

// crease_defect_excess of the vertices where faces on both sides of
// `first_side` meet, with uniform noise of `amplitude` per coordinate.
double excess_with_noise(test::Mesh m, double amplitude, unsigned seed,
                         bool (*first_side)(const test::Mesh&, Eigen::Index)) {
  test::add_noise(m.positions, amplitude, seed);
  const std::vector<bool> interior = interior_vertices(m.positions, m.triangles);
  const Eigen::VectorXd defects = angle_defects(m.positions, m.triangles, interior);
  const Normals normals = face_normals(m.positions, m.triangles);
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  std::vector<double> border_defects, gains;
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    bool sides[2] = {false, false};
    for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) sides[first_side(m, *f) ? 0 : 1] = true;
    if (!(sides[0] && sides[1])) continue;
    border_defects.push_back(defects[v]);
    gains.push_back(angle_defect_noise_gain(m.positions, m.triangles, normals, connectivity, v));
  }
  return crease_defect_excess(border_defects, gains, amplitude / std::sqrt(3.0));
}

// A straight fold is one developable sheet: its fold's defects are the
// noise's, the excess 1.01-1.07 on these seeds and noise levels (the fold's
// vertices answer the noise to first order, 4-18 times the inside's mean
// |defect| on devkit/families.py's curved folds). A mitred pipe's joint
// carries its own curvature: 26-29 at 5 % noise, 170-2800 at 2 and 0.5 %.
TEST(Plan, AFoldsDefectsAreTheNoisesAMitresAreNot) {
  const auto fold_side = [](const test::Mesh& m, Eigen::Index f) {
    double u = 0.0;
    for (int c = 0; c < 3; ++c) u += m.positions(m.triangles(f, c), 1) / 3.0;
    return u < 0.5;
  };
  const auto mitre_side = [](const test::Mesh& m, Eigen::Index f) { return test::below_mitre(m, f, 0.6); };
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (const double noise : {0.005, 0.02, 0.05}) {
      const double h = 1.0 / 40.0;  // the grid's spacing across the fold and along the pipe
      const double fold = excess_with_noise(test::folded_plane(41, 41, 0.9), noise * h, seed, fold_side);
      EXPECT_GT(fold, 0.5) << "seed " << seed << " noise " << noise;
      EXPECT_LT(fold, 1.5) << "seed " << seed << " noise " << noise;
      const double mitre = excess_with_noise(test::mitred_pipe(81, 48, 0.6), noise * h, seed, mitre_side);
      EXPECT_GT(mitre, 4.0 * kCreaseDefectExcess) << "seed " << seed << " noise " << noise;
    }
  }
}

// The other alternatives' result competes with the crease pieces' when it
// made the input one developable sheet within its noise: as developable as a
// flat mesh (99 % flat, a mean |defect| within 1 % of the input's) and moved
// by at most kCreaseMoveNoise times the noise (RMS).
TEST(Plan, OneSheetWithinNoiseIsDevelopableAndMovedNoMoreThanTheNoise) {
  Figures input;
  input.flat = 0.3;
  input.mean = 0.01;
  input.max = 0.2;
  Figures flat;
  flat.flat = 1.0;
  flat.mean = 1e-9;
  flat.max = 1e-7;
  const double noise = 0.001;
  EXPECT_TRUE(one_sheet_within_noise(flat, input, 1.0 * noise, noise));  // a curved fold as one patch
  EXPECT_TRUE(one_sheet_within_noise(flat, input, kCreaseMoveNoise * noise, noise));
  EXPECT_FALSE(one_sheet_within_noise(flat, input, 2.01 * noise, noise));  // moved beyond the noise
  Figures almost = flat;
  almost.flat = 0.99;
  almost.mean = 1e-4;  // 1 % of the input's
  EXPECT_TRUE(one_sheet_within_noise(almost, input, noise, noise));
  almost.flat = 0.973;  // a cup's other alternatives
  EXPECT_FALSE(one_sheet_within_noise(almost, input, noise, noise));
  almost.flat = 1.0;
  almost.mean = 1.01e-4;
  EXPECT_FALSE(one_sheet_within_noise(almost, input, noise, noise));
}

// The other alternatives compete where they show one sheet within the noise,
// or where the crease pieces' run improved nothing.
TEST(Plan, OtherAlternativesCompeteAsOneSheetOrWhereTheCreasePiecesDidNothing) {
  EXPECT_FALSE(others_compete(true, false));
  EXPECT_TRUE(others_compete(true, true));
  EXPECT_TRUE(others_compete(false, false));
  EXPECT_TRUE(others_compete(false, true));
}

}  // namespace
}  // namespace developable

// polish_run.h: the plan's settled stops. Every polish settles at the order's
// slack on the mean |defect| (as_developable cannot tell it from a longer
// one) but a polish of the raw input, which settles at half of it: least
// motion's, and the choice's where nothing was deformed.
#include "pipeline/polish_run.h"

#include "core/mesh_connectivity.h"
#include "pipeline/patches.h"
#include "pipeline/selection.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

struct NoisyCylinder {
  test::Mesh mesh = [] {
    test::Mesh m = test::cylinder(12, 32);
    test::add_noise(m.positions, 0.01, 7);
    return m;
  }();
  VertexFaces table = vertex_faces(mesh.triangles, mesh.positions.rows());
  PipelineOptions options;
  MeasuredInput input =
      measure_input(mesh.positions, mesh.triangles, table,
                    std::vector<bool>(static_cast<size_t>(mesh.positions.rows()), false), options, Clock::now());
  PatchRun run = patch_run(input, one_patch(input.normals, input.areas, options));
};

TEST(PolishPlan, TheRawInputsPolishSettlesAtHalfTheSlackTheOthersAtAllOfIt) {
  const NoisyCylinder cylinder;
  const double mean = cylinder.input.before.mean_abs;
  ASSERT_GT(mean, 0.0);
  const PolishPlan deformed = polish_plan(cylinder.run, true);
  EXPECT_DOUBLE_EQ(deformed.result.settled_defect, kDefectSlack * mean);
  EXPECT_DOUBLE_EQ(deformed.candidates.settled_defect, kDefectSlack * mean);
  EXPECT_DOUBLE_EQ(deformed.raw_input.settled_defect, 0.5 * kDefectSlack * mean);
  // The raw input's polish is a candidate's in everything else.
  EXPECT_EQ(deformed.raw_input.spread_damping, deformed.candidates.spread_damping);
  EXPECT_EQ(deformed.raw_input.direct_rows, deformed.candidates.direct_rows);
  EXPECT_EQ(deformed.raw_input.stall_flat_share, deformed.candidates.stall_flat_share);
  EXPECT_EQ(deformed.raw_input.limit, deformed.candidates.limit);

  // Nothing deformed: the choice's polish is the polish of the raw input;
  // the smoothings' polishes settle as before.
  const PolishPlan undeformed = polish_plan(cylinder.run, false);
  EXPECT_DOUBLE_EQ(undeformed.result.settled_defect, 0.5 * kDefectSlack * mean);
  EXPECT_DOUBLE_EQ(undeformed.candidates.settled_defect, kDefectSlack * mean);
  EXPECT_DOUBLE_EQ(undeformed.raw_input.settled_defect, 0.5 * kDefectSlack * mean);
}

// A deformed result's polish solves its damped systems as least motion's
// candidates do (conjugate gradients above a few thousand rows); only the
// polish of the raw input where nothing was deformed is factored further up.
TEST(PolishPlan, ADeformedResultsPolishSolvesAsTheCandidatesDo) {
  const NoisyCylinder cylinder;
  const PolishPlan deformed = polish_plan(cylinder.run, true);
  EXPECT_EQ(deformed.result.direct_rows, deformed.candidates.direct_rows);
  const PolishPlan undeformed = polish_plan(cylinder.run, false);
  EXPECT_GT(undeformed.result.direct_rows, undeformed.candidates.direct_rows);
}

// LeastMotionAhead polishes the projected start with the options of a
// deformed run before it knows whether anything was deformed: on one patch
// least motion's candidates' options do not depend on it.
TEST(PolishPlan, OnOnePatchTheCandidatesDoNotDependOnTheDeformation) {
  const NoisyCylinder cylinder;
  ASSERT_FALSE(cylinder.run.piecewise);
  const PolishPlan deformed = polish_plan(cylinder.run, true);
  const PolishPlan undeformed = polish_plan(cylinder.run, false);
  for (const auto& [a, b] : {std::pair{&deformed.candidates, &undeformed.candidates},
                             std::pair{&deformed.raw_input, &undeformed.raw_input}}) {
    EXPECT_EQ(a->settled_defect, b->settled_defect);
    EXPECT_EQ(a->spread_damping, b->spread_damping);
    EXPECT_EQ(a->spread_until, b->spread_until);
    EXPECT_EQ(a->stall_flat_share, b->stall_flat_share);
    EXPECT_EQ(a->active_defect, b->active_defect);
    EXPECT_EQ(a->target_defect, b->target_defect);
    EXPECT_EQ(a->max_iterations, b->max_iterations);
    EXPECT_EQ(a->direct_rows, b->direct_rows);
    EXPECT_EQ(a->limit, b->limit);
    EXPECT_EQ(a->crease_guard.active(), b->crease_guard.active());
    EXPECT_EQ(a->give_up_move, b->give_up_move);
    EXPECT_EQ(a->pull_steps, b->pull_steps);
  }
  EXPECT_TRUE(deformed.least_motion && undeformed.least_motion);
}

}  // namespace
}  // namespace developable

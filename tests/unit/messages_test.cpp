// messages.h: the run's words name every figure that got worse and every
// reason a candidate was turned away.
#include "pipeline/messages.h"

#include <gtest/gtest.h>

namespace developable {
namespace {

PipelineStats improved(double ruled_before, double ruled_after) {
  PipelineStats s;
  s.result = ResultKind::improved;
  s.mean_defect_before = 0.01;
  s.mean_defect_after = 0.005;
  s.max_defect_before = s.max_defect_after = 0.1;
  s.shares_before.ruled = ruled_before;
  s.shares_after.ruled = ruled_after;
  return s;
}

TEST(Messages, AnImprovedResultNamesFewerFlatAndRuledVertices) {
  EXPECT_EQ(result_message(improved(0.5, 0.6), Rejections{}), "");
  EXPECT_EQ(result_message(improved(0.5, 0.4), Rejections{}),
            "Improved, but fewer vertices are flat and ruled (50.0 % -> 40.0 %): some flat ones are crumpled into "
            "facets.");
  PipelineStats s = improved(0.5, 0.4);
  s.max_defect_after = 0.2;
  EXPECT_EQ(result_message(s, Rejections{}),
            "Improved, but the largest |defect| grew from 0.1 to 0.2 rad (+100 %), and fewer vertices are flat and "
            "ruled (50.0 % -> 40.0 %): some flat ones are crumpled into facets.");
  s.mean_defect_after = 0.02;
  EXPECT_NE(result_message(s, Rejections{}).find("pieces. Also fewer vertices are flat and ruled"), std::string::npos);
}

TEST(Messages, AnUnchangedRunNamesCrumpledCandidatesAndAdvisesOnce) {
  PipelineStats s;
  s.result = ResultKind::unchanged;
  s.unchanged_reason = UnchangedReason::rejected;
  Rejections r;
  r.ruled_share_fell = 2;
  r.defect_grew = 1;
  EXPECT_EQ(unchanged_message(r, s),
            "Returned the input unchanged: every iterate that lowered the curvature did so by raising the mean "
            "|defect|, crumpling flat vertices into facets (fewer flat and ruled). Try segmentation with more "
            "patches.");
}

}  // namespace
}  // namespace developable

// thinned_pieces.h: on a closed doubly curved mesh both piece sources keep every
// vertex within the move limit, turns no face over, creases no edge inside a
// piece beyond the crease guard, leaves no more crumpled vertices than the
// input had (beyond a small slack), and its result, held to the one rule,
// names its origin; the same input gives the same mesh.
#include "pipeline/thinned_pieces.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "pipeline/patch_alternative.h"
#include "pipeline/patches.h"
#include "pipeline/run_context.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

// An ellipsoid: doubly curved, closed, no symmetry that makes a piece exact.
test::Mesh ellipsoid() {
  test::Mesh m = test::sphere(4);  // 2048 faces
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    m.positions(v, 0) *= 1.6;
    m.positions(v, 2) *= 0.7;
  }
  return m;
}

// Within 1 % of its size a smooth ellipsoid of 2k faces cannot crease by
// the seam angle (it stays one piece); within 4 % it parts.
PipelineOptions four_percent() {
  PipelineOptions options;
  options.max_move = 0.04;
  return options;
}

struct EllipsoidRun {
  test::Mesh mesh = ellipsoid();
  VertexFaces table = vertex_faces(mesh.triangles, mesh.positions.rows());
  PipelineOptions options = four_percent();
  MeasuredInput input =
      measure_input(mesh.positions, mesh.triangles, table,
                    std::vector<bool>(static_cast<size_t>(mesh.positions.rows()), false), options, Clock::now());
};

VertexShares shares_of(const Positions& p, const Triangles& t, const VertexFaces& table,
                       const std::vector<bool>& interior) {
  const Eigen::VectorXd defects = angle_defects(p, t, interior);
  return vertex_shares(defects, ruling_spreads(p, t, face_normals(p, t), table, interior), interior);
}

TEST(ThinnedPieces, KeepsTheLimitTheFacesAndThePiecesUncreased) {
  const EllipsoidRun run;
  const MeasuredInput& input = run.input;
  ASSERT_TRUE(input.closed);
  NormalGuidedDeformation thinning = thinning_deformation(input);
  const Positions whole = thin_whole(input, thinning, {});
  for (Eigen::Index v = 0; v < input.positions.rows(); ++v)
    EXPECT_LE((whole.row(v) - input.positions.row(v)).norm(), kThinningLimitShare * input.limit * (1.0 + 1e-12));
  for (PieceSource source : {PieceSource::creases, PieceSource::segmentation}) {
    const ThinnedPieces thinned = thinned_pieces(input, whole, source, thinning.sharing_factor(), {});
    ASSERT_EQ(thinned.positions.rows(), input.positions.rows());
    ASSERT_EQ(static_cast<Eigen::Index>(thinned.pieces.size()), input.triangles.rows());
    EXPECT_GT(thinned.count, 1);
    EXPECT_EQ(thinned.count, 1 + *std::max_element(thinned.pieces.begin(), thinned.pieces.end()));
    for (Eigen::Index v = 0; v < input.positions.rows(); ++v)
      EXPECT_LE((thinned.positions.row(v) - input.positions.row(v)).norm(), input.limit * (1.0 + 1e-12));
    const Normals after = face_normals(thinned.positions, input.triangles);
    EXPECT_TRUE(turned_over_faces(after, input.normals).empty());
    const CreaseGuard guard(input.triangles, input.normals, thinned.pieces, kSegmentedCreaseGrowth);
    EXPECT_TRUE(guard.creased_faces(after).empty());
    const VertexShares before = shares_of(input.positions, input.triangles, run.table, input.measured.interior);
    const VertexShares now = shares_of(thinned.positions, input.triangles, run.table, input.measured.interior);
    EXPECT_LE(now.crumpled, before.crumpled + kCrumpleSlack);
    EXPECT_GT(now.ruled, before.ruled);  // flat and ruled share
    // Deterministic, and the shared factor steps as a factor of its own.
    EXPECT_EQ(thinned_pieces(input, whole, source, thinning_deformation(input), {}).positions, thinned.positions);
  }
}

TEST(ThinnedPieces, ItsAlternativeIsHeldToTheOneRule) {
  const EllipsoidRun run;
  NormalGuidedDeformation thinning = thinning_deformation(run.input);
  const PipelineResult r = run_thinned_alternative(run.input, thin_whole(run.input, thinning, {}),
                                                   PieceSource::segmentation, thinning.sharing_factor(), {});
  EXPECT_EQ(static_cast<Eigen::Index>(r.patch_ids.size()), run.input.triangles.rows());
  if (r.stats.result == ResultKind::improved) {
    EXPECT_EQ(r.stats.origin, ResultOrigin::thinned_pieces);
    EXPECT_GE(r.stats.flat_share_after, r.stats.flat_share_before);
    // An object's mean |defect| is held inside its pieces (admit): the
    // curvature gathers on the seams.
    const std::vector<bool> border =
        patch_border_vertices(run.input.triangles, r.patch_ids, run.input.positions.rows());
    double before = 0.0, after = 0.0;
    for (size_t v = 0; v < border.size(); ++v)
      if (r.interior[v] && !border[v]) {
        before += std::abs(r.defect_before[static_cast<Eigen::Index>(v)]);
        after += std::abs(r.defect_after[static_cast<Eigen::Index>(v)]);
      }
    EXPECT_LE(after, (1.0 + kClosedMeshGrowth) * before);
    EXPECT_EQ(r.stats.faces_turned_over, 0);
  } else {
    EXPECT_EQ(r.stats.origin, ResultOrigin::input);
    EXPECT_EQ(r.positions, run.input.positions);
  }
}

TEST(ThinnedPieces, WithoutAMoveLimitReturnsTheInput) {
  test::Mesh m = ellipsoid();
  const VertexFaces table = vertex_faces(m.triangles, m.positions.rows());
  PipelineOptions options;
  options.tolerance = 0.0;
  options.max_move = 0.0;
  const MeasuredInput input =
      measure_input(m.positions, m.triangles, table, std::vector<bool>(static_cast<size_t>(m.positions.rows()), false),
                    options, Clock::now());
  NormalGuidedDeformation thinning = thinning_deformation(input);
  const Positions whole = thin_whole(input, thinning, {});
  EXPECT_EQ(whole, m.positions);
  const ThinnedPieces thinned = thinned_pieces(input, whole, PieceSource::creases, std::move(thinning), {});
  EXPECT_EQ(thinned.positions, m.positions);
  EXPECT_EQ(thinned.count, 1);
}

}  // namespace
}  // namespace developable

// crease_pieces.h: a noisy mitred pipe comes back as its two cylinders, each
// fitting its cone within the noise, the noise read back from the fits; a
// noisy fold as its two planes; a noisy cylinder or plane as one piece; a
// mitred pipe taken as one piece parted by a plane along its mitre; the same
// pieces on any thread count.
#include "segmentation/crease_pieces.h"

#include "segmentation/crease_strength.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "crease_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

CreasePieces pieces_of(const test::Mesh& m, int threads = 0) {
  return crease_pieces(m.positions, m.triangles, face_normals(m.positions, m.triangles),
                       face_areas(m.positions, m.triangles), vertex_faces(m.triangles, m.positions.rows()), threads);
}

double worst(const CreasePieces& p) { return *std::max_element(p.fit.begin(), p.fit.end()); }

TEST(CreasePieces, ANoisyMitredPipeComesBackAsItsTwoCylinders) {
  for (double degrees : {20.0, 45.0}) {
    for (unsigned seed : {1u, 2u}) {
      const double turn = degrees * M_PI / 180.0;
      const int cols = 48;
      const double amplitude = 0.02 * 2.0 * M_PI / cols;  // 2 % of the spacing around
      test::Mesh m = test::mitred_pipe(33, cols, turn);
      test::add_noise(m.positions, amplitude, seed);
      const CreasePieces p = pieces_of(m);
      ASSERT_EQ(p.count, 2) << degrees << " degrees, seed " << seed;
      ASSERT_EQ(p.fit.size(), 2u);
      EXPECT_LE(worst(p), kCreasePieceFit);
      // Every face on its own cylinder's piece, but for a few along the mitre
      // at the sides, where the cylinders are tangent and either fits.
      const int first = p.ids[0];
      int astray = 0;
      for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
        astray += (p.ids[static_cast<size_t>(f)] == first) !=
                  (test::below_mitre(m, f, turn) == test::below_mitre(m, 0, turn));
      EXPECT_LT(astray, 0.005 * m.triangles.rows()) << degrees << " degrees, seed " << seed;
      // The noise the fits leave: a / sqrt(3) along the normal.
      EXPECT_NEAR(p.cone_noise, amplitude / std::sqrt(3.0), 0.3 * amplitude / std::sqrt(3.0));
      EXPECT_EQ(p.cut.size(), mesh_edges(m.triangles, vertex_faces(m.triangles, m.positions.rows())).size());
    }
  }
}

TEST(CreasePieces, ANoisyFoldComesBackAsItsTwoPlanes) {
  const int rows = 21, cols = 21;
  test::Mesh m = test::folded_plane(rows, cols, 0.3);
  test::add_noise(m.positions, 0.03 / (cols - 1), 9);
  const CreasePieces p = pieces_of(m);
  ASSERT_EQ(p.count, 2);
  EXPECT_LE(worst(p), kCreasePieceFit);
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const bool low = m.triangles(f, 0) / cols < (rows - 1) / 2 || m.triangles(f, 1) / cols < (rows - 1) / 2 ||
                     m.triangles(f, 2) / cols < (rows - 1) / 2;
    EXPECT_EQ(p.ids[static_cast<size_t>(f)], low ? 0 : 1);
  }
}

TEST(CreasePieces, OneSheetIsOnePiece) {
  test::Mesh cylinder = test::cylinder(21, 32, 1.0);
  test::add_noise(cylinder.positions, 0.03 * 2.0 * M_PI / 32, 2);
  const CreasePieces p = pieces_of(cylinder);
  EXPECT_EQ(p.count, 1);
  EXPECT_LE(worst(p), kCreasePieceFit);
  test::Mesh plane = test::plane(25, 25);
  test::add_noise(plane.positions, 0.05 / 24, 2);
  EXPECT_EQ(pieces_of(plane).count, 1);
  // Without noise a cylinder fits its cone exactly.
  const CreasePieces exact = pieces_of(test::cylinder(21, 32, 1.0));
  EXPECT_EQ(exact.count, 1);
  EXPECT_LT(exact.fit[0], 1e-3);
}

// Step 5: a mitred pipe taken as one piece (its mitre line missed) is parted
// by a plane along the mitre, whatever the turn and the noise's seed.
TEST(CreasePieces, APlaneFindsTheMitreOfTwoCylindersTakenAsOne) {
  for (double degrees : {15.0, 30.0, 60.0}) {
    for (unsigned seed : {3u, 4u}) {
      const double turn = degrees * M_PI / 180.0;
      const int cols = 40;
      test::Mesh m = test::mitred_pipe(31, cols, turn);
      test::add_noise(m.positions, 0.04 * 2.0 * M_PI / cols, seed);  // 4 % of the spacing around
      std::vector<int> all(static_cast<size_t>(m.triangles.rows()));
      for (size_t f = 0; f < all.size(); ++f) all[f] = static_cast<int>(f);
      const std::vector<bool> beyond =
          plane_parting(all, m.positions, m.triangles, face_normals(m.positions, m.triangles),
                        face_areas(m.positions, m.triangles), 10);
      ASSERT_EQ(beyond.size(), all.size());
      // The plane's side agrees with the mitre's on every face but a few
      // beside it (those settle_borders moves to their cylinder).
      const bool first_beyond = beyond[0] != test::below_mitre(m, 0, turn);
      int astray = 0;
      for (size_t f = 0; f < all.size(); ++f)
        astray += (beyond[f] != test::below_mitre(m, static_cast<Eigen::Index>(f), turn)) != first_beyond;
      EXPECT_LT(astray, 0.02 * m.triangles.rows()) << degrees << " degrees, seed " << seed;
    }
  }
}

TEST(CreasePieces, NoPlaneWhenEitherSideWouldBeTooSmall) {
  const test::Mesh m = test::mitred_pipe(5, 8, 0.5);
  const std::vector<int> some = {0, 1, 2, 3, 4, 5};
  EXPECT_TRUE(plane_parting(some, m.positions, m.triangles, face_normals(m.positions, m.triangles),
                            face_areas(m.positions, m.triangles), 4)
                  .empty());
}

TEST(CreasePieces, AnyThreadCountGivesTheSamePieces) {
  test::Mesh m = test::mitred_pipe(41, 64, 0.5);
  test::add_noise(m.positions, 0.002, 11);
  const CreasePieces one = pieces_of(m, 1), four = pieces_of(m, 4);
  EXPECT_EQ(one.ids, four.ids);
  EXPECT_EQ(one.fit, four.fit);
  EXPECT_EQ(one.cone_noise, four.cone_noise);
}

}  // namespace
}  // namespace developable

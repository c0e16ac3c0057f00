// crease_strength.h: every edge listed once with its faces; a fold jumps by
// its angle and nothing beside it does, a cylinder's facets make no jump;
// the noise is read off the mesh in the caller's units and scales with it;
// a noisy fold stands out against its noise; any thread count gives the
// same scores.
#include "segmentation/crease_strength.h"

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "crease_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <utility>

namespace developable {
namespace {

struct Scored {
  std::vector<MeshEdge> edges;
  CreaseStrengths strengths;
};

Scored score(const test::Mesh& m, int threads = 0) {
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  Scored s;
  s.edges = mesh_edges(m.triangles, connectivity);
  s.strengths = crease_strengths(m.positions, m.triangles, face_normals(m.positions, m.triangles), connectivity,
                                 s.edges, threads);
  return s;
}

// The grid row of a vertex of test::grid(rows, cols, ...).
int row_of(int v, int cols) { return v / cols; }

// crease_lines.h's kLineScore, without depending on that stage here.
constexpr double kLoudScore = 3.0;

TEST(CreaseStrength, EveryEdgeListedOnceWithTheFacesBesideIt) {
  const test::Mesh m = test::plane(4, 5);
  const VertexFaces connectivity = vertex_faces(m.triangles, m.positions.rows());
  const std::vector<MeshEdge> edges = mesh_edges(m.triangles, connectivity);
  EXPECT_EQ(edges.size(), 4u * 4 + 5 * 3 + 3 * 4);  // rows, columns, diagonals
  std::set<std::pair<int, int>> seen;
  int boundary = 0;
  for (const MeshEdge& e : edges) {
    EXPECT_LT(e.a, e.b);
    EXPECT_TRUE(seen.insert({e.a, e.b}).second);
    for (int f : {e.f, e.g}) {
      if (f < 0) continue;
      std::set<int> corners{m.triangles(f, 0), m.triangles(f, 1), m.triangles(f, 2)};
      EXPECT_TRUE(corners.count(e.a) && corners.count(e.b));
    }
    boundary += e.g < 0;
  }
  EXPECT_EQ(boundary, 2 * 3 + 2 * 4);
}

TEST(CreaseStrength, AFoldJumpsByItsAngleAndNothingAwayFromItDoes) {
  const int rows = 11, cols = 9, fold = (rows - 1) / 2;
  const double angle = 0.5;
  const Scored s = score(test::folded_plane(rows, cols, angle));
  int on_fold = 0, away = 0;
  for (size_t e = 0; e < s.edges.size(); ++e) {
    const int ra = row_of(s.edges[e].a, cols), rb = row_of(s.edges[e].b, cols);
    const double jump = s.strengths.jump[static_cast<Eigen::Index>(e)];
    if (ra == fold && rb == fold && s.edges[e].g >= 0 && s.strengths.score[static_cast<Eigen::Index>(e)] > 0.0) {
      EXPECT_NEAR(jump, angle, 1e-9);  // each side one plane: the fits are exact
      ++on_fold;
    } else if (std::min(std::abs(ra - fold), std::abs(rb - fold)) >= 3) {
      EXPECT_LT(jump, 1e-9);
      ++away;
    }
  }
  EXPECT_GE(on_fold, cols - 3);  // the edges at the ends have too few faces on a side
  EXPECT_GT(away, 0);
}

TEST(CreaseStrength, ACylindersFacetsHardlyJump) {
  // Away from its open ends (rows 2-6 of 9), a quarter of the facet angle at
  // most, where the rulings' dihedral angles are the whole facet angle.
  const int rows = 9, cols = 24;
  const Scored s = score(test::cylinder(rows, cols));
  const double facet = 2.0 * M_PI / cols;
  double largest = 0.0;
  for (size_t e = 0; e < s.edges.size(); ++e) {
    const int ra = row_of(s.edges[e].a, cols), rb = row_of(s.edges[e].b, cols);
    if (std::min(ra, rb) >= 2 && std::max(ra, rb) <= rows - 3)
      largest = std::max(largest, s.strengths.jump[static_cast<Eigen::Index>(e)]);
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(largest, 0.25 * facet);
}

TEST(CreaseStrength, TheNoiseIsReadOffTheMeshInItsUnits) {
  // Uniform noise of amplitude a per coordinate: its standard deviation along
  // the normal is a / sqrt(3).
  const int n = 31;
  const double spacing = 1.0 / (n - 1), a = 0.02 * spacing;
  test::Mesh m = test::plane(n, n);
  test::add_noise(m.positions, a, 5);
  const double noise = score(m).strengths.noise;
  EXPECT_NEAR(noise, a / std::sqrt(3.0), 0.25 * a / std::sqrt(3.0));
  // Twice the noise, or the mesh twice the size: twice the estimate.
  test::Mesh louder = test::plane(n, n);
  test::add_noise(louder.positions, 2.0 * a, 5);
  EXPECT_NEAR(score(louder).strengths.noise / noise, 2.0, 0.1);
  test::Mesh larger = m;
  larger.positions *= 2.0;
  EXPECT_NEAR(score(larger).strengths.noise / noise, 2.0, 1e-9);
  // A noise-free plane: the floor.
  const test::Mesh exact = test::plane(n, n);
  EXPECT_NEAR(score(exact).strengths.noise, kNoiseFloor * spacing, 0.5 * kNoiseFloor * spacing);
}

TEST(CreaseStrength, ANoisyFoldStandsOutAgainstItsNoise) {
  const int rows = 21, cols = 21, fold = (rows - 1) / 2;
  test::Mesh m = test::folded_plane(rows, cols, 0.3);
  test::add_noise(m.positions, 0.03 / (cols - 1), 7);  // 3 % of the spacing
  const Scored s = score(m);
  int away = 0, loud = 0;
  for (size_t e = 0; e < s.edges.size(); ++e) {
    const auto k = static_cast<Eigen::Index>(e);
    const int ra = row_of(s.edges[e].a, cols), rb = row_of(s.edges[e].b, cols);
    if (ra == fold && rb == fold && s.strengths.score[k] > 0.0) {
      EXPECT_GT(s.strengths.score[k], 2.0 * kLoudScore);
      EXPECT_NEAR(s.strengths.jump[k], 0.3, 0.1);
    }
    if (std::min(std::abs(ra - fold), std::abs(rb - fold)) >= 3 && s.strengths.score[k] > 0.0) {
      ++away;
      loud += s.strengths.score[k] > kLoudScore;
    }
  }
  // Noise alone (uniform, on faces that share corners) puts some 7 % of the
  // edges above 3, more than a Gaussian's 1 %: lines, not edges, tell.
  EXPECT_LT(loud, 0.1 * away);
}

TEST(CreaseStrength, SliversThatTiltAlikeStayInTheFits) {
  // A pipe of slivers, 12 facets around and cells some six times as long
  // around as along: the noise read off it is 2.8 times the noise's own (what
  // the facets make of the fits), which tilts every sliver by more than
  // kUnreliableTilt. They tilt alike, so they stay, and the edges are scored.
  test::Mesh m = test::mitred_pipe(61, 12, 0.5);
  test::add_noise(m.positions, 0.02 * 2.0 * M_PI / 12, 3);
  const Scored s = score(m);
  int tilted = 0;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const double tilt = std::sqrt(barycentric_gradients(m.positions, m.triangles, f).squaredNorm() / 2.0);
    tilted += s.strengths.noise * tilt > kUnreliableTilt;
  }
  EXPECT_GT(tilted, 0.9 * m.triangles.rows());
  int scored = 0;
  for (Eigen::Index e = 0; e < s.strengths.score.size(); ++e) scored += s.strengths.score[e] > 0.0;
  EXPECT_GT(scored, 0.9 * s.strengths.score.size());
}

TEST(CreaseStrength, AnyThreadCountGivesTheSameScores) {
  test::Mesh m = test::mitred_pipe(41, 64, 0.5);
  test::add_noise(m.positions, 0.002, 11);
  const Scored one = score(m, 1), four = score(m, 4);
  EXPECT_EQ(one.strengths.noise, four.strengths.noise);
  EXPECT_TRUE(one.strengths.score == four.strengths.score);
  EXPECT_TRUE(one.strengths.jump == four.strengths.jump);
}

TEST(CreaseStrength, FacesWithoutAreaGetNoScore) {
  // The middle vertex moved onto its left neighbour: the two faces holding
  // both lose their area, and the edge between them its length.
  test::Mesh m = test::plane(9, 9);
  m.positions.row(40) = m.positions.row(39);
  const Scored s = score(m);
  for (size_t e = 0; e < s.edges.size(); ++e) {
    const MeshEdge& edge = s.edges[e];
    if ((edge.a == 39 && edge.b == 40) || (edge.a == 40 && edge.b == 39)) {
      EXPECT_EQ(s.strengths.score[static_cast<Eigen::Index>(e)], 0.0);
    }
  }
}

}  // namespace
}  // namespace developable

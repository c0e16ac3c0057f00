// Flat patterns: the rule that keeps a piece whole (flatten.h), the chord a
// piece is split along (piece_split.h), the seams' smoothed curves
// (seam_curves.h) and the labels' room (pattern_labels.h).
#include "pattern/piece_split.h"
#include "core/measures.h"
#include "pattern/flatten.h"
#include "pattern/pattern_labels.h"
#include "pattern/seam_curves.h"
#include "pattern/unfold.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>

namespace developable {
namespace {

using namespace unfolding;

TEST(StrainLimit, FlatPiecesMayStrainAsMuchAsTheirCurvatureNeeds) {
  PieceDefects flat;
  flat.largest = 0.9 * kFlatDefect;
  flat.sum = 0.3;
  EXPECT_NEAR(strain_limit(0.0025, flat), 0.3 / (2 * M_PI), 1e-15);
  flat.sum = 1e-4;  // the tolerance is the floor
  EXPECT_EQ(strain_limit(0.0025, flat), 0.0025);
  PieceDefects nearly = flat;  // one vertex at 3e-3 rad: it needs 4.8e-4, under the tolerance
  nearly.largest = 3e-3;
  nearly.curved_sum = 3e-3;
  nearly.sum = 0.3;
  EXPECT_NEAR(strain_limit(0.0025, nearly), 0.3 / (2 * M_PI), 1e-15);
  PieceDefects curved = nearly;  // vertices that are not flat needing more than the tolerance
  curved.curved_sum = 2 * M_PI * 0.0026;
  EXPECT_EQ(strain_limit(0.0025, curved), 0.0025);
  EXPECT_TRUE(std::isinf(strain_limit(0.0, curved)));
}

// A cone of `rings` rings and `sectors` sectors around its apex (vertex 0):
// every vertex but the apex flat, the apex's defect 2 pi (1 - sin(half angle)).
test::Mesh apex_cone(int rings, int sectors) {
  test::Mesh m;
  m.positions.resize(1 + rings * sectors, 3);
  m.positions.row(0) << 0, 0, 1;
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const double a = 2 * M_PI * s / sectors, t = static_cast<double>(r) / rings;
      m.positions.row(1 + (r - 1) * sectors + s) << t * std::cos(a), t * std::sin(a), 1 - t;
    }
  std::vector<std::array<int, 3>> tris;
  for (int s = 0; s < sectors; ++s) tris.push_back({0, 1 + s, 1 + (s + 1) % sectors});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const int a = 1 + (r - 1) * sectors + s, b = 1 + (r - 1) * sectors + (s + 1) % sectors;
      tris.push_back({a, a + sectors, b + sectors});
      tris.push_back({a, b + sectors, b});
    }
  m.triangles.resize(tris.size(), 3);
  for (size_t f = 0; f < tris.size(); ++f) m.triangles.row(f) << tris[f][0], tris[f][1], tris[f][2];
  return m;
}

TEST(Unfold, AConeApexGetsADartNotASplit) {
  // The apex (defect 2 pi (1 - 1/sqrt 2) = 1.84 rad) cannot lie flat inside
  // a piece; a dart from it to the border opens it, and the cone, flat
  // everywhere else, is one exact piece.
  const auto m = apex_cone(6, 24);
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.split_count, 0);
  EXPECT_EQ(r.pieces[0].cut_edges, 6);  // apex to rim along one ruling
  EXPECT_LT(r.pieces[0].max_strain, 1e-9);
  ASSERT_EQ(r.seams.size(), 1u);
  EXPECT_TRUE(r.seams[0].cut);
}

TEST(PieceDefects, InnerVerticesOnly) {
  const auto m = test::cylinder(6, 20);  // closed band: every vertex on a border ring or flat
  LocalPiece piece = local_piece(m.triangles,
                                 [&] {
                                   std::vector<int> f(m.triangles.rows());
                                   std::iota(f.begin(), f.end(), 0);
                                   return f;
                                 }(),
                                 {});
  const EdgeTable edges = edge_table(piece.tris);
  const PieceDefects d =
      piece_defects(m.positions, piece, piece_topology(piece, edges, std::vector<char>(edges.keys.size(), 0)));
  EXPECT_TRUE(d.flat());
  EXPECT_LT(d.sum, 1e-9);
}

std::vector<int> all_faces(const test::Mesh& m) {
  std::vector<int> f(m.triangles.rows());
  std::iota(f.begin(), f.end(), 0);
  return f;
}

// Whether a set of faces is connected across shared edges.
bool connected(const Triangles& triangles, const std::vector<int>& faces) {
  const LocalPiece piece = local_piece(triangles, faces, {});
  const EdgeTable edges = edge_table(piece.tris);
  std::vector<int> seen(faces.size(), 0), stack{0};
  seen[0] = 1;
  size_t count = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (int k = 0; k < 3; ++k) {
      const auto& uses = edges.uses[edges.of_face_edge[3 * f + k]];
      if (uses[1] < 0) continue;
      const int g = (uses[0] / 3 == f ? uses[1] : uses[0]) / 3;
      if (!seen[g]) seen[g] = 1, ++count, stack.push_back(g);
    }
  }
  return count == faces.size();
}

TEST(SplitAlongChord, TwoConnectedSidesNearTheMiddle) {
  const auto m = test::plane(9, 21);  // a long plane: the chord crosses it near its middle
  const LocalPiece piece = local_piece(m.triangles, all_faces(m), {});
  const auto sides = split_along_chord(m.positions, piece, SplitThrough::middle);
  ASSERT_FALSE(sides[0].empty());
  ASSERT_FALSE(sides[1].empty());
  EXPECT_EQ(sides[0].size() + sides[1].size(), static_cast<size_t>(m.triangles.rows()));
  EXPECT_TRUE(connected(m.triangles, sides[0]));
  EXPECT_TRUE(connected(m.triangles, sides[1]));
  const double share = static_cast<double>(sides[0].size()) / m.triangles.rows();
  EXPECT_GT(share, 0.25);
  EXPECT_LT(share, 0.75);
}

TEST(SplitAlongChord, ThroughTheVertexThatIsNotFlat) {
  auto m = test::plane(11, 11);
  // Lift one inner vertex: a cone point; the chord must run through it.
  int lifted = -1;
  double best = 1e9;
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double d = (m.positions.row(v).head<2>() - Eigen::RowVector2d(0.3, 0.6)).norm();
    if (d < best) best = d, lifted = static_cast<int>(v);
  }
  m.positions(lifted, 2) += 0.05;
  const LocalPiece piece = local_piece(m.triangles, all_faces(m), {});
  const auto sides = split_along_chord(m.positions, piece, SplitThrough::largest_defect);
  ASSERT_FALSE(sides[1].empty());
  std::array<bool, 2> touches{false, false};
  for (int s = 0; s < 2; ++s)
    for (int f : sides[s])
      for (int k = 0; k < 3; ++k) touches[s] = touches[s] || m.triangles(f, k) == lifted;
  EXPECT_TRUE(touches[0] && touches[1]);  // the vertex is on the chord
}

TEST(Zigzag, StaircaseYesSmoothCurveAndCornerNo) {
  const std::vector<double> stairs{0, 0.78, -0.78, 0.78, -0.78, 0.78, 0};
  const auto z = zigzag_points(stairs, false);
  EXPECT_EQ(std::count(z.begin(), z.end(), 1), 5);
  EXPECT_EQ(z.front(), 0);
  EXPECT_EQ(z.back(), 0);
  const std::vector<double> arc(9, 0.2);  // one sense: a smooth curve
  const auto a = zigzag_points(arc, false);
  EXPECT_EQ(std::count(a.begin(), a.end(), 1), 0);
  const std::vector<double> corner{0, 0, 0, 1.57, 0, 0, 0};
  const auto c = zigzag_points(corner, false);
  EXPECT_EQ(std::count(c.begin(), c.end(), 1), 0);
}

TEST(SmoothPolyline, MovesOnlyTheMovablePointsAndIsLinear) {
  std::vector<Eigen::Vector2d> p{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {3, 2}};
  const std::vector<char> movable{0, 1, 1, 1, 1, 0};
  std::vector<Eigen::Vector2d> q = p;
  smooth_polyline(q, movable, false);
  EXPECT_EQ(q.front(), p.front());
  EXPECT_EQ(q.back(), p.back());
  // Nearer the diagonal than the stairs were.
  for (size_t i = 1; i + 1 < q.size(); ++i)
    EXPECT_LT(std::abs(q[i].x() - q[i].y() - 0.5), std::abs(p[i].x() - p[i].y() - 0.5) + 1e-12);
  // A similarity of the input gives the same similarity of the output.
  std::vector<Eigen::Vector2d> r = p;
  for (auto& x : r) x = Eigen::Rotation2Dd(0.7) * (2.0 * x) + Eigen::Vector2d(3, -1);
  smooth_polyline(r, movable, false);
  for (size_t i = 0; i < q.size(); ++i)
    EXPECT_LT((r[i] - (Eigen::Rotation2Dd(0.7) * (2.0 * q[i]) + Eigen::Vector2d(3, -1))).norm(), 1e-12);
}

TEST(LabelSpace, BoxesThatOverlapAreRefused) {
  LabelSpace space(5.0);
  const auto a = label_box("12", Eigen::Vector2d(10, 10), 3.0, 0.0);
  EXPECT_NEAR(a.sizes().x(), 2 * kGlyphWidth * 3.0, 1e-12);
  EXPECT_TRUE(space.free(a));
  space.add(a);
  EXPECT_FALSE(space.free(label_box("7", Eigen::Vector2d(12, 11), 2.0, 0.0)));
  EXPECT_TRUE(space.free(label_box("7", Eigen::Vector2d(30, 10), 2.0, 0.0)));
  const auto turned = label_box("12", Eigen::Vector2d(0, 0), 3.0, 90.0);
  EXPECT_NEAR(turned.sizes().y(), 2 * kGlyphWidth * 3.0, 1e-9);
}

TEST(Unfold, APlateWithAHoleIsOnePieceWithoutASlit) {
  const auto m = test::plane(13, 13);
  // Drop the faces around the centre: a hole.
  std::vector<int> kept;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
    const Eigen::RowVector3d c =
        (m.positions.row(m.triangles(f, 0)) + m.positions.row(m.triangles(f, 1)) + m.positions.row(m.triangles(f, 2))) /
        3;
    if ((c.head<2>() - Eigen::RowVector2d(0.5, 0.5)).norm() > 0.2) kept.push_back(static_cast<int>(f));
  }
  Triangles holed(kept.size(), 3);
  for (size_t i = 0; i < kept.size(); ++i) holed.row(i) = m.triangles.row(kept[i]);
  const UnfoldResult r = unfold(m.positions, holed, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.pieces[0].cut_edges, 0);
  EXPECT_TRUE(r.seams.empty());
  ASSERT_EQ(r.pieces[0].outline.size(), 2u);  // the outer loop, then the hole
  EXPECT_GT(r.pieces[0].outline[0].size(), r.pieces[0].outline[1].size());
  EXPECT_LT(r.pieces[0].max_strain, 1e-9);
}

}  // namespace
}  // namespace developable

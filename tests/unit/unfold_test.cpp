// Flat patterns: unfold.h, pattern_layout.h and pattern_svg.h from the
// promises in their headers, on exact meshes.
#include "pattern/unfold.h"
#include "pattern/pattern_layout.h"
#include "pattern/pattern_svg.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace developable {
namespace {

double max_edge_strain(const test::Mesh& m, const UnfoldResult& r) {
  double worst = 0.0;
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const double l3 = (m.positions.row(m.triangles(f, k)) - m.positions.row(m.triangles(f, (k + 1) % 3))).norm();
      const double l2 = (r.corners.row(3 * f + k) - r.corners.row(3 * f + (k + 1) % 3)).norm();
      worst = std::max(worst, std::abs(l2 / l3 - 1.0));
    }
  return worst;
}

TEST(Unfold, ClosedCylinderIsCutOnceAndLaidFlatIsometrically) {
  const auto m = test::cylinder(8, 24);
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.pieces[0].cut_edges, 7);  // one ruling across the 8 rings
  ASSERT_EQ(r.seams.size(), 1u);
  EXPECT_TRUE(r.seams[0].cut);
  EXPECT_EQ(r.seams[0].piece_a, 0);
  EXPECT_EQ(r.seams[0].piece_b, 0);
  EXPECT_LT(max_edge_strain(m, r), 1e-9);
  EXPECT_NEAR(r.pieces[0].max_strain, max_edge_strain(m, r), 1e-15);
  EXPECT_NEAR(r.pieces[0].area_change, 0.0, 1e-12);
  // The flat band is a rectangle: outline = 2 (circumference + height).
  const double side = 2.0 * std::sin(M_PI / 24);
  EXPECT_NEAR(r.pieces[0].outline_length, 2.0 * (24 * side + 1.0), 1e-9);
}

TEST(Unfold, PatchesBecomePiecesAndTheirBorderIsOneSeam) {
  const auto m = test::plane(6, 7);
  std::vector<int> patches(m.triangles.rows());
  for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
    patches[f] =
        (m.positions.row(m.triangles(f, 0)) + m.positions.row(m.triangles(f, 1)) + m.positions.row(m.triangles(f, 2)))
                        .x() /
                    3.0 <
                0.5
            ? 0
            : 3;
  const UnfoldResult r = unfold(m.positions, m.triangles, patches);
  ASSERT_EQ(r.pieces.size(), 2u);
  ASSERT_EQ(r.seams.size(), 1u);
  EXPECT_FALSE(r.seams[0].cut);
  EXPECT_NEAR(r.seams[0].length_a, r.seams[0].length_3d, 1e-12);
  EXPECT_NEAR(r.seams[0].length_b, r.seams[0].length_3d, 1e-12);
}

TEST(Unfold, RefusesBadPatchIds) {
  const auto m = test::plane();
  EXPECT_THROW(unfold(m.positions, m.triangles, {1, 2}), EngineError);
  EXPECT_THROW(unfold(m.positions, m.triangles, std::vector<int>(m.triangles.rows(), -1)), EngineError);
}

TEST(PatternLayout, PiecesStayInsideTheMarginsAtTrueScale) {
  const auto m = test::cone();
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  LayoutOptions o;
  o.scale = 0.0;  // automatic
  const Layout layout = layout_pattern(r, m.triangles, o);
  EXPECT_EQ(layout.sheets, 1);
  EXPECT_GT(layout.options.scale, 0.0);
  EXPECT_LE(layout.options.scale, 1.0);
  const Eigen::Vector2d lo = layout.corners.colwise().minCoeff(), hi = layout.corners.colwise().maxCoeff();
  EXPECT_GE(lo.minCoeff(), o.margin - 1e-9);
  EXPECT_LE(hi.x(), o.sheet_width - o.margin + 1e-9);
  EXPECT_LE(hi.y(), o.sheet_height - o.margin - o.footer + 1e-9);
  // Distances on the sheet are model distances times scale times unit.
  const double mm = layout.options.scale * o.unit_mm;
  EXPECT_NEAR((layout.corners.row(0) - layout.corners.row(1)).norm(), (r.corners.row(0) - r.corners.row(1)).norm() * mm,
              1e-9);
  ASSERT_EQ(layout.marks.size(), 2 * r.seams.size());
  EXPECT_EQ(layout.marks[0].label.text, layout.marks[1].label.text);
  o.scale = 1.0;  // a 3 m cone on A4 at 1:1
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
}

TEST(PatternSvg, SizeIsInMillimetres) {
  const auto m = test::plane();
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  LayoutOptions o;
  o.scale = 0.1;
  const std::string svg = pattern_svg(layout_pattern(r, m.triangles, o), r, 0);
  EXPECT_NE(svg.find("width=\"210mm\" height=\"297mm\" viewBox=\"0 0 210 297\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"piece-A\""), std::string::npos);
  EXPECT_NE(svg.find("scale 1:10"), std::string::npos);
}

TEST(PatternLayout, SeamAllowanceWidensEveryPieceAndItsCutLine) {
  const auto m = test::cone();
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  LayoutOptions o;
  o.scale = 0.025;
  const Layout plain = layout_pattern(r, m.triangles, o);
  o.seam_allowance = 7.0;
  const Layout layout = layout_pattern(r, m.triangles, o);
  ASSERT_EQ(layout.pieces.size(), plain.pieces.size());
  for (size_t p = 0; p < layout.pieces.size(); ++p) {
    const PlacedPiece& piece = layout.pieces[p];
    EXPECT_TRUE(plain.pieces[p].cut_line.empty());
    EXPECT_NEAR(piece.size.x(), plain.pieces[p].size.x() + 14.0, 1e-9);
    EXPECT_NEAR(piece.size.y(), plain.pieces[p].size.y() + 14.0, 1e-9);
    ASSERT_GE(piece.cut_line.size(), 3u);
    EXPECT_FALSE(piece.cut_line_from_hull);
    // The cut line lies in the margins' room, 7 mm outside every outline corner.
    Eigen::AlignedBox2d cut;
    for (const Eigen::Vector2d& q : piece.cut_line) cut.extend(q);
    EXPECT_GE(cut.min().minCoeff(), o.margin - 1e-9);
    EXPECT_LE(cut.max().x(), o.sheet_width - o.margin + 1e-9);
    for (Eigen::Index row : r.pieces[p].outline.front()) {
      const Eigen::Vector2d corner = layout.corners.row(row).transpose();
      double nearest = INFINITY;
      for (size_t i = 0; i < piece.cut_line.size(); ++i) {
        const Eigen::Vector2d a = piece.cut_line[i], e = piece.cut_line[(i + 1) % piece.cut_line.size()] - a;
        const double t = std::clamp(e.dot(corner - a) / e.squaredNorm(), 0.0, 1.0);
        nearest = std::min(nearest, (a + t * e - corner).norm());
      }
      EXPECT_GE(nearest, 7.0 - 0.011);
    }
  }
  // The notches reach across the allowance to the cut line.
  ASSERT_EQ(layout.marks.size(), plain.marks.size());
  for (size_t k = 0; k < layout.marks.size(); ++k)
    EXPECT_NEAR((layout.marks[k].notch_to - layout.marks[k].notch_from).norm(),
                (plain.marks[k].notch_to - plain.marks[k].notch_from).norm() + 7.0, 1e-9);
  const std::string svg = pattern_svg(layout, r, 0);
  EXPECT_NE(svg.find("id=\"seam-lines\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"seam-A\""), std::string::npos);
  EXPECT_EQ(pattern_svg(plain, r, 0).find("seam-lines"), std::string::npos);
  o.seam_allowance = -1.0;
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
  o.seam_allowance = NAN;
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
  o.seam_allowance = 0.5 * (o.sheet_width - 2.0 * o.margin);  // no room left for any piece
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
  o.seam_allowance = 1e300;
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
}

TEST(PatternLayout, GlueTabsOnOneSideOfEverySeam) {
  // The closed cylinder is cut once: one seam, both sides on the one piece,
  // a tab on one of them, folded along it.
  const auto m = test::cylinder(8, 24);
  const UnfoldResult r = unfold(m.positions, m.triangles, {});
  ASSERT_EQ(r.seams.size(), 1u);
  LayoutOptions o;
  o.scale = 0.02;
  const Layout plain = layout_pattern(r, m.triangles, o);
  o.glue_tabs = 5.0;
  const Layout layout = layout_pattern(r, m.triangles, o);
  EXPECT_EQ(layout.glue_tabs, 1);
  EXPECT_EQ(layout.glue_tabs_dropped, 0);
  ASSERT_EQ(layout.fold_lines.size(), 1u);
  EXPECT_EQ(layout.fold_lines[0].points.size(), r.seams[0].edges.size() + 1);
  EXPECT_NEAR(layout.pieces[0].size.x(), plain.pieces[0].size.x() + 10.0, 1e-9);
  // The cut line: the outline with the seam side's inner corners moved out
  // onto the tab's edge, and the tab's two shoulders (where its 45 degree
  // ends meet its top).
  EXPECT_EQ(layout.pieces[0].cut_line.size(), r.pieces[0].outline.front().size() + 2);
  const std::string svg = pattern_svg(layout, r, 0);
  EXPECT_NE(svg.find("id=\"fold-lines\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"tabbed-pieces\""), std::string::npos);
  o.seam_allowance = 3.0;  // not both
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
  o.seam_allowance = 0.0;
  o.glue_tabs = -1.0;
  EXPECT_THROW(layout_pattern(r, m.triangles, o), EngineError);
}

}  // namespace
}  // namespace developable

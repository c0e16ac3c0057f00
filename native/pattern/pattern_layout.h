// Flat patterns, step 2 of 3 (unfold -> pattern_layout -> pattern_svg): the
// flat pieces packed onto sheets at true scale, with labels and match marks.
#pragma once

#include "core/types.h"
#include "pattern/unfold.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace developable {

struct LayoutOptions {
  double sheet_width = 210.0;   // mm; default A4 portrait
  double sheet_height = 297.0;  // mm
  double margin = 10.0;         // mm kept free on every side
  double spacing = 4.0;         // mm at least between two pieces
  double footer = 12.0;         // mm above the bottom margin for the scale bar and the title
  // Paper length per model length (1: 1:1, 0.1: 1:10); 0 = automatic: the
  // largest of 1, 1/2, 1/5, 1/10, 1/20, ... at which every piece fits.
  double scale = 1.0;
  double unit_mm = 1000.0;      // one model unit in mm: 1000 for metres
  std::string unit_name = "m";  // the model unit's name, for the scale bar ("in" gives inch lengths)
  // mm of seam allowance around every piece (for sewing or gluing): the cut
  // line is the outline offset outward by it (seam_allowance.h) and the
  // outline becomes the seam line; 0: the outline is the cut line.
  double seam_allowance = 0.0;
  // mm: glue tabs this high on one side of every seam (piece_a's, piece_b's
  // where none fits there; glue_tabs.h), folded along the seam; 0: none. Not
  // with a seam allowance.
  double glue_tabs = 0.0;
};

// A label at a point of a sheet, text centred there, turned by `angle`.
struct SheetLabel {
  std::string text;
  int sheet = 0;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // mm, x right, y down from the top left corner
  double size = 3.0;                             // text height, mm
  double angle = 0.0;                            // degrees, clockwise on the sheet
};

struct PlacedPiece {
  int sheet = 0;
  Eigen::Vector2d size = Eigen::Vector2d::Zero();  // its upright bounding box on the sheet, mm,
                                                   // seam allowance included
  // With a seam allowance: the cut line, mm on the sheet, the outline's
  // offset (from_hull: that of its convex hull, see offset_outline); with
  // glue tabs: the outline with its tabs; else empty (the outline is cut).
  std::vector<Eigen::Vector2d> cut_line;
  bool cut_line_from_hull = false;
  SheetLabel label;  // "A", "B", ... at the (sampled) face centre farthest
                     // from the outline, its box within that distance
};

// One side of a seam: a notch across the cut line at the seam's middle (with
// a seam allowance, from the cut line across the allowance) and the seam's
// label beside it, inside the piece.
struct MatchMark {
  int seam = 0;
  int side = 0;  // 0: piece_a, 1: piece_b of the seam
  Eigen::Vector2d notch_from = Eigen::Vector2d::Zero(), notch_to = Eigen::Vector2d::Zero();
  SheetLabel label;
};

// Where a glue tab is folded: its seam side's corners on a sheet, mm.
struct FoldLine {
  int sheet = 0;
  std::vector<Eigen::Vector2d> points;
};

struct Layout {
  LayoutOptions options;  // as used (scale resolved when automatic)
  int sheets = 0;
  FlatCorners corners;  // per face corner (3 f + k), mm on its piece's sheet
  std::vector<PlacedPiece> pieces;
  std::vector<std::string> seam_labels;  // per seam: "1", "2", ...; both sides carry it
  std::vector<MatchMark> marks;          // two per seam
  std::vector<FoldLine> fold_lines;      // one per glue tab
  int glue_tabs = 0;                     // tabs placed
  int glue_tabs_dropped = 0;             // seams (each run of one) with a tab on neither side
  // Per piece, per outline loop (the outer one first, then its holes): the
  // outline as drawn on its sheet, mm (UnfoldPiece::outline_curve placed).
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> outlines;
  int labels_left_out = 0;  // seam labels with no free room beside their notch (the notch stays)
};

// Packs the pieces of `unfolded` (from unfold() on this mesh's `triangles`).
// Each piece is turned to its smallest bounding rectangle (lying, or standing
// when only that fits), mirrored never (the sheet shows the side the face
// normals point to), then placed by first-fit decreasing height on shelves,
// so that the bounding boxes, hence the pieces (their cut lines with a seam
// allowance or glue tabs), are at least `spacing` apart and inside the margins.
// No two labels' boxes (label_box, pattern_labels.h) overlap: a piece's
// label lies inside it, scaled to fit; a seam's label goes beside its notch
// where it is free, near the seam's middle, shrunk to half size at most, or
// is left out (labels_left_out; the notch stays). Throws
// EngineError(invalid_argument) for a non-positive or non-finite size, a
// negative, non-finite or too wide seam allowance or glue tab, both of them, a
// margin that leaves no room, or a piece
// that does not fit the printable area at the given scale (the message names
// the piece, its size and the scale that would fit), cancelled when `progress`
// says stop (reported as the share of the pieces placed).
Layout layout_pattern(const UnfoldResult& unfolded, const Triangles& triangles, const LayoutOptions& options = {},
                      const Progress& progress = {});

// Loop `loop` of piece p's outline on its sheet (0: the outer one), mm, one
// point per outline corner in the unfolding's order.
std::vector<Eigen::Vector2d> outline_on_sheet(const Layout& layout, size_t p, size_t loop = 0);

// "A" .. "Z", "AA", "AB", ... for piece index 0, 1, ...
std::string piece_label(int index);

}  // namespace developable

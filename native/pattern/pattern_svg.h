// Flat patterns, step 3 of 3 (unfold -> pattern_layout -> pattern_svg): the
// laid-out pieces as SVG files at true scale.
#pragma once

#include "pattern/pattern_layout.h"
#include "pattern/unfold.h"

#include <string>
#include <vector>

namespace developable {

// The SVG text of sheet `sheet` (0-based) of `layout`: width and height in mm
// and a viewBox in mm, so that a renderer at 100 % prints true sizes. Holds a
// white page, the pieces' outlines as cut lines (filled light blue; with a
// seam allowance the cut lines are the offsets, group "cut-lines", and the
// outlines are dashed seam lines, group "seam-lines"; with glue tabs the cut
// lines hold the tabs, the pieces are filled inside them, group
// "tabbed-pieces", and the tabs' dashed fold lines are group "fold-lines"), each
// piece's label, the match marks (a red notch and the seam's label on both
// sides), and a footer with a scale bar, the scale and the sheet's number.
std::string pattern_svg(const Layout& layout, const UnfoldResult& unfolded, int sheet);

// Writes every sheet: to `path` itself when there is one sheet, else to
// <stem>-1<ext>, <stem>-2<ext>, ... beside it. Returns the paths written.
// Throws EngineError(invalid_argument) when a file cannot be written.
std::vector<std::string> write_pattern_svg(const Layout& layout, const UnfoldResult& unfolded, const std::string& path);

}  // namespace developable

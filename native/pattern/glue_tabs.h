// Flat patterns, beside pattern_layout: glue tabs, the flaps papercraft and
// card models are glued by, on one side of each seam.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace developable {

// A run of consecutive outline edges that gets a tab: edges first .. first +
// count - 1 of the outline (edge i joins corner i to corner i + 1, cyclic).
struct TabRun {
  int first = 0;
  int count = 0;
};

struct TabbedOutline {
  // The cut line: the outline with every tab that fits spliced in (its
  // run's corners replaced by the tab's outer edge), same orientation.
  std::vector<Eigen::Vector2d> cut_line;
  // The fold lines: each tab's run of outline corners, first to last.
  std::vector<std::vector<Eigen::Vector2d>> folds;
  int tabs = 0;              // runs that got a tab
  int dropped = 0;           // runs where no tab fits (none at `height` nor at half of it)
  std::vector<bool> tabbed;  // per run, in the order given: whether it got a tab
};

// Glue tabs on the runs of a simple closed outline (a piece on the sheet).
//   outline: the piece's corners in order, either orientation, at least 3;
//   runs: disjoint runs of its edges (count >= 1), in any order;
//   height: > 0, the tabs' height (the outline's units, mm on the sheet).
// A tab stands on its run outside the piece: at arc length s along a run of
// length L its outer edge is min(height, s, L - s) away (45 degree ends, a
// triangle on a run shorter than 2 height), along the outward bisector at
// the run's corners, so every point of it is within `height` of the run. A
// tab is kept only if its outer edge crosses neither itself, the outline nor
// an earlier tab, and no outline corner next to the run lies inside it; else
// it is tried at half the height, else dropped (the run stays a plain cut
// line). Runs are tried in the order given: an earlier run has the first
// claim on the room around the piece. Throws
// EngineError(invalid_argument) for a non-positive or non-finite height, an
// outline of fewer than 3 corners, or a run out of range or overlapping
// another.
TabbedOutline add_glue_tabs(const std::vector<Eigen::Vector2d>& outline, const std::vector<TabRun>& runs,
                            double height);

}  // namespace developable

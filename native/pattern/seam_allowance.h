// Flat patterns, beside pattern_layout: the cut line of a piece with a seam
// allowance (the margin a sewer or a gluer needs beyond the seam line).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace developable {

// The outward offset of a simple closed polygon: the outer boundary of the
// set of points within `distance` of the polygon's region, with round
// corners. Where two parts of the outline come nearer than 2 `distance` (a
// slot, the inside of a C), their offsets meet and the cut line bridges the
// gap, as a sewer's allowance does.
//   outline: the polygon's corners in order, either orientation, the last
//     not repeating the first; consecutive repeats are ignored; at least 3
//     distinct corners, not all on one line, the polygon not crossing itself.
//   distance: > 0, the outline's units (the layout passes sheet mm).
//   tolerance: > 0, the largest gap between a round corner and the chords
//     that draw it (same units).
// Returns the offset polygon (`points`), in the outline's orientation, every corner at
// `distance` from the outline to within `tolerance` and the whole polygon
// at least `distance` - `tolerance` from it, outside. O(n^2) in the outline's
// corners, bounding boxes first. Throws EngineError(invalid_argument) for a
// non-finite or non-positive distance or tolerance and for an outline of
// fewer than 3 distinct or non-finite corners or of no area. If the offset's
// pieces do not close into a loop (rounding on a near-degenerate outline), the
// offset of the outline's convex hull is returned instead, with `from_hull`
// set: a valid cut line, wider than asked in the hull's pockets.
struct OffsetOutline {
  std::vector<Eigen::Vector2d> points;
  bool from_hull = false;
};
OffsetOutline offset_outline(const std::vector<Eigen::Vector2d>& outline, double distance, double tolerance);

}  // namespace developable

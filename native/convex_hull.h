// Shared plumbing of the flat patterns (pattern_layout, seam_allowance): the
// convex hull of points in the plane.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace developable {

// The convex hull of `points` (Andrew's monotone chain): its corners
// counter-clockwise, no repeated end point, no corner on an edge. Fewer than
// 3 points come back sorted as they are; all points on one line give its two
// ends. O(n log n).
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> points);

}  // namespace developable

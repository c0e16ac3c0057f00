// Shared plumbing of the flat patterns (unfold, pattern_layout,
// seam_allowance, glue_tabs): plane geometry of points and polygons.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace developable {

// a.x b.y - a.y b.x: positive when b turns left of a.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// The signed area of the closed polygon: positive counter-clockwise.
double signed_area(const std::vector<Eigen::Vector2d>& polygon);

// Segments [a, b] and [c, d] cross at a point inside both: touching ends and
// collinear overlaps do not count.
bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d);

// Whether x is inside the closed polygon (even-odd rule; a point on its
// boundary may go either way).
bool inside_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& x);

// The convex hull of `points` (Andrew's monotone chain): its corners
// counter-clockwise, no repeated end point, no corner on an edge. Fewer than
// 3 points come back sorted as they are; all points on one line give its two
// ends. O(n log n).
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> points);

}  // namespace developable

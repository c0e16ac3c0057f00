// Nearest points on polylines in the Gauss chart (2-D): the one search that
// the ideal curve's refinement (ideal_curve.cpp) and the skeleton's ordering
// (skeleton.cpp) share. Sphere curves have their own (curve_search.h): there
// the segments are great-circle arcs.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace developable {

// A polyline in the chart with a parameter per point (a sampled B-spline's
// t, or any increasing values).
struct ChartPolyline {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> params;  // one per point
  bool closed = false;         // the last point connects back to the first
};

// The nearest point of segment a -> b to q: returns its fraction f in [0, 1]
// along the segment (0 for a segment of no length) and sets `dist2` to the
// squared distance.
inline double nearest_on_segment(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                 double& dist2) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double f = len2 > 0.0 ? std::min(1.0, std::max(0.0, (q - a).dot(ab) / len2)) : 0.0;
  dist2 = (a + f * ab - q).squaredNorm();
  return f;
}

// Nearest point of a set of chart polylines, exact, with bounding circles
// over runs of segments so that a query touches few segments. Keeps a
// reference to `lines`, which must outlive it.
class ChartPolylineSearch {
 public:
  struct Hit {
    int curve = -1;  // -1 when there is no segment
    double param = 0.0;
    double dist2 = INFINITY;  // squared distance to the nearest point
  };

  explicit ChartPolylineSearch(const std::vector<ChartPolyline>& lines);

  // Nearest point; for open polylines a query beyond an end is extended along
  // the end tangent to a parameter outside [0, 1] (so a refit can grow the
  // curve to cover its data).
  // `warm` is the group to search first (a nearby query's answer, so the
  // bound is tight early); it becomes the group of this answer.
  Hit nearest(const Eigen::Vector2d& q, int& warm) const;

 private:
  static constexpr int kRun = 16;
  struct Group {
    int curve, begin, end;  // segments begin .. end-1
    Eigen::Vector2d center;
    double radius;
  };
  int segments(int c) const {
    const int n = static_cast<int>(lines_[c].points.size());
    return lines_[c].closed ? n : n - 1;
  }
  const Eigen::Vector2d& point(int c, int i) const {
    const auto& p = lines_[c].points;
    return p[static_cast<size_t>(i) % p.size()];
  }
  const std::vector<ChartPolyline>& lines_;
  std::vector<Group> groups_;
};

}  // namespace developable

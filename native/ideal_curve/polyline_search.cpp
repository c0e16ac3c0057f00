#include "ideal_curve/polyline_search.h"

#include <algorithm>

namespace developable {

ChartPolylineSearch::ChartPolylineSearch(const std::vector<ChartPolyline>& lines) : lines_(lines) {
  for (int c = 0; c < static_cast<int>(lines.size()); ++c) {
    const int segs = segments(c);
    for (int s0 = 0; s0 < segs; s0 += kRun) {
      Group g{c, s0, std::min(segs, s0 + kRun), Eigen::Vector2d::Zero(), 0.0};
      Eigen::Vector2d lo = point(c, s0), hi = lo;
      for (int s = s0; s <= g.end; ++s) {
        lo = lo.cwiseMin(point(c, s));
        hi = hi.cwiseMax(point(c, s));
      }
      g.center = 0.5 * (lo + hi);
      for (int s = s0; s <= g.end; ++s) g.radius = std::max(g.radius, (point(c, s) - g.center).norm());
      groups_.push_back(g);
    }
  }
}

ChartPolylineSearch::Hit ChartPolylineSearch::nearest(const Eigen::Vector2d& q, int& warm) const {
  Hit hit;
  int best_c = -1, best_s = -1, best_g = -1;
  double best_f = 0.0;
  const int groups = static_cast<int>(groups_.size());
  if (groups == 0) return hit;
  warm = std::min(std::max(warm, 0), groups - 1);
  for (int k = -1; k < groups; ++k) {
    if (k == warm) continue;
    const int gi = k < 0 ? warm : k;
    const Group& g = groups_[gi];
    const double d = (q - g.center).norm() - g.radius;
    if (d > 0.0 && d * d >= hit.dist2) continue;
    for (int s = g.begin; s < g.end; ++s) {
      double d2 = 0.0;
      const double f = nearest_on_segment(q, point(g.curve, s), point(g.curve, s + 1), d2);
      if (d2 < hit.dist2) {
        hit.dist2 = d2;
        best_c = g.curve;
        best_s = s;
        best_g = gi;
        best_f = f;
      }
    }
  }
  if (best_c < 0) return hit;
  warm = best_g;
  const ChartPolyline& line = lines_[best_c];
  const int n = static_cast<int>(line.points.size());
  hit.curve = best_c;
  const double t0 = line.params[best_s];
  const double t1 = (best_s + 1 < n) ? line.params[best_s + 1] : 1.0;
  hit.param = t0 + best_f * (t1 - t0);
  if (!line.closed && n >= 2) {
    if (best_s == 0 && best_f == 0.0) {
      const Eigen::Vector2d ab = line.points[1] - line.points[0];
      const double len = ab.norm();
      if (len > 0.0) {
        const double s = -(q - line.points[0]).dot(ab) / len;
        hit.param = line.params[0] - std::max(0.0, s) * (line.params[1] - line.params[0]) / len;
      }
    } else if (best_s == n - 2 && best_f == 1.0) {
      const Eigen::Vector2d ab = line.points[n - 1] - line.points[n - 2];
      const double len = ab.norm();
      if (len > 0.0) {
        const double s = (q - line.points[n - 1]).dot(ab) / len;
        hit.param = line.params[n - 1] + std::max(0.0, s) * (line.params[n - 1] - line.params[n - 2]) / len;
      }
    }
  }
  return hit;
}

}  // namespace developable

#include "pattern/glue_tabs.h"

#include "core/types.h"
#include "pattern/plane_geometry.h"

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;

// The tab's outer edge over `chain`, from its first corner to its last:
// min(height, s, L - s) out along the outward normal (the bisector at a
// corner), sampled at the chain's corners and where the height stops
// growing or starts falling.
std::vector<Vec2> tab_top(const std::vector<Vec2>& chain, const std::vector<Vec2>& normal, double height) {
  const size_t k = chain.size() - 1;  // edges
  std::vector<double> at(chain.size(), 0.0);
  for (size_t i = 0; i < k; ++i) at[i + 1] = at[i] + (chain[i + 1] - chain[i]).norm();
  const double length = at[k];
  std::vector<double> samples(at.begin(), at.end());
  if (height < length - height) {
    samples.push_back(height);
    samples.push_back(length - height);
  } else {
    samples.push_back(0.5 * length);  // a triangle's tip
  }
  std::sort(samples.begin(), samples.end());
  samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
  std::vector<Vec2> top;
  size_t edge = 0;
  for (double s : samples) {
    while (edge + 1 < k && at[edge + 1] < s) ++edge;
    const double h = std::max(0.0, std::min({height, s, length - s}));
    Vec2 point, out;
    const auto corner = std::find(at.begin(), at.end(), s);
    if (corner != at.end()) {
      const size_t i = static_cast<size_t>(corner - at.begin());
      point = chain[i];
      const Vec2 sum = normal[std::min(i, k - 1)] + normal[i > 0 ? i - 1 : 0];
      out = sum.norm() > 1e-9 ? Vec2(sum.normalized()) : normal[std::min(i, k - 1)];
    } else {
      const double t = (s - at[edge]) / std::max(at[edge + 1] - at[edge], 1e-300);
      point = chain[edge] + t * (chain[edge + 1] - chain[edge]);
      out = normal[edge];
    }
    top.push_back(point + h * out);
  }
  return top;
}

}  // namespace

TabbedOutline add_glue_tabs(const std::vector<Vec2>& outline, const std::vector<TabRun>& runs, double height) {
  if (!std::isfinite(height) || !(height > 0.0))
    throw EngineError(Status::invalid_argument, "add_glue_tabs: the height must be positive");
  const int n = static_cast<int>(outline.size());
  if (n < 3) throw EngineError(Status::invalid_argument, "add_glue_tabs: the outline needs 3 corners");
  std::vector<char> taken(static_cast<size_t>(n), 0);
  for (const TabRun& run : runs) {
    if (run.first < 0 || run.first >= n || run.count < 1 || run.count > n)
      throw EngineError(Status::invalid_argument, "add_glue_tabs: a run is out of range");
    for (int e = 0; e < run.count; ++e) {
      char& edge = taken[static_cast<size_t>((run.first + e) % n)];
      if (edge) throw EngineError(Status::invalid_argument, "add_glue_tabs: two runs share an edge");
      edge = 1;
    }
  }
  // Outward: right of each edge when the piece is on its left (counter-clockwise).
  const double side = signed_area(outline) > 0.0 ? 1.0 : -1.0;
  const auto outward = [&](const Vec2& a, const Vec2& b) {
    const Vec2 u = (b - a).normalized();
    return Vec2(side * u.y(), -side * u.x());
  };

  TabbedOutline result;
  std::vector<std::vector<Vec2>> tops(runs.size());  // empty where no tab fits
  for (size_t r = 0; r < runs.size(); ++r) {
    const TabRun& run = runs[r];
    std::vector<Vec2> chain, normal;
    for (int i = 0; i <= run.count; ++i) chain.push_back(outline[static_cast<size_t>((run.first + i) % n)]);
    for (int i = 0; i < run.count; ++i) normal.push_back(outward(chain[i], chain[i + 1]));
    const Vec2 before = outline[static_cast<size_t>((run.first + n - 1) % n)];
    const Vec2 after = outline[static_cast<size_t>((run.first + run.count + 1) % n)];
    for (double h : {height, 0.5 * height}) {
      const std::vector<Vec2> top = tab_top(chain, normal, h);
      const size_t m = top.size();
      bool fits = m >= 3;
      for (const Vec2& p : top) fits = fits && p.allFinite();  // (a zero-length edge's normal is 0)
      for (size_t i = 0; fits && i + 1 < m; ++i) {
        for (size_t j = i + 2; fits && j + 1 < m; ++j) fits = !segments_cross(top[i], top[i + 1], top[j], top[j + 1]);
        for (int e = 0; fits && e < n; ++e)
          fits = !segments_cross(top[i], top[i + 1], outline[static_cast<size_t>(e)],
                                 outline[static_cast<size_t>((e + 1) % n)]);
        for (size_t earlier = 0; earlier < r; ++earlier)
          for (size_t j = 0; fits && j + 1 < tops[earlier].size(); ++j)
            fits = !segments_cross(top[i], top[i + 1], tops[earlier][j], tops[earlier][j + 1]);
      }
      if (fits) {
        std::vector<Vec2> region(chain);  // the tab: up the run, back along its outer edge
        region.insert(region.end(), top.rbegin() + 1, top.rend() - 1);
        fits = !inside_polygon(region, before) && !inside_polygon(region, after);
      }
      if (fits) {
        tops[r] = top;
        result.folds.push_back(chain);
        break;
      }
    }
    if (tops[r].empty())
      ++result.dropped;
    else
      ++result.tabs;
    result.tabbed.push_back(!tops[r].empty());
  }

  // The cut line: the outline's corners, a tabbed run's inner corners
  // replaced by its tab's outer edge.
  std::vector<int> starts(static_cast<size_t>(n), -1);
  std::vector<char> inner(static_cast<size_t>(n), 0);
  for (size_t r = 0; r < runs.size(); ++r) {
    if (tops[r].empty()) continue;
    starts[static_cast<size_t>(runs[r].first)] = static_cast<int>(r);
    for (int i = 1; i < runs[r].count; ++i) inner[static_cast<size_t>((runs[r].first + i) % n)] = 1;
  }
  for (int j = 0; j < n; ++j) {
    if (inner[static_cast<size_t>(j)]) continue;
    result.cut_line.push_back(outline[static_cast<size_t>(j)]);
    if (starts[static_cast<size_t>(j)] >= 0) {
      const auto& top = tops[static_cast<size_t>(starts[static_cast<size_t>(j)])];
      result.cut_line.insert(result.cut_line.end(), top.begin() + 1, top.end() - 1);
    }
  }
  return result;
}

}  // namespace developable

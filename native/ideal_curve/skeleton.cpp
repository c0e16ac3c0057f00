#include "ideal_curve/skeleton.h"

#include "core/union_find.h"
#include "ideal_curve/polyline_search.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

namespace developable {

namespace {

struct Edge {
  double length;
  int a, b;
  bool operator<(const Edge& o) const { return std::tie(length, a, b) < std::tie(o.length, o.a, o.b); }
};

using Tree = std::vector<std::vector<std::pair<int, double>>>;

// Tree distances from `start`, not entering nodes marked in `blocked`;
// returns the farthest node and fills parent pointers for the path back.
int farthest(const Tree& tree, int start, const std::vector<char>& blocked, std::vector<int>& parent,
             std::vector<double>& dist) {
  std::vector<int> stack{start};
  parent[start] = -1;
  dist[start] = 0.0;
  int best = start;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    if (dist[u] > dist[best] || (dist[u] == dist[best] && u < best)) best = u;
    for (const auto& [v, w] : tree[u]) {
      if (v == parent[u] || blocked[v]) continue;
      parent[v] = u;
      dist[v] = dist[u] + w;
      stack.push_back(v);
    }
  }
  return best;
}

std::vector<int> path_to(int end, const std::vector<int>& parent) {
  std::vector<int> path;
  for (int u = end; u >= 0; u = parent[u]) path.push_back(u);
  return path;  // from end back to the start
}

double path_length(const std::vector<Eigen::Vector2d>& pts) {
  double length = 0.0;
  for (size_t i = 1; i < pts.size(); ++i) length += (pts[i] - pts[i - 1]).norm();
  return length;
}

// A path of ridge points on its way to becoming a SkeletonCurve.
struct Candidate {
  std::vector<Eigen::Vector2d> points;
  double length = 0.0;
  bool closed = false;
};

// Closed when the gap between the ends is like a step along the path (a ring
// whose MST dropped one edge) or small against the length.
bool closes(const Candidate& c, double link_distance) {
  double longest_step = 0.0;
  for (size_t k = 1; k < c.points.size(); ++k) {
    longest_step = std::max(longest_step, (c.points[k] - c.points[k - 1]).norm());
  }
  const double gap = (c.points.front() - c.points.back()).norm();
  return c.points.size() >= 4 && c.length >= 3.0 * gap &&
         gap <= std::max(std::min(2.0 * link_distance, 1.5 * longest_step), 0.08 * c.length);
}

// Unit direction in which a path leaves through its back end, from the
// point `reach` (path length) before that end; 0 for a path of no length.
Eigen::Vector2d leaving_direction(const std::vector<Eigen::Vector2d>& pts, double reach) {
  const Eigen::Vector2d& end = pts.back();
  double walked = 0.0;
  size_t k = pts.size() - 1;
  while (k > 0 && walked < reach) {
    walked += (pts[k] - pts[k - 1]).norm();
    --k;
  }
  const Eigen::Vector2d d = end - pts[k];
  const double length = d.norm();
  return length > 0.0 ? Eigen::Vector2d(d / length) : Eigen::Vector2d::Zero();
}

// Whether the back end of path a continues into the front end of path b: the
// gap is at most join_distance, the paths run the same way (within 60
// degrees), and b starts ahead of a's end along a's direction (an overlap up
// to one link is allowed) and within one link, or 30 degrees, of that line;
// and the same seen from b. Ends are given with their leaving directions
// (ta leaves a forward, tb leaves b backward).
constexpr double kCos60Degrees = 0.5;    // paths running the same way
constexpr double kMaxAheadSlope = 0.58;  // lateral / along, ~tan 30 degrees (0.577)

bool continues(const Eigen::Vector2d& pa, const Eigen::Vector2d& ta, const Eigen::Vector2d& pb,
               const Eigen::Vector2d& tb, double link_distance, double join_distance) {
  const Eigen::Vector2d gap = pb - pa;
  if (gap.norm() > join_distance || ta.dot(-tb) < kCos60Degrees) return false;
  auto ahead = [&](const Eigen::Vector2d& t, const Eigen::Vector2d& g) {
    const double along = g.dot(t);
    const double lateral = (g - along * t).norm();
    return along >= -link_distance && lateral <= std::max(link_distance, kMaxAheadSlope * along);
  };
  return ahead(ta, gap) && ahead(tb, -gap);
}

// Chains open paths whose ends continue each other (continues()), shortest
// gaps first, each end used once; a chain whose own ends then meet is
// closed by the closure rule. A curve whose ridge broke into pieces (its
// Gauss image thinned into clusters between which the field dips) is one
// curve again. Points of a piece that fall behind the end it continues are
// dropped, so an overlap does not fold the chain back.
std::vector<Candidate> join_pieces(std::vector<Candidate> pieces, double link_distance, double join_distance) {
  std::vector<Candidate> out;
  std::vector<int> open;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i) {
    if (pieces[i].closed)
      out.push_back(std::move(pieces[i]));
    else
      open.push_back(i);
  }
  // End 2k is the front of piece open[k], 2k+1 its back; each with its
  // position and the direction in which the path leaves through it.
  const int ends = 2 * static_cast<int>(open.size());
  std::vector<Eigen::Vector2d> end_point(ends), end_leaving(ends);
  const double reach = join_distance;
  for (int k = 0; k < static_cast<int>(open.size()); ++k) {
    std::vector<Eigen::Vector2d> pts = pieces[open[k]].points;
    end_point[2 * k + 1] = pts.back();
    end_leaving[2 * k + 1] = leaving_direction(pts, reach);
    std::reverse(pts.begin(), pts.end());
    end_point[2 * k] = pts.back();
    end_leaving[2 * k] = leaving_direction(pts, reach);
  }
  std::vector<Edge> joins;
  for (int e = 0; e < ends; ++e) {
    for (int f = e + 1; f < ends; ++f) {
      if (e / 2 == f / 2) continue;
      if (continues(end_point[e], end_leaving[e], end_point[f], end_leaving[f], link_distance, join_distance)) {
        joins.push_back({(end_point[f] - end_point[e]).norm(), e, f});
      }
    }
  }
  std::sort(joins.begin(), joins.end());
  std::vector<int> partner(ends, -1);
  UnionFind chains(static_cast<int>(open.size()));
  for (const Edge& j : joins) {
    if (partner[j.a] >= 0 || partner[j.b] >= 0 || !chains.unite(j.a / 2, j.b / 2)) continue;
    partner[j.a] = j.b;
    partner[j.b] = j.a;
  }
  // Walk each chain from a free end.
  std::vector<char> used(open.size(), 0);
  for (int start = 0; start < ends; ++start) {
    if (partner[start] >= 0 || used[start / 2]) continue;
    Candidate chain;
    for (int e = start; e >= 0;) {
      const int k = e / 2;
      used[k] = 1;
      std::vector<Eigen::Vector2d> pts = std::move(pieces[open[k]].points);
      if (e % 2 == 1) std::reverse(pts.begin(), pts.end());  // enter through end e
      size_t first = 0;
      if (!chain.points.empty()) {
        const Eigen::Vector2d end = chain.points.back();
        const Eigen::Vector2d t = leaving_direction(chain.points, reach);
        while (first + 2 < pts.size() && (pts[first] - end).dot(t) < 0.0) ++first;
      }
      chain.points.insert(chain.points.end(), pts.begin() + static_cast<std::ptrdiff_t>(first), pts.end());
      const int exit = e ^ 1;
      e = partner[exit];
    }
    chain.length = path_length(chain.points);
    chain.closed = closes(chain, link_distance);
    out.push_back(std::move(chain));
  }
  return out;
}

// Whether at least half of the points lie within `distance` of a curve
// (closed curves with their closing segment).
bool shadowed(const std::vector<Eigen::Vector2d>& pts, const std::vector<SkeletonCurve>& curves, double distance) {
  std::vector<ChartPolyline> lines;
  for (const auto& c : curves) {
    ChartPolyline line{c.points, std::vector<double>(c.points.size(), 0.0), c.closed};
    lines.push_back(std::move(line));
  }
  const ChartPolylineSearch search(lines);
  int warm = 0;
  size_t near = 0;
  for (const auto& p : pts) near += std::sqrt(search.nearest(p, warm).dist2) <= distance;
  return 2 * near >= pts.size();
}

}  // namespace

std::vector<Eigen::Vector2d> find_ridge_points(const EffectField& field, double min_field_fraction) {
  if (!(min_field_fraction >= 0.0 && min_field_fraction < 1.0)) {
    throw EngineError(Status::invalid_argument, "skeleton: min_field_fraction must be in [0, 1)");
  }
  std::vector<Eigen::Vector2d> ridge;
  const int n = field.resolution;
  if (n < 3 || field.values.rows() != n || field.values.cols() != n) return ridge;
  const Eigen::MatrixXd& f = field.values;
  const double peak = f.maxCoeff();
  if (!(peak > 0.0)) return ridge;
  const double floor_value = min_field_fraction * peak;
  const double radius_cells = field.effect_radius / field.cell_size;
  // Bilinear sample in cell-index coordinates (cells are whole here).
  auto at = [&](double x, double y) {
    const int i0 = std::min(n - 2, std::max(0, static_cast<int>(std::floor(x))));
    const int j0 = std::min(n - 2, std::max(0, static_cast<int>(std::floor(y))));
    const double fx = x - i0, fy = y - j0;
    return (1 - fx) * (1 - fy) * f(i0, j0) + fx * (1 - fy) * f(i0 + 1, j0) + (1 - fx) * fy * f(i0, j0 + 1) +
           fx * fy * f(i0 + 1, j0 + 1);
  };
  for (int iy = 1; iy < n - 1; ++iy) {
    for (int ix = 1; ix < n - 1; ++ix) {
      const double f0 = f(ix, iy);
      if (f0 < floor_value || !(f0 > 0.0)) continue;
      // Derivatives per cell.
      const double gx = 0.5 * (f(ix + 1, iy) - f(ix - 1, iy));
      const double gy = 0.5 * (f(ix, iy + 1) - f(ix, iy - 1));
      const double fxx = f(ix + 1, iy) - 2.0 * f0 + f(ix - 1, iy);
      const double fyy = f(ix, iy + 1) - 2.0 * f0 + f(ix, iy - 1);
      const double fxy = 0.25 * (f(ix + 1, iy + 1) - f(ix + 1, iy - 1) - f(ix - 1, iy + 1) + f(ix - 1, iy - 1));
      const double mean = 0.5 * (fxx + fyy);
      const double dev = std::sqrt(0.25 * (fxx - fyy) * (fxx - fyy) + fxy * fxy);
      const double lmin = mean - dev, lmax = mean + dev;
      // Across-curvature must dominate (not a saddle, not isotropic).
      if (!(lmin < 0.0) || -lmin < 2.0 * std::abs(lmax)) continue;
      // Flat along the ridge compared with the fall across it (see header).
      if (std::sqrt(gx * gx + gy * gy) > 0.5 * -lmin * radius_cells) continue;
      // Eigenvector of lmin: the better conditioned of the two forms.
      Eigen::Vector2d e(fxy, lmin - fxx);
      const Eigen::Vector2d e2(lmin - fyy, fxy);
      if (e2.squaredNorm() > e.squaredNorm()) e = e2;
      if (!(e.squaredNorm() > 0.0)) continue;
      e.normalize();
      const double fp = at(ix + e.x(), iy + e.y());
      const double fm = at(ix - e.x(), iy - e.y());
      if (f0 < fp || f0 < fm || (f0 == fp && f0 == fm)) continue;
      const double denom = fp - 2.0 * f0 + fm;
      double t = denom < 0.0 ? 0.5 * (fm - fp) / denom : 0.0;
      t = std::max(-0.5, std::min(0.5, t));
      ridge.push_back(field.cell_center(ix, iy) + (t * field.cell_size) * e);
    }
  }
  return ridge;
}

namespace {

// The edges of the k-nearest-neighbour graph of the points within
// `link_distance` (kNeighbours per point), found through a bucket grid.
std::vector<Edge> neighbour_edges(const std::vector<Eigen::Vector2d>& points, double link_distance) {
  constexpr int kNeighbours = 8;
  const int count = static_cast<int>(points.size());
  Eigen::Vector2d lo = points[0], hi = points[0];
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int bx = std::max(1, std::min(4096, static_cast<int>((hi.x() - lo.x()) / link_distance) + 1));
  const int by = std::max(1, std::min(4096, static_cast<int>((hi.y() - lo.y()) / link_distance) + 1));
  auto bucket_of = [&](const Eigen::Vector2d& p) {
    const int i = std::min(bx - 1, static_cast<int>((p.x() - lo.x()) / link_distance));
    const int j = std::min(by - 1, static_cast<int>((p.y() - lo.y()) / link_distance));
    return std::make_pair(i, j);
  };
  std::vector<int> bucket_start(static_cast<size_t>(bx) * by + 1, 0), order(count);
  for (const auto& p : points) {
    const auto [i, j] = bucket_of(p);
    ++bucket_start[static_cast<size_t>(j) * bx + i + 1];
  }
  std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
  {
    std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (int k = 0; k < count; ++k) {
      const auto [i, j] = bucket_of(points[k]);
      order[fill[static_cast<size_t>(j) * bx + i]++] = k;
    }
  }
  std::vector<Edge> edges;
  std::vector<std::pair<double, int>> near;
  const double link2 = link_distance * link_distance;
  for (int k = 0; k < count; ++k) {
    near.clear();
    const auto [ci, cj] = bucket_of(points[k]);
    for (int j = std::max(0, cj - 1); j <= std::min(by - 1, cj + 1); ++j) {
      for (int i = std::max(0, ci - 1); i <= std::min(bx - 1, ci + 1); ++i) {
        const size_t b = static_cast<size_t>(j) * bx + i;
        for (int s = bucket_start[b]; s < bucket_start[b + 1]; ++s) {
          const int m = order[s];
          if (m == k) continue;
          const double d2 = (points[m] - points[k]).squaredNorm();
          if (d2 <= link2) near.emplace_back(d2, m);
        }
      }
    }
    const size_t keep = std::min<size_t>(kNeighbours, near.size());
    std::partial_sort(near.begin(), near.begin() + keep, near.end());
    for (size_t s = 0; s < keep; ++s) {
      edges.push_back({std::sqrt(near[s].first), std::min(k, near[s].second), std::max(k, near[s].second)});
    }
  }
  return edges;
}

// Kruskal: the minimum spanning forest of `edges` over `count` points.
Tree spanning_forest(std::vector<Edge> edges, int count) {
  std::sort(edges.begin(), edges.end());
  UnionFind sets(count);
  Tree tree(count);
  for (const Edge& e : edges) {
    if (sets.unite(e.a, e.b)) {
      tree[e.a].emplace_back(e.b, e.length);
      tree[e.b].emplace_back(e.a, e.length);
    }
  }
  return tree;
}

// Marks every point of `root`'s component of the tree as seen.
void mark_component(const Tree& tree, int root, std::vector<char>& seen) {
  std::vector<int> stack{root};
  seen[root] = 1;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    for (const auto& [v, w] : tree[u]) {
      if (!seen[v]) {
        seen[v] = 1;
        stack.push_back(v);
      }
    }
  }
}

// Per component of the forest: the longest path (into `pieces`), and the
// subtrees hanging off it, measured from their junction (into `branches`).
void tree_paths(const Tree& tree, const std::vector<Eigen::Vector2d>& points, double link_distance,
                std::vector<Candidate>& pieces, std::vector<Candidate>& branches) {
  const int count = static_cast<int>(points.size());
  std::vector<char> blocked(count, 0), seen(count, 0);
  std::vector<int> parent(count, -1);
  std::vector<double> dist(count, 0.0);
  for (int root = 0; root < count; ++root) {
    if (seen[root]) continue;
    const int a = farthest(tree, root, blocked, parent, dist);
    const int b = farthest(tree, a, blocked, parent, dist);
    const std::vector<int> main = path_to(b, parent);  // b ... a
    mark_component(tree, root, seen);
    if (main.size() < 2) continue;
    Candidate c;
    for (int u : main) c.points.push_back(points[u]);
    c.length = path_length(c.points);
    c.closed = closes(c, link_distance);
    for (int u : main) blocked[u] = 1;
    for (int u : main) {
      for (const auto& [v, w] : tree[u]) {
        if (blocked[v]) continue;
        const int tip = farthest(tree, v, blocked, parent, dist);
        std::vector<int> branch = path_to(tip, parent);  // tip ... v
        std::reverse(branch.begin(), branch.end());
        Candidate br;
        br.points.push_back(points[u]);
        for (int x : branch) br.points.push_back(points[x]);
        br.length = path_length(br.points);
        br.closed = false;
        branches.push_back(std::move(br));
      }
    }
    for (int u : main) blocked[u] = 0;
    pieces.push_back(std::move(c));
  }
}

}  // namespace

std::vector<SkeletonCurve> order_ridge_points(const std::vector<Eigen::Vector2d>& points, double link_distance,
                                              double join_distance, double min_branch_fraction, double min_length) {
  if (!(link_distance > 0.0) || !std::isfinite(link_distance)) {
    throw EngineError(Status::invalid_argument, "skeleton: link_distance must be finite and > 0");
  }
  std::vector<SkeletonCurve> curves;
  if (points.size() < 2) return curves;
  const Tree tree = spanning_forest(neighbour_edges(points, link_distance), static_cast<int>(points.size()));
  std::vector<Candidate> pieces, branches;
  tree_paths(tree, points, link_distance, pieces, branches);
  std::vector<Candidate> found = join_pieces(std::move(pieces), link_distance, join_distance);
  for (auto& br : branches) found.push_back(std::move(br));
  double longest = 0.0;
  for (const auto& c : found) longest = std::max(longest, c.length);
  const double keep_length = std::max(min_branch_fraction * longest, min_length);
  std::stable_sort(found.begin(), found.end(),
                   [](const Candidate& x, const Candidate& y) { return x.length > y.length; });
  for (auto& c : found) {
    if (c.length < keep_length || c.points.size() < 2) continue;
    // A curve beside a longer one (a second ridge through the same noisy
    // band) is not a curve of its own.
    if (!curves.empty() && shadowed(c.points, curves, 0.5 * join_distance)) continue;
    if (c.closed && c.points.size() > 2 && (c.points.front() - c.points.back()).norm() < 1e-12) {
      c.points.pop_back();
    }
    curves.push_back({std::move(c.points), c.closed});
  }
  return curves;
}

std::vector<SkeletonCurve> extract_skeleton(const EffectField& field, const SkeletonOptions& options) {
  if (!(options.min_branch_fraction >= 0.0) || !(options.min_extent_over_spread >= 0.0)) {
    throw EngineError(Status::invalid_argument, "skeleton: options must be >= 0");
  }
  std::vector<SkeletonCurve> none;
  int total_count = 0;
  for (const FieldSource& s : field.sources) total_count += s.count;
  if (total_count < 4 || field.sources.size() < 2) return none;

  std::vector<SkeletonCurve> curves;
  if (static_cast<int>(field.sources.size()) < options.min_sources_for_field) {
    // Few distinct normals (a coarse mesh: a 12-sided cylinder has 12): there
    // is no density to find a ridge in, and the gaps exceed any useful effect
    // radius. Each occupied cell is a skeleton point; all may link.
    std::vector<Eigen::Vector2d> nodes;
    for (const FieldSource& s : field.sources) {
      if (s.weight > 0.0) nodes.push_back(s.position);
    }
    curves = order_ridge_points(nodes, field.cell_size * field.resolution * 2.0, 0.0, options.min_branch_fraction, 0.0);
  } else {
    const std::vector<Eigen::Vector2d> ridge = find_ridge_points(field, options.min_field_fraction);
    const double link = std::max(2.5 * field.cell_size, 0.5 * field.effect_radius);
    curves = order_ridge_points(ridge, link, 2.0 * field.effect_radius, options.min_branch_fraction, 2.0 * link);
  }
  if (curves.empty()) return none;

  // Planar test: ridge extent against the RMS spread of the points.
  double total = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const FieldSource& s : field.sources) {
    centroid += s.weight * s.position;
    total += s.weight;
  }
  if (!(total > 0.0)) return none;
  centroid /= total;
  double spread2 = 0.0;
  for (const FieldSource& s : field.sources) spread2 += s.weight * (s.position - centroid).squaredNorm();
  const double spread = std::sqrt(spread2 / total);
  Eigen::Vector2d lo = curves[0].points[0], hi = lo;
  for (const auto& c : curves) {
    for (const auto& p : c.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if ((hi - lo).norm() < options.min_extent_over_spread * spread) return none;
  // A blob: its scatter across any ridge is comparable with its spread.
  if (field.thickness > options.max_thickness_over_spread * spread) return none;
  return curves;
}

}  // namespace developable

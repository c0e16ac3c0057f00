#include "ideal_curve/effect_field.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace developable {

namespace {

constexpr int kPadCells = 4;

int clamp_index(double u, int n) {
  const double f = std::floor(u);
  if (!(f >= 0.0)) return 0;
  if (f >= n - 1) return n - 1;
  return static_cast<int>(f);
}

// Distance from each source to its nearest other source, by rings of cells
// around it: stops as soon as no farther ring can hold a closer source.
std::vector<double> nearest_source_gaps(const EffectField& field, const std::vector<int>& cell_source) {
  const int n = field.resolution;
  const double h = field.cell_size;
  std::vector<double> gaps;
  gaps.reserve(field.sources.size());
  for (const FieldSource& s : field.sources) {
    const int cx = clamp_index((s.position.x() - field.origin.x()) / h, n);
    const int cy = clamp_index((s.position.y() - field.origin.y()) / h, n);
    double best2 = INFINITY;
    for (int k = 1; k < n; ++k) {
      for (int iy = std::max(0, cy - k); iy <= std::min(n - 1, cy + k); ++iy) {
        const bool edge_row = (iy == cy - k || iy == cy + k);
        const int step = edge_row ? 1 : 2 * k;
        for (int ix = cx - k; ix <= cx + k; ix += step) {
          if (ix < 0 || ix >= n) continue;
          const int j = cell_source[static_cast<size_t>(iy) * n + ix];
          if (j < 0) continue;
          best2 = std::min(best2, (field.sources[j].position - s.position).squaredNorm());
        }
      }
      // Cells of ring k+1 are at least k cells away from the source's cell.
      if (best2 <= (k * h) * (k * h)) break;
    }
    if (std::isfinite(best2)) gaps.push_back(std::sqrt(best2));
  }
  return gaps;
}

// The single-linkage distance at which the points become a few comparable
// pieces. Sources are joined shortest gap first (Kruskal over the pairs of
// sources whose grid Voronoi regions touch, which hold the Euclidean minimum
// spanning tree) until the effective number of pieces, (sum of weights)^2 /
// sum of (piece weight)^2, is at most `pieces`. An outlier barely counts (its
// weight is small); a curve whose normals have clumped into clusters counts
// as many pieces until the gaps between its clusters are bridged; two
// separate curves of similar weight count as two. Chart units; 0 when the
// sources are already few enough pieces.
double linking_distance(const EffectField& field, const std::vector<int>& cell_source, double pieces) {
  const int n = field.resolution;
  const size_t cells = static_cast<size_t>(n) * n;
  std::vector<int> label(cells, -1);
  std::vector<int> queue;
  queue.reserve(cells);
  for (size_t c = 0; c < cells; ++c) {
    if (cell_source[c] >= 0) {
      label[c] = cell_source[c];
      queue.push_back(static_cast<int>(c));
    }
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const int c = queue[head];
    const int ix = c % n, iy = c / n;
    const int next[4] = {ix > 0 ? c - 1 : -1, ix + 1 < n ? c + 1 : -1, iy > 0 ? c - n : -1, iy + 1 < n ? c + n : -1};
    for (int m : next) {
      if (m >= 0 && label[m] < 0) {
        label[m] = label[c];
        queue.push_back(m);
      }
    }
  }
  // Pairs of touching regions; a boundary repeats its pair along its
  // length, so a pair equal to the last one recorded is skipped at once.
  std::vector<uint64_t> pairs;
  uint64_t last[2] = {0, 0};
  auto touch = [&](int a, int b, uint64_t& previous) {
    if (a == b) return;
    const uint64_t key = static_cast<uint64_t>(std::min(a, b)) << 32 | static_cast<uint32_t>(std::max(a, b));
    if (key != previous) pairs.push_back(key);
    previous = key;
  };
  for (int iy = 0; iy < n; ++iy) {
    for (int ix = 0; ix < n; ++ix) {
      const size_t c = static_cast<size_t>(iy) * n + ix;
      if (ix + 1 < n) touch(label[c], label[c + 1], last[0]);
      if (iy + 1 < n) touch(label[c], label[c + n], last[1]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<std::pair<double, uint64_t>> edges;
  edges.reserve(pairs.size());
  for (uint64_t p : pairs) {
    const int a = static_cast<int>(p >> 32), b = static_cast<int>(p & 0xffffffffu);
    edges.emplace_back((field.sources[a].position - field.sources[b].position).squaredNorm(), p);
  }
  std::sort(edges.begin(), edges.end());
  const size_t count = field.sources.size();
  std::vector<int> parent(count);
  std::vector<double> weight(count);
  double total = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < count; ++i) {
    parent[i] = static_cast<int>(i);
    weight[i] = field.sources[i].weight;
    total += weight[i];
    sum_sq += weight[i] * weight[i];
  }
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  if (!(sum_sq > 0.0) || total * total <= pieces * sum_sq) return 0.0;
  for (const auto& [d2, p] : edges) {
    const int a = find(static_cast<int>(p >> 32)), b = find(static_cast<int>(p & 0xffffffffu));
    if (a == b) continue;
    sum_sq += 2.0 * weight[a] * weight[b];
    weight[std::min(a, b)] += weight[std::max(a, b)];
    parent[std::max(a, b)] = std::min(a, b);
    if (total * total <= pieces * sum_sq) return std::sqrt(d2);
  }
  return 0.0;
}

// Weighted RMS thickness of the points at scale `radius`: per source, the
// smaller principal spread of the points in the square window of half-side
// `radius` around it (summed-area tables of the moments make each window
// O(1)), averaged over sources by weight. A curve with across-scatter s
// gives ~s once the window is wider than the scatter; a 2-D blob gives a
// fixed fraction of the window (0.58 radius for uniform points).
class ThicknessProbe {
 public:
  ThicknessProbe(const EffectField& field, const std::vector<double>& cell_weight,
                 const std::vector<Eigen::Vector2d>& cell_sum, const std::vector<Eigen::Matrix2d>& cell_outer)
      : field_(field), n_(field.resolution), table_(static_cast<size_t>(n_ + 1) * (n_ + 1)) {
    for (int iy = 0; iy < n_; ++iy) {
      for (int ix = 0; ix < n_; ++ix) {
        const size_t c = static_cast<size_t>(iy) * n_ + ix;
        Moments m{cell_weight[c], cell_sum[c], cell_outer[c]};
        m += at(ix, iy + 1);
        m += at(ix + 1, iy);
        m -= at(ix, iy);
        at(ix + 1, iy + 1) = m;
      }
    }
  }

  double thickness(double radius) const {
    const double h = field_.cell_size;
    const int k = std::max(1, static_cast<int>(std::ceil(radius / h)));
    double sum = 0.0, total = 0.0;
    for (const FieldSource& s : field_.sources) {
      if (!(s.weight > 0.0)) continue;
      const int cx = clamp_index((s.position.x() - field_.origin.x()) / h, n_);
      const int cy = clamp_index((s.position.y() - field_.origin.y()) / h, n_);
      const int x0 = std::max(0, cx - k), x1 = std::min(n_, cx + k + 1);
      const int y0 = std::max(0, cy - k), y1 = std::min(n_, cy + k + 1);
      Moments m = at(x1, y1);
      m -= at(x0, y1);
      m -= at(x1, y0);
      m += at(x0, y0);
      if (!(m.w > 0.0)) continue;
      const Eigen::Vector2d mean = m.sum / m.w;
      const Eigen::Matrix2d cov = m.outer / m.w - mean * mean.transpose();
      const double half_trace = 0.5 * (cov(0, 0) + cov(1, 1));
      const double dev = std::sqrt(0.25 * (cov(0, 0) - cov(1, 1)) * (cov(0, 0) - cov(1, 1)) + cov(0, 1) * cov(0, 1));
      sum += s.weight * std::max(0.0, half_trace - dev);
      total += s.weight;
    }
    return total > 0.0 ? std::sqrt(sum / total) : 0.0;
  }

 private:
  struct Moments {
    double w = 0.0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d outer = Eigen::Matrix2d::Zero();
    Moments& operator+=(const Moments& o) {
      w += o.w;
      sum += o.sum;
      outer += o.outer;
      return *this;
    }
    Moments& operator-=(const Moments& o) {
      w -= o.w;
      sum -= o.sum;
      outer -= o.outer;
      return *this;
    }
  };
  Moments& at(int x, int y) { return table_[static_cast<size_t>(y) * (n_ + 1) + x]; }
  const Moments& at(int x, int y) const { return table_[static_cast<size_t>(y) * (n_ + 1) + x]; }

  const EffectField& field_;
  int n_;
  std::vector<Moments> table_;
};

}  // namespace

double EffectField::sample(const Eigen::Vector2d& p) const {
  const double u = (p.x() - origin.x()) / cell_size - 0.5;
  const double v = (p.y() - origin.y()) / cell_size - 0.5;
  if (!(u > -1.0 && v > -1.0 && u < resolution && v < resolution)) return 0.0;
  const int i0 = static_cast<int>(std::floor(u));
  const int j0 = static_cast<int>(std::floor(v));
  const double fu = u - i0, fv = v - j0;
  double sum = 0.0;
  for (int dj = 0; dj < 2; ++dj) {
    for (int di = 0; di < 2; ++di) {
      const int i = i0 + di, j = j0 + dj;
      if (i < 0 || j < 0 || i >= resolution || j >= resolution) continue;
      sum += (di ? fu : 1.0 - fu) * (dj ? fv : 1.0 - fv) * values(i, j);
    }
  }
  return sum;
}

namespace {

// Throws EngineError(invalid_argument) naming the first bad input.
void check_field_input(const ChartPoints& points, const Eigen::VectorXd& weights, const EffectFieldOptions& options) {
  if (points.rows() != weights.size()) {
    throw EngineError(Status::invalid_argument, "effect field: " + std::to_string(points.rows()) + " points but " +
                                                    std::to_string(weights.size()) + " weights");
  }
  if (points.rows() == 0) throw EngineError(Status::invalid_argument, "effect field: no points");
  if (options.grid_resolution < 16 || options.grid_resolution > 4096) {
    throw EngineError(Status::invalid_argument, "effect field: grid_resolution must be in 16..4096, got " +
                                                    std::to_string(options.grid_resolution));
  }
  if (!(options.effect_radius >= 0.0) || !std::isfinite(options.effect_radius)) {
    throw EngineError(Status::invalid_argument, "effect field: effect_radius must be finite and >= 0");
  }
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (!points.row(i).allFinite()) {
      throw EngineError(Status::invalid_argument, "effect field: point " + std::to_string(i) + " is not finite");
    }
    if (!(weights[i] >= 0.0) || !std::isfinite(weights[i])) {
      throw EngineError(Status::invalid_argument,
                        "effect field: weight " + std::to_string(i) + " is negative or not finite");
    }
  }
}

// The points binned into the cells of the grid: per cell their weight,
// count, weighted position sums and second moments, and the occupied cells'
// sources.
struct Bins {
  std::vector<double> weight;
  std::vector<int> count;
  std::vector<Eigen::Vector2d> sum, plain_sum;
  std::vector<Eigen::Matrix2d> outer;
  std::vector<int> source;  // per cell: its index in EffectField::sources, -1 when empty
};

// Sets the field's window (resolution, cell size, origin: the points'
// bounding square, kPadCells cells of margin) and returns its extent (the
// bounding square's side).
double place_window(EffectField& field, const ChartPoints& points, int resolution) {
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    lo = lo.cwiseMin(points.row(i).transpose());
    hi = hi.cwiseMax(points.row(i).transpose());
  }
  field.resolution = resolution;
  // A window that cannot collapse: all points equal still get a tiny one.
  const double extent = std::max((hi - lo).maxCoeff(), 1e-9);
  const double side = extent / (1.0 - 2.0 * kPadCells / resolution);
  field.cell_size = side / resolution;
  field.origin = 0.5 * (lo + hi) - Eigen::Vector2d::Constant(0.5 * side);
  return extent;
}

// Bins the points into the field's cells and fills field.sources (in cell
// order) and field.total_weight. Without any positive weight every point
// weighs 1.
Bins bin_points(EffectField& field, const ChartPoints& points, const Eigen::VectorXd& weights) {
  const int n = field.resolution;
  const double h = field.cell_size;
  const bool any_weight = (weights.array() > 0.0).any();
  const size_t cells = static_cast<size_t>(n) * n;
  Bins bins{std::vector<double>(cells, 0.0),
            std::vector<int>(cells, 0),
            std::vector<Eigen::Vector2d>(cells, Eigen::Vector2d::Zero()),
            std::vector<Eigen::Vector2d>(cells, Eigen::Vector2d::Zero()),
            std::vector<Eigen::Matrix2d>(cells, Eigen::Matrix2d::Zero()),
            std::vector<int>(cells, -1)};
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector2d p = points.row(i).transpose();
    const int ix = clamp_index((p.x() - field.origin.x()) / h, n);
    const int iy = clamp_index((p.y() - field.origin.y()) / h, n);
    const size_t c = static_cast<size_t>(iy) * n + ix;
    const double w = any_weight ? weights[i] : 1.0;
    bins.weight[c] += w;
    bins.count[c] += 1;
    bins.sum[c] += w * p;
    bins.outer[c] += w * p * p.transpose();
    bins.plain_sum[c] += p;
  }
  for (size_t c = 0; c < cells; ++c) {
    if (bins.count[c] == 0) continue;
    FieldSource s;
    s.weight = bins.weight[c];
    s.count = bins.count[c];
    s.position =
        s.weight > 0.0 ? Eigen::Vector2d(bins.sum[c] / s.weight) : Eigen::Vector2d(bins.plain_sum[c] / s.count);
    bins.source[c] = static_cast<int>(field.sources.size());
    field.sources.push_back(s);
    field.total_weight += s.weight;
  }
  return bins;
}

// The automatic effect radius (see automatic_effect_radius in the header).
double automatic_radius(const EffectField& field, const Bins& bins, const ThicknessProbe& probe, double extent) {
  const double h = field.cell_size;
  std::vector<double> gaps = nearest_source_gaps(field, bins.source);
  double g90 = 0.0;
  if (!gaps.empty()) {
    const size_t k = std::min(gaps.size() - 1, static_cast<size_t>(0.9 * gaps.size()));
    std::nth_element(gaps.begin(), gaps.begin() + k, gaps.end());
    g90 = gaps[k];
  }
  const double linked = linking_distance(field, bins.source, 4.0);
  const double lower = 3.0 * h;
  const double upper = std::max(0.25 * extent, lower);
  double radius = std::min(upper, std::max(lower, std::max({0.08 * extent, 1.5 * g90, 2.0 * linked})));
  // Wider than three times the across-curve scatter, so the field is one
  // ridge across a noisy curve (and one smooth bump on a noisy plane) rather
  // than a ridge per clump of noise. The scatter measured depends on the
  // window for a 2-D blob, hence the few rounds.
  for (int round = 0; round < 8 && radius < upper; ++round) {
    const double wanted = 3.3 * probe.thickness(radius);
    if (wanted <= radius) break;
    radius = std::min(upper, wanted);
  }
  return radius;
}

// With a wide kernel the cells are much finer than the field needs (its
// features are ~R/3 wide): the sources splatted from blocks of b x b cells,
// b = R / (6 h), each a source at its weighted centroid. Keeps the cost near
// O(cells * 36 * pi) whatever R is, at no visible change of the field.
std::vector<FieldSource> splat_sources(const EffectField& field) {
  const int n = field.resolution;
  const double h = field.cell_size;
  const int block = std::max(1, static_cast<int>(std::floor(field.effect_radius / (6.0 * h))));
  if (block == 1) return field.sources;
  const int nb = (n + block - 1) / block;
  std::vector<FieldSource> merged(static_cast<size_t>(nb) * nb);
  for (auto& m : merged) m.position.setZero();
  for (const FieldSource& src : field.sources) {
    const int bx = clamp_index((src.position.x() - field.origin.x()) / h, n) / block;
    const int by = clamp_index((src.position.y() - field.origin.y()) / h, n) / block;
    FieldSource& m = merged[static_cast<size_t>(by) * nb + bx];
    m.position += src.weight * src.position;
    m.weight += src.weight;
    m.count += src.count;
  }
  std::vector<FieldSource> splat;
  for (FieldSource& m : merged) {
    if (m.weight > 0.0) {
      m.position /= m.weight;
      splat.push_back(m);
    }
  }
  return splat;
}

// Adds every source's kernel over the cells of its effect region to
// field.values (Eq. 1 with the density term r(p) = share(cell) * R, the
// paper's k = 1).
void splat_field(EffectField& field, const std::vector<FieldSource>& splat) {
  const int n = field.resolution;
  const double h = field.cell_size;
  const double radius = field.effect_radius;
  field.values = Eigen::MatrixXd::Zero(n, n);
  const double rho0_2 = field.base_softening * field.base_softening;
  const double radius2 = radius * radius;
  const double total = field.total_weight > 0.0 ? field.total_weight : 1.0;
  // Most cells hold a small share of the patch, so their r(p) is negligible
  // against rho0 and they share one kernel: tabulate it in d^2 (linear
  // interpolation, relative error ~1e-5) instead of a sqrt per cell.
  constexpr int kTable = 2048;
  std::vector<double> table(kTable + 2);
  const double base_cut = 1.0 / std::sqrt(radius2 + rho0_2);
  for (int k = 0; k <= kTable + 1; ++k) {
    const double d2 = radius2 * k / kTable;
    table[k] = 1.0 / std::sqrt(d2 + rho0_2) - base_cut;
  }
  const double to_table = kTable / radius2;
  for (const FieldSource& s : splat) {
    if (!(s.weight > 0.0)) continue;
    const double r = (s.weight / total) * radius;
    const double rho2 = rho0_2 + r * r;
    const double cut = 1.0 / std::sqrt(radius2 + rho2);
    const bool tabulated = r * r <= 1e-4 * rho0_2;
    const double u = (s.position.x() - field.origin.x()) / h - 0.5;  // cell-centre coordinates
    const double v = (s.position.y() - field.origin.y()) / h - 0.5;
    const double rc = radius / h;
    const int ix0 = std::max(0, static_cast<int>(std::ceil(u - rc)));
    const int ix1 = std::min(n - 1, static_cast<int>(std::floor(u + rc)));
    const int iy0 = std::max(0, static_cast<int>(std::ceil(v - rc)));
    const int iy1 = std::min(n - 1, static_cast<int>(std::floor(v + rc)));
    for (int iy = iy0; iy <= iy1; ++iy) {
      const double dy = (iy - v) * h;
      const double base = dy * dy + rho2;
      if (dy * dy >= radius2) continue;
      double* column = &field.values(0, iy);
      if (tabulated) {
        for (int ix = ix0; ix <= ix1; ++ix) {
          const double dx = (ix - u) * h;
          const double d2 = dx * dx + dy * dy;
          if (d2 >= radius2) continue;
          const double x = d2 * to_table;
          const int k = static_cast<int>(x);
          const double f = x - k;
          column[ix] += s.weight * (table[k] + f * (table[k + 1] - table[k]));
        }
      } else {
        for (int ix = ix0; ix <= ix1; ++ix) {
          const double dx = (ix - u) * h;
          if (dx * dx + dy * dy >= radius2) continue;
          column[ix] += s.weight * (1.0 / std::sqrt(dx * dx + base) - cut);
        }
      }
    }
  }
}

}  // namespace

EffectField compute_effect_field(const ChartPoints& points, const Eigen::VectorXd& weights,
                                 const EffectFieldOptions& options) {
  check_field_input(points, weights, options);
  EffectField field;
  const double extent = place_window(field, points, options.grid_resolution);
  const Bins bins = bin_points(field, points, weights);
  const ThicknessProbe probe(field, bins.weight, bins.sum, bins.outer);
  double radius = options.effect_radius == 0.0 ? automatic_radius(field, bins, probe, extent) : options.effect_radius;
  // A radius below one cell would leave only isolated spikes.
  radius = std::max(radius, field.cell_size);
  field.thickness = probe.thickness(radius);
  field.effect_radius = radius;
  field.base_softening = std::max(radius / 3.0, field.cell_size);
  splat_field(field, splat_sources(field));
  return field;
}

}  // namespace developable

#include "ideal_curve.h"

#include "effect_field.h"
#include "gauss_chart.h"
#include "skeleton.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>

namespace developable {

namespace {

// ---------------------------------------------------------------------------
// Cubic B-splines in the chart: clamped with uniform interior knots when
// open (the curve starts and ends at its end control points), uniform
// periodic when closed. Parameter t in [0, 1].

struct Spline {
  std::vector<Eigen::Vector2d> ctrl;
  bool closed = false;
};

// Basis values b[0..3] of the control points first .. first+3 (mod n if closed).
int basis(int n, bool closed, double t, double b[4]) {
  if (closed) {
    double u = (t - std::floor(t)) * n;
    int seg = std::min(n - 1, std::max(0, static_cast<int>(std::floor(u))));
    const double s = u - seg, s2 = s * s, s3 = s2 * s;
    b[0] = (1.0 - s) * (1.0 - s) * (1.0 - s) / 6.0;
    b[1] = (3.0 * s3 - 6.0 * s2 + 4.0) / 6.0;
    b[2] = (-3.0 * s3 + 3.0 * s2 + 3.0 * s + 1.0) / 6.0;
    b[3] = s3 / 6.0;
    return seg;
  }
  // Clamped knots 0,0,0,0, 1/(n-3), ..., 1,1,1,1 (n + 4 of them).
  const int spans = n - 3;
  auto knot = [&](int i) { return std::min(1.0, std::max(0.0, static_cast<double>(i - 3) / spans)); };
  t = std::min(1.0, std::max(0.0, t));
  const int span = std::min(n - 1, 3 + static_cast<int>(std::floor(t * spans)));
  // Cox-de Boor (The NURBS Book, A2.2).
  double left[4], right[4];
  b[0] = 1.0;
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - knot(span + 1 - j);
    right[j] = knot(span + j) - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom > 0.0 ? b[r] / denom : 0.0;
      b[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    b[j] = saved;
  }
  return span - 3;
}

Eigen::Vector2d evaluate(const Spline& s, double t) {
  const int n = static_cast<int>(s.ctrl.size());
  double b[4];
  const int first = basis(n, s.closed, t, b);
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int k = 0; k < 4; ++k) p += b[k] * s.ctrl[(first + k) % n];
  return p;
}

// Weighted least squares with a small second-difference penalty on the
// control polygon: keeps the system well-posed where data are missing (the
// polygon is bridged straight) while barely biasing a well-sampled curve.
// Relative weight 1e-4 shrinks a 16-point circle by ~3e-6 of its radius.
Spline fit_spline(const std::vector<Eigen::Vector2d>& data, const std::vector<double>& params,
                  const std::vector<double>& weights, int n, bool closed) {
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  for (size_t i = 0; i < data.size(); ++i) {
    double b[4];
    const int first = basis(n, closed, params[i], b);
    for (int a = 0; a < 4; ++a) {
      const int ia = (first + a) % n;
      rhs.row(ia) += weights[i] * b[a] * data[i].transpose();
      for (int c = 0; c < 4; ++c) normal(ia, (first + c) % n) += weights[i] * b[a] * b[c];
    }
  }
  const double scale = normal.trace() > 0.0 ? normal.trace() / n : 1.0;
  const double lambda = 1e-4 * scale;
  const int rows = closed ? n : n - 2;
  for (int r = 0; r < rows; ++r) {
    const int idx[3] = {r % n, (r + 1) % n, (r + 2) % n};
    const double coef[3] = {1.0, -2.0, 1.0};
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) normal(idx[a], idx[c]) += lambda * coef[a] * coef[c];
    }
  }
  normal.diagonal().array() += 1e-12 * scale;  // all data at one parameter
  const Eigen::MatrixXd solution = normal.ldlt().solve(rhs);
  Spline s;
  s.closed = closed;
  s.ctrl.resize(n);
  for (int i = 0; i < n; ++i) s.ctrl[i] = solution.row(i).transpose();
  if (!solution.allFinite()) {
    throw EngineError(Status::numerical_failure, "ideal curve: B-spline fit is not finite");
  }
  return s;
}

// Chart polyline samples per control point for projections: a chord of
// 1/8 of a control span leaves a circle of 16 control points by < 1e-4 of
// its radius.
constexpr int kSamplesPerControl = 8;

// A spline sampled densely, for projections.
struct Polyline {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> params;
  bool closed = false;
};

Polyline sample_spline(const Spline& s, int count) {
  Polyline p;
  p.closed = s.closed;
  for (int i = 0; i < count; ++i) {
    const double t = s.closed ? static_cast<double>(i) / count : static_cast<double>(i) / (count - 1);
    p.points.push_back(evaluate(s, t));
    p.params.push_back(t);
  }
  return p;
}

// Nearest point of a set of chart polylines, with bounding circles over runs
// of segments so that a query touches few segments.
class ChartNearest {
 public:
  struct Hit {
    int curve = -1;
    double param = 0.0;
    double dist2 = INFINITY;
  };

  explicit ChartNearest(const std::vector<Polyline>& lines) : lines_(lines) {
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

  // Nearest point; for open polylines a query beyond an end is extended along
  // the end tangent to a parameter outside [0, 1] (so a refit can grow the
  // curve to cover its data).
  // `warm` is the group to search first (a nearby query's answer, so the
  // bound is tight early); it becomes the group of this answer.
  Hit nearest(const Eigen::Vector2d& q, int& warm) const {
    Hit hit;
    int best_c = -1, best_s = -1, best_g = -1;
    double best_f = 0.0;
    const int groups = static_cast<int>(groups_.size());
    warm = std::min(std::max(warm, 0), groups - 1);
    for (int k = -1; k < groups; ++k) {
      if (k == warm) continue;
      const int gi = k < 0 ? warm : k;
      const Group& g = groups_[gi];
      const double d = (q - g.center).norm() - g.radius;
      if (d > 0.0 && d * d >= hit.dist2) continue;
      for (int s = g.begin; s < g.end; ++s) {
        const Eigen::Vector2d a = point(g.curve, s), ab = point(g.curve, s + 1) - a;
        const double len2 = ab.squaredNorm();
        const double f = len2 > 0.0 ? std::min(1.0, std::max(0.0, (q - a).dot(ab) / len2)) : 0.0;
        const double d2 = (a + f * ab - q).squaredNorm();
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
    const Polyline& line = lines_[best_c];
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
  const std::vector<Polyline>& lines_;
  std::vector<Group> groups_;
};

// Control points: about one per effect radius of curve, 4 (6 closed) to 16.
int control_count(double length, double radius, bool closed) {
  const double wanted = radius > 0.0 ? std::round(length / radius) : 16.0;
  return static_cast<int>(std::min(16.0, std::max(closed ? 6.0 : 4.0, wanted)));
}

Spline fit_skeleton(const SkeletonCurve& curve, double radius) {
  const auto& pts = curve.points;
  std::vector<double> params(pts.size(), 0.0);
  for (size_t i = 1; i < pts.size(); ++i) params[i] = params[i - 1] + (pts[i] - pts[i - 1]).norm();
  double total = params.back();
  if (curve.closed) total += (pts.front() - pts.back()).norm();
  if (total > 0.0) {
    for (double& t : params) t /= total;
  }
  const std::vector<double> weights(pts.size(), 1.0);
  return fit_spline(pts, params, weights, control_count(total, radius, curve.closed), curve.closed);
}

double weighted_quantile(const std::vector<double>& values, const std::vector<double>& weights, double q) {
  std::vector<size_t> order(values.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return values[a] < values[b]; });
  double total = 0.0;
  for (double w : weights) total += w;
  double acc = 0.0;
  for (size_t i : order) {
    acc += weights[i];
    if (acc >= q * total) return values[i];
  }
  return values[order.back()];
}

// Refits the splines to the field's sources (cell centroids weighted by
// area): the skeleton is quantised to the grid, the centroids are not, so
// this reaches sub-cell accuracy. Each source is given to its nearest curve
// if within the effect radius (farther ones are outliers), with the parameter
// of its projection (Hastie-Stuetzle principal-curve step).
// Returns, per curve, how many sources the last round gave it.
std::vector<int> refine(std::vector<Spline>& splines, const EffectField& field, int rounds) {
  const double reach2 = field.effect_radius * field.effect_radius;
  std::vector<int> support(splines.size(), 0);
  for (int round = 0; round < rounds; ++round) {
    std::vector<Polyline> lines;
    for (const Spline& s : splines) lines.push_back(sample_spline(s, kSamplesPerControl * static_cast<int>(s.ctrl.size())));
    const ChartNearest search(lines);
    int warm = 0;
    std::vector<std::vector<Eigen::Vector2d>> data(splines.size());
    std::vector<std::vector<double>> params(splines.size()), weights(splines.size());
    for (const FieldSource& src : field.sources) {
      if (!(src.weight > 0.0)) continue;
      const ChartNearest::Hit hit = search.nearest(src.position, warm);
      if (hit.curve < 0 || hit.dist2 > reach2) continue;
      data[hit.curve].push_back(src.position);
      params[hit.curve].push_back(hit.param);
      weights[hit.curve].push_back(src.weight);
    }
    for (size_t c = 0; c < splines.size(); ++c) {
      support[c] = static_cast<int>(data[c].size());
      if (data[c].size() < 4) continue;  // too little to refit: keep the skeleton fit
      Spline& s = splines[c];
      if (!s.closed) {
        // The data's projections span the curve: map the 0.2 % .. 99.8 %
        // weighted quantiles to [0, 1] (so a few noisy points beyond an end
        // do not drag it out; they are clamped to the end instead).
        const double t0 = weighted_quantile(params[c], weights[c], 0.002);
        const double t1 = weighted_quantile(params[c], weights[c], 0.998);
        // For evenly spread data the quantiles sit 0.2 % of the span inside
        // the true ends: step back out by that much.
        const double pad = (0.002 / 0.996) * (t1 - t0);
        const double span = t1 - t0 + 2.0 * pad;
        if (!(span > 1e-9)) continue;
        for (double& t : params[c]) t = std::min(1.0, std::max(0.0, (t - t0 + pad) / span));
      }
      s = fit_spline(data[c], params[c], weights[c], static_cast<int>(s.ctrl.size()), s.closed);
    }
  }
  return support;
}

// See the planar test in fit_ideal_curves: a noisy arc shorter than ~10
// noise widths counts as a point.
constexpr double kMaxResidualOverSpread = 0.35;

SphereCurve single_point(const Eigen::Vector3d& p) {
  SphereCurve c;
  c.points.push_back(p);
  return c;
}

}  // namespace

std::vector<SphereCurve> fit_ideal_curves(const Normals& normals, const Eigen::VectorXd& weights,
                                          const IdealCurveOptions& options) {
  if (normals.rows() != weights.size()) {
    throw EngineError(Status::invalid_argument, "ideal curve: " + std::to_string(normals.rows()) +
                                                    " normals but " + std::to_string(weights.size()) +
                                                    " weights");
  }
  if (normals.rows() == 0) throw EngineError(Status::invalid_argument, "ideal curve: empty patch");
  if (options.samples_per_curve < 2 || options.samples_per_curve > 1000000) {
    throw EngineError(Status::invalid_argument, "ideal curve: samples_per_curve must be in 2..1000000, got " +
                                                    std::to_string(options.samples_per_curve));
  }
  // Clean copies: unit normals; zero-length normals (collapsed faces) weigh 0.
  const Eigen::Index count = normals.rows();
  Normals unit(count, 3);
  Eigen::VectorXd w(count);
  bool any_weight = false;
  int usable = 0;
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Vector3d n = normals.row(i).transpose();
    if (!n.allFinite()) {
      throw EngineError(Status::invalid_argument, "ideal curve: normal " + std::to_string(i) + " is not finite");
    }
    if (!(weights[i] >= 0.0) || !std::isfinite(weights[i])) {
      throw EngineError(Status::invalid_argument,
                        "ideal curve: weight " + std::to_string(i) + " is negative or not finite");
    }
    const double length = n.norm();
    unit.row(i) = length > 0.0 ? Eigen::RowVector3d(n.transpose() / length) : Eigen::RowVector3d::Zero();
    w[i] = length > 0.0 ? weights[i] : 0.0;
    any_weight = any_weight || w[i] > 0.0;
    usable += length > 0.0;
  }
  if (usable == 0) throw EngineError(Status::invalid_argument, "ideal curve: every normal has zero length");
  if (!any_weight) {
    for (Eigen::Index i = 0; i < count; ++i) w[i] = unit.row(i).squaredNorm() > 0.0 ? 1.0 : 0.0;
  }

  // The planar answer: the weighted mean normal (the heaviest normal if the
  // mean vanishes, e.g. two opposite normals).
  Eigen::Vector3d mean = (unit.transpose() * w);
  if (mean.norm() > 1e-9 * w.sum()) {
    mean.normalize();
  } else {
    Eigen::Index k = 0;
    w.maxCoeff(&k);
    mean = unit.row(k).transpose();
  }
  double max_dev = 0.0;
  for (Eigen::Index i = 0; i < count; ++i) {
    if (w[i] > 0.0) max_dev = std::max(max_dev, (unit.row(i).transpose() - mean).norm());
  }
  if (usable < 4 || max_dev < 1e-7) return {single_point(mean)};

  const GaussChart chart(choose_chart_pole(unit, w));
  const ChartPoints points = project_to_chart(chart, unit);
  EffectFieldOptions field_options;
  field_options.grid_resolution =
      options.grid_resolution > 0 ? options.grid_resolution : automatic_grid_resolution(count);
  field_options.effect_radius = options.effect_radius;
  field_options.density_scale = options.density_scale;
  const EffectField field = compute_effect_field(points, w, field_options);
  const std::vector<SkeletonCurve> skeleton = extract_skeleton(field, SkeletonOptions());
  if (skeleton.empty()) return {single_point(mean)};

  std::vector<Spline> splines;
  for (const SkeletonCurve& s : skeleton) splines.push_back(fit_skeleton(s, field.effect_radius));
  const std::vector<int> support = refine(splines, field, 4);

  // Planar after all when the curves barely explain the points: their RMS
  // distance to the curves is a large part of their RMS spread about the
  // centroid (a 2-D blob with a few ridges through its noise).
  {
    std::vector<Polyline> lines;
    for (const Spline& s : splines) lines.push_back(sample_spline(s, kSamplesPerControl * static_cast<int>(s.ctrl.size())));
    const ChartNearest search(lines);
    int warm = 0;
    double total = 0.0, residual = 0.0, spread = 0.0;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const FieldSource& src : field.sources) {
      total += src.weight;
      centroid += src.weight * src.position;
      residual += src.weight * search.nearest(src.position, warm).dist2;
    }
    if (total > 0.0) {
      centroid /= total;
      for (const FieldSource& src : field.sources) spread += src.weight * (src.position - centroid).squaredNorm();
      if (residual > kMaxResidualOverSpread * kMaxResidualOverSpread * spread) return {single_point(mean)};
    }
  }

  std::vector<SphereCurve> curves;
  for (size_t k = 0; k < splines.size(); ++k) {
    // A curve through fewer than 3 occupied cells is a guess, not a fit
    // (typical of a handful of scattered normals).
    if (support[k] < 3) continue;
    const Spline& s = splines[k];
    SphereCurve c;
    c.closed = s.closed;
    const Polyline line = sample_spline(s, options.samples_per_curve);
    c.points.reserve(line.points.size());
    for (const auto& p : line.points) c.points.push_back(chart.to_sphere(p));
    curves.push_back(std::move(c));
  }
  if (curves.empty()) return {single_point(mean)};
  return curves;
}

int automatic_grid_resolution(Eigen::Index normal_count) {
  const double cells = 2.0 * std::sqrt(static_cast<double>(std::max<Eigen::Index>(normal_count, 0)));
  return static_cast<int>(std::clamp(std::lround(cells), 32L, 128L));
}

}  // namespace developable

#include "ideal_curve/ideal_curve.h"

#include "ideal_curve/bspline.h"
#include "ideal_curve/effect_field.h"
#include "ideal_curve/gauss_chart.h"
#include "ideal_curve/polyline_search.h"
#include "ideal_curve/skeleton.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace developable {

namespace {

// Chart polyline samples per control point for projections: a chord of
// 1/8 of a control span leaves a circle of 16 control points by < 1e-4 of
// its radius.
constexpr int kSamplesPerControl = 8;

// Control points: about one per effect radius of curve, 4 (6 closed) to 16.
int control_count(double length, double radius, bool closed) {
  const double wanted = radius > 0.0 ? std::round(length / radius) : 16.0;
  return static_cast<int>(std::min(16.0, std::max(closed ? 6.0 : 4.0, wanted)));
}

BSpline fit_skeleton(const SkeletonCurve& curve, double radius) {
  const auto& pts = curve.points;
  std::vector<double> params(pts.size(), 0.0);
  for (size_t i = 1; i < pts.size(); ++i) params[i] = params[i - 1] + (pts[i] - pts[i - 1]).norm();
  double total = params.back();
  if (curve.closed) total += (pts.front() - pts.back()).norm();
  if (total > 0.0) {
    for (double& t : params) t /= total;
  }
  const std::vector<double> weights(pts.size(), 1.0);
  return fit_bspline(pts, params, weights, control_count(total, radius, curve.closed), curve.closed);
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
std::vector<int> refine(std::vector<BSpline>& splines, const EffectField& field, int rounds) {
  const double reach2 = field.effect_radius * field.effect_radius;
  std::vector<int> support(splines.size(), 0);
  for (int round = 0; round < rounds; ++round) {
    std::vector<ChartPolyline> lines;
    for (const BSpline& s : splines)
      lines.push_back(sample_bspline(s, kSamplesPerControl * static_cast<int>(s.ctrl.size())));
    const ChartPolylineSearch search(lines);
    int warm = 0;
    std::vector<std::vector<Eigen::Vector2d>> data(splines.size());
    std::vector<std::vector<double>> params(splines.size()), weights(splines.size());
    for (const FieldSource& src : field.sources) {
      if (!(src.weight > 0.0)) continue;
      const ChartPolylineSearch::Hit hit = search.nearest(src.position, warm);
      if (hit.curve < 0 || hit.dist2 > reach2) continue;
      data[hit.curve].push_back(src.position);
      params[hit.curve].push_back(hit.param);
      weights[hit.curve].push_back(src.weight);
    }
    for (size_t c = 0; c < splines.size(); ++c) {
      support[c] = static_cast<int>(data[c].size());
      if (data[c].size() < 4) continue;  // too little to refit: keep the skeleton fit
      BSpline& s = splines[c];
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
      s = fit_bspline(data[c], params[c], weights[c], static_cast<int>(s.ctrl.size()), s.closed);
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
    throw EngineError(Status::invalid_argument, "ideal curve: " + std::to_string(normals.rows()) + " normals but " +
                                                    std::to_string(weights.size()) + " weights");
  }
  if (normals.rows() == 0) throw EngineError(Status::invalid_argument, "ideal curve: empty patch");
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
  const EffectField field = compute_effect_field(points, w, field_options);
  const std::vector<SkeletonCurve> skeleton = extract_skeleton(field, SkeletonOptions());
  if (skeleton.empty()) return {single_point(mean)};

  std::vector<BSpline> splines;
  for (const SkeletonCurve& s : skeleton) splines.push_back(fit_skeleton(s, field.effect_radius));
  const std::vector<int> support = refine(splines, field, 4);

  // Planar after all when the curves barely explain the points: their RMS
  // distance to the curves is a large part of their RMS spread about the
  // centroid (a 2-D blob with a few ridges through its noise).
  {
    std::vector<ChartPolyline> lines;
    for (const BSpline& s : splines)
      lines.push_back(sample_bspline(s, kSamplesPerControl * static_cast<int>(s.ctrl.size())));
    const ChartPolylineSearch search(lines);
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
    const BSpline& s = splines[k];
    SphereCurve c;
    c.closed = s.closed;
    const ChartPolyline line = sample_bspline(s, kSamplesPerCurve);
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

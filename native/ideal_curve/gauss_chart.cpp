#include "ideal_curve/gauss_chart.h"

#include "core/cone_fit.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace developable {

namespace {

// Below this |weighted mean normal| the normals spread over much of the sphere
// (e.g. a 240 degree arc of a cylinder has |mean| = 0.41) and the plane-fit
// axis is the better pole.
constexpr double kShortMean = 0.7;

bool usable(const Eigen::Vector3d& n) { return n.allFinite() && n.squaredNorm() > 1e-300; }

}  // namespace

Eigen::Vector3d choose_chart_pole(const Normals& normals, const Eigen::VectorXd& weights) {
  if (normals.rows() != weights.size()) {
    throw EngineError(Status::invalid_argument, "gauss chart: " + std::to_string(normals.rows()) + " normals but " +
                                                    std::to_string(weights.size()) + " weights");
  }
  // All-zero weights (e.g. a patch of slivers) count as uniform: better a
  // pole than a refusal.
  bool any_weight = false;
  for (Eigen::Index i = 0; i < weights.size(); ++i) {
    if (!(weights[i] >= 0.0) || !std::isfinite(weights[i])) {
      throw EngineError(Status::invalid_argument,
                        "gauss chart: weight " + std::to_string(i) + " is negative or not finite");
    }
    any_weight = any_weight || weights[i] > 0.0;
  }
  double total = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    const Eigen::Vector3d n = normals.row(i).transpose();
    if (!usable(n)) continue;
    const double w = any_weight ? weights[i] : 1.0;
    sum += w * n.normalized();
    total += w;
  }
  if (!(total > 0.0)) {
    throw EngineError(Status::invalid_argument, "gauss chart: no normal with positive weight");
  }
  const Eigen::Vector3d mean = sum / total;
  const double mean_length = mean.norm();
  if (mean_length >= kShortMean) return mean / mean_length;

  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    const Eigen::Vector3d n = normals.row(i).transpose();
    if (!usable(n)) continue;
    const double w = any_weight ? weights[i] : 1.0;
    const Eigen::Vector3d d = n.normalized() - mean;
    cov += w * d * d.transpose();
  }

  // The axis of the weighted plane fit (cone_fit.h), oriented toward the
  // mean, so a cone's circle sits at its half-angle (< 90 degrees) rather
  // than at 180 minus it; for a full cylinder either sign is as good and
  // the largest component positive keeps it deterministic.
  const NormalPlaneFit plane = fit_normal_plane(mean, cov / total);
  if (!plane.found) {
    return mean_length > 0.0 ? Eigen::Vector3d(mean / mean_length) : Eigen::Vector3d::UnitZ();
  }
  return plane.axis;
}

GaussChart::GaussChart(const Eigen::Vector3d& pole) {
  if (!usable(pole)) {
    throw EngineError(Status::invalid_argument, "gauss chart: pole is zero or not finite");
  }
  pole_ = pole.normalized();
  // e1: the world axis least aligned with the pole, made orthogonal to it.
  Eigen::Index k = 0;
  pole_.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d e1 = Eigen::Vector3d::Unit(k).cross(pole_).normalized();
  const Eigen::Vector3d e2 = pole_.cross(e1);
  frame_.row(0) = e1.transpose();
  frame_.row(1) = e2.transpose();
  frame_.row(2) = pole_.transpose();
}

Eigen::Vector2d GaussChart::to_chart(const Eigen::Vector3d& n) const {
  const double length = n.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Vector2d::Zero();
  const Eigen::Vector3d r = frame_ * (n / length);
  const double z = std::max(-1.0, std::min(1.0, r.z()));
  // sqrt(2/(1+z)) * (x, y) has |(x, y)| = sqrt((1-z)(1+z)), so its length is
  // sqrt(2(1-z)); written this way nothing divides by 1+z.
  const double radius = std::sqrt(2.0 * (1.0 - z));
  const double planar = std::sqrt(r.x() * r.x() + r.y() * r.y());
  if (planar < 1e-300) return z > 0.0 ? Eigen::Vector2d::Zero() : Eigen::Vector2d(radius, 0.0);
  return Eigen::Vector2d(r.x(), r.y()) * (radius / planar);
}

Eigen::Vector3d GaussChart::to_sphere(const Eigen::Vector2d& p) const {
  double rho2 = p.squaredNorm();
  if (!std::isfinite(rho2)) return -pole_;
  Eigen::Vector2d q = p;
  if (rho2 > 4.0) {  // outside the chart: clamp to the rim
    q *= 2.0 / std::sqrt(rho2);
    rho2 = 4.0;
  }
  const double z = 1.0 - 0.5 * rho2;
  const double s = std::sqrt(std::max(0.0, 1.0 - 0.25 * rho2));
  const Eigen::Vector3d local(q.x() * s, q.y() * s, z);
  return (frame_.transpose() * local).normalized();
}

ChartPoints project_to_chart(const GaussChart& chart, const Normals& normals) {
  ChartPoints points(normals.rows(), 2);
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    points.row(i) = chart.to_chart(normals.row(i).transpose()).transpose();
  }
  return points;
}

}  // namespace developable

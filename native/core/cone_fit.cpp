#include "core/cone_fit.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace developable {

namespace {

// Below this spread (rad) of the normals about their mean, the covariance
// carries no direction worth trusting: treat the set as a plane.
constexpr double kPlanarSpread = 1e-3;

}  // namespace

void NormalMoments::add(const Eigen::Vector3d& normal, double w) {
  weight += w;
  sum += w * normal;
  outer += w * normal * normal.transpose();
}

NormalMoments& NormalMoments::operator+=(const NormalMoments& other) {
  weight += other.weight;
  sum += other.sum;
  outer += other.outer;
  return *this;
}

NormalPlaneFit fit_normal_plane(const Eigen::Vector3d& mean, const Eigen::Matrix3d& covariance) {
  NormalPlaneFit fit;
  fit.mean = mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  fit.eigenvalues = eigen.eigenvalues().cwiseMax(0.0);  // ascending
  Eigen::Vector3d axis = eigen.eigenvectors().col(0);
  if (!axis.allFinite() || axis.squaredNorm() < 0.5) return fit;  // keeps UnitZ
  axis.normalize();
  // The cone of -axis at pi - angle is the same circle: toward the mean keeps
  // angle <= pi/2.
  double side = axis.dot(fit.mean);
  if (std::abs(side) < 1e-12) {
    Eigen::Index k = 0;
    axis.cwiseAbs().maxCoeff(&k);
    side = axis[k];
  }
  fit.axis = side < 0.0 ? Eigen::Vector3d(-axis) : axis;
  fit.found = true;
  return fit;
}

ConeFit fit_cone(const NormalMoments& moments) {
  ConeFit fit;
  if (!(moments.weight > 0.0)) return fit;
  const Eigen::Vector3d mean = moments.sum / moments.weight;
  const Eigen::Matrix3d covariance = moments.outer / moments.weight - mean * mean.transpose();
  const NormalPlaneFit plane = fit_normal_plane(mean, covariance);
  const double mean_norm = plane.mean.norm();
  if (plane.eigenvalues(2) < kPlanarSpread * kPlanarSpread && mean_norm > 0.0) {
    fit.cone.axis = plane.mean / mean_norm;
    fit.cone.angle = 0.0;
    fit.residual = moments.weight * fit.cone.axis.dot(covariance * fit.cone.axis);
    return fit;
  }
  fit.cone.axis = plane.axis;
  fit.cone.angle = std::acos(std::clamp(fit.cone.axis.dot(plane.mean), -1.0, 1.0));
  fit.residual = moments.weight * plane.eigenvalues(0);
  return fit;
}

double angle_to_cone(const Cone& cone, const Eigen::Vector3d& normal) {
  return std::abs(std::acos(std::clamp(cone.axis.dot(normal), -1.0, 1.0)) - cone.angle);
}

}  // namespace developable

#include "cone_fit.h"

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

ConeFit fit_cone(const NormalMoments& moments) {
  ConeFit fit;
  if (!(moments.weight > 0.0)) return fit;
  const Eigen::Vector3d mean = moments.sum / moments.weight;
  const Eigen::Matrix3d covariance = moments.outer / moments.weight - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d eigenvalues = eigen.eigenvalues().cwiseMax(0.0);  // ascending
  const double mean_norm = mean.norm();

  if (eigenvalues(2) < kPlanarSpread * kPlanarSpread && mean_norm > 0.0) {
    fit.cone.axis = mean / mean_norm;
    fit.cone.angle = 0.0;
    fit.residual = moments.weight * fit.cone.axis.dot(covariance * fit.cone.axis);
    return fit;
  }
  Eigen::Vector3d axis = eigen.eigenvectors().col(0);
  // The cone of -axis at pi - angle is the same circle: keep angle <= pi/2.
  if (axis.dot(mean) < 0.0) axis = -axis;
  fit.cone.axis = axis.normalized();
  fit.cone.angle = std::acos(std::clamp(fit.cone.axis.dot(mean), -1.0, 1.0));
  fit.residual = moments.weight * eigenvalues(0);
  return fit;
}

double angle_to_cone(const Cone& cone, const Eigen::Vector3d& normal) {
  return std::abs(std::acos(std::clamp(cone.axis.dot(normal), -1.0, 1.0)) - cone.angle);
}

}  // namespace developable

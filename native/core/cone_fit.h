// Cone of directions fitted to a set of unit normals (the Gauss image of a
// patch). A developable surface's normals lie on a curve of the sphere; a
// cone (a circle of the sphere) is the simplest such curve and covers planes
// (a point), cylinders (a great circle) and circular cones (a small circle).
#pragma once

#include <Eigen/Core>

namespace developable {

// The unit vectors at angle `angle` from `axis`: a circle of the unit sphere.
struct Cone {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit
  double angle = 0.0;                               // half-opening, rad, in [0, pi/2]; 0 is a plane's single normal
};

// Weighted first and second moments of a set of unit normals: enough to fit a
// cone, and additive, so that two sets merge without revisiting their faces.
struct NormalMoments {
  double weight = 0.0;                              // sum of w
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();    // sum of w n
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();  // sum of w n n^T

  void add(const Eigen::Vector3d& normal, double w);
  NormalMoments& operator+=(const NormalMoments& other);
};

// The weighted plane fit of a set of unit normals: the normals of a cone
// satisfy axis . n = cos(angle), a plane equation in n, so the axis is the
// direction in which they vary least.
struct NormalPlaneFit {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // weighted mean normal (not unit)
  // Eigenvector of the smallest eigenvalue of the weighted covariance about
  // the mean, unit, oriented toward the mean; when the mean is orthogonal to
  // it (|axis . mean| < 1e-12, a full cylinder) the largest component is
  // positive, so the sign is deterministic.
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  // of the covariance, ascending, >= 0
  bool found = false;  // false when the eigenvector was not finite (axis stays UnitZ)
};

// Fits the plane of normals given their weighted mean and their weighted
// covariance about it (from NormalMoments, or summed about the mean, which
// rounds less: choose_chart_pole in gauss_chart.h).
NormalPlaneFit fit_normal_plane(const Eigen::Vector3d& mean, const Eigen::Matrix3d& covariance);

struct ConeFit {
  Cone cone;
  // Weighted sum of squared algebraic residuals (axis . n - cos(angle))^2 of
  // the fit: zero when every normal lies on the cone. Units: weight.
  double residual = 0.0;
};

// Least-squares cone of the normals: the axis of their plane fit
// (fit_normal_plane) and cos(angle) = axis . mean. Closed form, no iteration.
// A set whose normals all lie within ~1e-3 rad (a plane) fits every axis; it
// gets axis = mean normal and angle 0. Zero total weight gives the default
// cone with residual 0.
ConeFit fit_cone(const NormalMoments& moments);

// Angle (rad, >= 0) on the sphere between a unit normal and the cone's circle.
double angle_to_cone(const Cone& cone, const Eigen::Vector3d& normal);

}  // namespace developable

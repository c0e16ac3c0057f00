// Cubic B-splines in the Gauss chart (the paper, Sec. III: "the ideal curve
// is fitted by a B-spline"): clamped with uniform interior knots when open
// (the curve starts and ends at its end control points), uniform periodic
// when closed. Parameter t in [0, 1]. Used by ideal_curve.cpp.
#pragma once

#include "core/types.h"
#include "ideal_curve/polyline_search.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

struct BSpline {
  std::vector<Eigen::Vector2d> ctrl;  // control points, chart units
  bool closed = false;
};

// Basis values b[0..3] at t of the control points first .. first+3 (mod n if
// closed), returning `first`. n >= 4 control points (open), >= 3 (closed);
// t outside [0, 1] is clamped (open) or wrapped (closed). The values are
// non-negative and sum to 1.
int bspline_basis(int n, bool closed, double t, double b[4]);

// The point of the spline at t.
Eigen::Vector2d evaluate(const BSpline& spline, double t);

// Weighted least-squares fit of n control points to data points at given
// parameters, with a small second-difference penalty on the control polygon:
// keeps the system well-posed where data are missing (the polygon is bridged
// straight) while barely biasing a well-sampled curve (relative weight 1e-4
// shrinks a 16-point circle by ~3e-6 of its radius).
//   data, params, weights: one parameter in [0, 1] and one weight >= 0 per point.
// Throws EngineError(numerical_failure) when the solution is not finite.
BSpline fit_bspline(const std::vector<Eigen::Vector2d>& data, const std::vector<double>& params,
                    const std::vector<double>& weights, int n, bool closed);

// `count` samples at evenly spaced parameters (the end excluded when closed),
// with their parameters.
ChartPolyline sample_bspline(const BSpline& spline, int count);

}  // namespace developable

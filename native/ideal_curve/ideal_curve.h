// Stage 6 of the pipeline: the ideal curve of a patch's Gauss image, and the
// target normals on it (paper, Sec. III).
//
// fit_ideal_curves() chains the stages before it: the Gauss image chart
// (gauss_chart.h), the radial effect field (effect_field.h) and its skeleton
// (skeleton.h). It fits a least-squares cubic B-spline to each ordered skeleton
// branch in the chart and lifts it back to the unit sphere as a dense polyline.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// One ideal curve on the unit sphere, as a dense polyline of unit vectors.
// A single point stands for a planar patch (its Gauss image is about a point).
struct SphereCurve {
  std::vector<Eigen::Vector3d> points;
  bool closed = false;  // the last point connects back to the first
};

struct IdealCurveOptions {
  // Effect-field grid: cells per side of the square chart window; 0 picks it
  // from the number of normals (automatic_grid_resolution).
  int grid_resolution = 0;
  // Effect-region threshold R of Eq. 1, in chart units (the equal-area chart
  // spans a disc of radius 2). 0: automatic (compute_effect_field in
  // effect_field.h).
  double effect_radius = 0.0;
};

// Polyline samples per fitted B-spline (fit_ideal_curves): the targets are
// the nearest points on these, about 0.1 degree apart on a typical curve.
inline constexpr int kSamplesPerCurve = 512;

// The effect-field grid for `normal_count` normals: 2 sqrt(N) cells per side,
// from 32 to 128. A few thousand normals leave most cells of a finer grid
// empty, and the field costs grow with the cells times the kernel support;
// on the curved cone 64 cells give the same result as 128 at half the time.
int automatic_grid_resolution(Eigen::Index normal_count);

// Fits the ideal curve(s) of one patch.
//   normals: unit face normals of the patch (its Gauss image), one per row.
//   weights: one non-negative weight per normal (face areas), same length.
// Returns at least one curve: several for a branched or split Gauss image, a
// single one-point curve (the weighted mean normal) for a planar patch.
// Throws EngineError(invalid_argument) on size mismatch or an empty patch.
std::vector<SphereCurve> fit_ideal_curves(const Normals& normals, const Eigen::VectorXd& weights,
                                          const IdealCurveOptions& options);

}  // namespace developable

// Stage 3 of the pipeline: a planar chart of a patch's Gauss image (paper,
// Sec. III, "the normal image is mapped to the parametric domain").
//
// The paper does not say which map. We rotate a chosen pole to +z and apply
// the Lambert azimuthal EQUAL-AREA projection: equal areas of the sphere get
// equal areas of the chart, so the point densities that drive the effect
// field (Eq. 1) are not inflated or deflated by the map. The chart is the
// disc of radius 2; only the antipode of the pole maps to its rim.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

namespace developable {

// Points of the chart, one (x, y) row per normal.
using ChartPoints = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// The pole of the chart for a set of normals.
//   normals: one per row, any non-zero length (they are normalised here);
//            zero or non-finite rows are skipped.
//   weights: one non-negative weight per normal (face areas).
// Returns a unit vector: the area-weighted mean normal when it is long
// (|mean| >= 0.7, the normals cover a cap of the sphere), otherwise the axis
// of a weighted plane fit to the normals (smallest eigenvector of their
// weighted covariance about the mean), oriented toward the mean. The second
// case is a cylinder or a steep cone whose Gauss image is a (near) circle:
// its mean is short and badly defined, but the circle's axis is sharp and
// keeps the whole circle away from the antipode, where the chart distorts.
// Throws EngineError(invalid_argument) on a size mismatch or when no normal
// has positive weight and length (all-zero weights count as uniform weights).
Eigen::Vector3d choose_chart_pole(const Normals& normals, const Eigen::VectorXd& weights);

// The Lambert equal-area chart about a pole. A small value class: cheap to
// copy, immutable, safe to share between threads.
class GaussChart {
 public:
  // pole: any non-zero finite vector (normalised here); throws
  // EngineError(invalid_argument) otherwise.
  explicit GaussChart(const Eigen::Vector3d& pole);

  const Eigen::Vector3d& pole() const { return pole_; }

  // Unit normal -> chart point, |result| <= 2 (the pole goes to the origin).
  // (x, y) = sqrt(2 / (1 + z)) (n_x, n_y) in the rotated frame, computed as
  // radius sqrt(2 (1 - z)) times the unit azimuth so that the antipode
  // (z -> -1) stays finite: it lands on the rim in direction +x.
  // n need not be exactly unit (it is normalised); a zero n maps to 0.
  Eigen::Vector2d to_chart(const Eigen::Vector3d& n) const;

  // Chart point -> unit normal; the exact inverse of to_chart inside the disc
  // of radius 2. Points outside the disc are clamped to its rim (the antipode).
  Eigen::Vector3d to_sphere(const Eigen::Vector2d& p) const;

 private:
  Eigen::Vector3d pole_;
  Eigen::Matrix3d frame_;  // rows: e1, e2, pole (world -> chart frame)
};

// Projects every normal with the chart. Rows of zero length map to the origin.
ChartPoints project_to_chart(const GaussChart& chart, const Normals& normals);

}  // namespace developable

// Stage 4 of the pipeline: the radial effect field of Eq. 1 (paper, Sec. III),
// a grid image over the Gauss chart whose ridges are the skeleton of the
// Gauss image.
//
// Where we depart from the paper, and why:
//  * Eq. 1 sums sqrt(d^2 + r^2) (Goshtasby's multiquadric). That sum is convex
//    and grows away from the points: it has no ridge along them to find. We
//    use the DECAYING inverse multiquadric 1/sqrt(d^2 + rho^2), shifted to
//    reach zero at the effect radius R (the paper's sign(dist) threshold) so
//    the field is continuous there.
//  * Each occupied cell is one source at the weighted centroid of its points
//    (not at the cell centre), with amplitude its total weight (face area):
//    "the more points a grid contains, the larger its influence", counted by
//    area so that a finely tessellated region does not dominate.
//  * The density term r(p) = k * share(cell) * R with k = 1, share = the cell's fraction
//    of the total weight (the paper's #(points in cell)/#(points) for uniform
//    weights). Multiplying by R gives it chart units: a cell holding the whole
//    patch spreads its influence over its effect region. It softens the
//    kernel together with a base softening rho0 = max(R/3, cell): rho =
//    sqrt(rho0^2 + r^2), which keeps the field smooth at the grid scale.
#pragma once

#include "core/types.h"
#include "ideal_curve/gauss_chart.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

struct EffectFieldOptions {
  // Cells per side of the square window; 16 .. 4096.
  int grid_resolution = 128;
  // Effect radius R in chart units (>= 0); 0 = automatic (see below).
  double effect_radius = 0.0;
};

// One occupied cell of the grid: where its points are and how much they weigh.
struct FieldSource {
  Eigen::Vector2d position;  // weighted centroid of the cell's points, chart units
  double weight = 0.0;       // sum of the points' weights
  int count = 0;             // number of points
};

// The field on a resolution x resolution grid of square cells.
struct EffectField {
  int resolution = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // lower-left corner of the window
  double cell_size = 0.0;                            // chart units
  double effect_radius = 0.0;                        // R actually used, chart units
  double base_softening = 0.0;                       // rho0, chart units
  // Weighted RMS scatter of the points across their local principal
  // direction, in windows of half-side R: ~ the noise width of a curve-like
  // Gauss image, a fixed fraction of R for a 2-D blob. Chart units.
  double thickness = 0.0;
  Eigen::MatrixXd values;            // values(ix, iy) at the centre of cell (ix, iy)
  std::vector<FieldSource> sources;  // occupied cells, in cell order (iy major)
  double total_weight = 0.0;

  Eigen::Vector2d cell_center(int ix, int iy) const { return origin + cell_size * Eigen::Vector2d(ix + 0.5, iy + 0.5); }
  // Bilinear value at a chart point; 0 outside the window.
  double sample(const Eigen::Vector2d& p) const;
};

// Computes the effect field of chart points.
//   points: chart points (gauss_chart.h), one per row, finite.
//   weights: one non-negative weight per point; all zero counts as uniform.
// The window is the points' bounding square, padded by 4 cells on each side so
// ridges at the data's edge keep their neighbours.
// Automatic effect radius (options.effect_radius == 0), with D the side of the
// points' bounding square, h the cell size, g90 the 90th percentile of the
// distance from each source to its nearest other source, and L the
// single-linkage distance at which the sources form at most 4 pieces of
// comparable weight:
//   R = clamp(max(0.08 D, 1.5 g90, 2 L), 3 h, U),  U = max(0.25 D, 3 h),
// then, up to 8 times, R = min(U, 3.3 t(R)) while that is larger, t(R) being
// the points' scatter across their local direction in windows of half-side
// R (the `thickness` below). 0.08 D resolves features down to ~1/6 of the
// image; 1.5 g90 bridges the gaps of a coarse mesh (a 32-sided cylinder's
// Gauss image is 32 points) and 2 L those between the clusters a thinned
// curve breaks into, so each ridge stays one curve; 3.3 t makes a noisy curve
// one ridge across (and a noisy plane one bump); 3 h keeps the kernel
// resolved on the grid. A given or automatic R below h is raised to h.
// Cost: O(sources * (R/h)^2), about 1 ms for a typical 128^2 field.
// Throws EngineError(invalid_argument) on a size mismatch, no points,
// non-finite input, negative weights or options out of range.
EffectField compute_effect_field(const ChartPoints& points, const Eigen::VectorXd& weights,
                                 const EffectFieldOptions& options);

}  // namespace developable

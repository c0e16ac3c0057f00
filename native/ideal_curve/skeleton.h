// Stage 5 of the pipeline: the skeleton points of the effect field (paper,
// Sec. III: "based on local maximum and image gradient direction, those
// skeleton points ... can be found"), ordered into curves.
//
// The paper neither defines "local maximum" on a 2-D field nor says how the
// unordered points become the ordered input of a B-spline fit. Here:
//  * A skeleton point is a ridge point: the field is a local maximum ACROSS
//    the ridge, the across direction being the Hessian eigenvector of the most
//    negative eigenvalue; the position is refined inside the cell by a
//    parabola through the cell and its two neighbours along that direction.
//  * An isotropic bump (a planar patch's Gauss image) has every point on it a
//    maximum across its level line. Such points are rejected by asking the
//    across-curvature to dominate (|lambda_min| >= 2 |lambda_max|) and the
//    field to be flat along the ridge compared with how sharply it falls
//    across (|grad f| <= |lambda_min| * R / 2, per cell).
//  * A coarse mesh has few distinct normals and no density to speak of:
//    below min_sources_for_field occupied cells, the cells' centroids are
//    the skeleton points.
//  * Ordering: a Euclidean minimum spanning tree over the ridge points (on
//    their k-nearest-neighbour graph) and its longest path (tree diameter).
//    When the two ends of that path are close compared with its length, the
//    Gauss image wraps around (cylinder, cone) and the curve is closed.
//    Branches off the path and separate components that are long enough
//    compared with the longest path become curves of their own.
#pragma once

#include "ideal_curve/effect_field.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// One ordered skeleton curve in the Gauss chart.
struct SkeletonCurve {
  std::vector<Eigen::Vector2d> points;  // chart units, in order along the curve
  bool closed = false;                  // the last point connects back to the first
};

struct SkeletonOptions {
  // A ridge point needs field >= this fraction of the field's maximum.
  double min_field_fraction = 0.01;
  // Branches and separate components shorter than this fraction of the
  // longest path are dropped as noise.
  double min_branch_fraction = 0.25;
  // Planar test: the Gauss image counts as "about a point" when the ridge's
  // bounding-box diagonal is below this multiple of the points' RMS spread
  // about their weighted centroid (a line of length L has diagonal/spread
  // 3.5, a full circle 2.8, an isotropic blob ~1 or less).
  double min_extent_over_spread = 1.5;
  // Planar test: ... or when the points' scatter across the ridge (the
  // field's thickness) exceeds this fraction of their spread. A curve of
  // length L and scatter s gives 3.5 s / L, so an arc shorter than ~7
  // scatter widths counts as a point. Blobs of noise can pass both tests
  // (a Gaussian blob measures ~0.45 here) and keep short ridges through the
  // noise: fit_ideal_curves's residual test makes those a point.
  double max_thickness_over_spread = 0.5;
  // Below this many occupied cells the field is skipped: the cells'
  // centroids themselves are the skeleton points (coarse meshes).
  int min_sources_for_field = 48;
};

// Unordered ridge points of the field, chart units, in cell order (so
// deterministic). Empty when the field has no ridge (e.g. a single bump).
//   min_field_fraction in [0, 1).
std::vector<Eigen::Vector2d> find_ridge_points(const EffectField& field, double min_field_fraction);

// Orders ridge points into curves (see the file comment).
//   points: chart points; link_distance: longest gap bridged between two
//   neighbouring points (chart units, > 0); join_distance: longest gap
//   bridged between the ends of two paths that continue each other (>= 0,
//   chart units; see below); min_branch_fraction as above; min_length:
//   shortest curve kept, chart units.
// A path is closed when the gap between its ends is at most
// max(min(2 link, 1.5 * its longest step), 0.08 * its length).
// Joining: when a curve's Gauss image has thinned into clusters, the field
// dips between them and the ridge breaks into pieces. Open paths are chained,
// shortest gap first, when the gap is at most join_distance, they run the
// same way (end directions within 60 degrees, measured over join_distance of
// path) and each end lies ahead of the other along its direction, within one
// link or 30 degrees of it; the chain is then tested for closure again.
// After joining, a curve with half of its points within join_distance / 2 of
// a longer kept curve is dropped (a second ridge through the same band).
// Returns curves longest first; each has >= 2 points. Empty if points has
// fewer than 2 points or nothing is long enough.
std::vector<SkeletonCurve> order_ridge_points(const std::vector<Eigen::Vector2d>& points, double link_distance,
                                              double join_distance, double min_branch_fraction, double min_length);

// The whole stage: ridge points, ordering, and the planar test.
// Returns an empty vector when the Gauss image is about a point by the
// planar tests above (fewer than 4 points, a ridge too short against the
// spread, or too thick); the caller then uses the mean normal. A noisy blob
// may still give short curves (see max_thickness_over_spread).
// Link distance: max(2.5 cells, R / 2); join distance 2 R.
// Throws EngineError(invalid_argument) on options out of range.
std::vector<SkeletonCurve> extract_skeleton(const EffectField& field, const SkeletonOptions& options);

}  // namespace developable

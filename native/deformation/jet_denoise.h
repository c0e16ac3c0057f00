// Stage 8a (beyond the paper): the input's noise smoothed by local
// quadrics, the start of two of least motion's candidates (run_pipeline;
// docs/method.md, "Smoothed input").
//
// Each vertex is moved along the normal of its two-ring's best plane onto
// the quadric height field z = a x^2 + b xy + c y^2 + d x + e y + f fitted to
// that two-ring by least squares (an osculating jet of degree 2, as CGAL's
// jet_smooth_point_set does on point sets, here on the mesh's rings rather
// than k nearest points, so that the two sides of a thin part never mix),
// the ring's vertices weighed by a Gaussian of their distance (sigma = sqrt 2
// times the ring's RMS radius). A noise-free smooth surface moves by the
// third-order terms only, the far vertices' most, hence the weights; a
// vertex whose noise is white moves back by most of it.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <vector>

namespace developable {

// The feature guard's default angle (JetDenoiseOptions::feature_angle_deg).
constexpr double kJetFeatureAngle = 30.0;

struct JetDenoiseOptions {
  // A vertex is left where it is if a face of its two-ring turns more than
  // this (degrees) from the ring's plane: a crease, a corner, or a surface
  // too coarsely sampled for one quadric (a wave a few edges long), where
  // the fit would cut the feature instead of the noise.
  double feature_angle_deg = kJetFeatureAngle;
  // Empty, or one group id per face (pieces meeting at creases): a vertex's
  // rings then hold only the faces of its own group, so that the fit never
  // reaches across a border, and a vertex on a border (faces of two groups)
  // keeps its place.
  std::vector<int> face_groups;
};

// Returns the smoothed positions.
//   positions, triangles: a valid mesh (validate_mesh), `connectivity` its
//   faces around each vertex; pinned: one entry per vertex (true: kept
//   bit-identical) or empty.
// Vertices with fewer than 9 two-ring neighbours within their group (6
// unknowns and some to spare) and those at a feature (options) keep their
// place, as do pinned ones. Moves are along the fitted plane's normal only,
// in the caller's units. O(vertices x two-ring size); throws
// EngineError(internal_error) only when face_groups is neither empty nor one
// per face.
Positions jet_denoise(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                      const std::vector<bool>& pinned, const JetDenoiseOptions& options = {});

// The smoothings of several feature guards at once: one per entry of
// feature_angles_deg, in that order, each the same bits as jet_denoise with
// that angle alone (and `face_groups`), each vertex's ring and quadric
// fitted once for all of them (least motion's guarded and unguarded starts:
// half the work of two calls). Empty for no angle; throws as above.
std::vector<Positions> jet_denoise(const Positions& positions, const Triangles& triangles,
                                   const VertexFaces& connectivity, const std::vector<bool>& pinned,
                                   const std::vector<double>& feature_angles_deg, const std::vector<int>& face_groups);

}  // namespace developable

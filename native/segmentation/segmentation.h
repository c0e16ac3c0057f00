// Pre-processing stage: curvature-based segmentation into quasi-developable
// patches, in the spirit of D-Charts (Julius, Kraevoy, Sheffer 2005; the
// paper's reference [8]).
//
// Each chart is fitted by a cone (axis and opening angle, from a weighted
// plane fit to its face normals); charts grow by a cost of fitting error,
// compactness and boundary straightness, in Lloyd-style rounds until the
// labels settle; small charts are merged into neighbours.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

struct SegmentationOptions {
  // Largest cone-fitting error of a patch: the area-weighted RMS angle (rad)
  // between a face normal and its chart's cone. 0 picks the default.
  double max_fit_error = 0.0;
  // Wanted number of patches; 0 lets max_fit_error decide.
  int target_patches = 0;
};

// Labels every face with a patch id in 0 .. k-1 (k >= 1), each patch edge-connected.
//   positions, triangles: a mesh that passed validate_mesh (mesh_input.h).
// Deterministic: the same input gives the same labels. Reports progress as
// stage "segmentation"; throws EngineError(cancelled) if the callback says stop.
std::vector<int> segment_mesh(const Positions& positions, const Triangles& triangles,
                              const SegmentationOptions& options, const Progress& progress);

// The same with what the caller has already computed: the unit face normals
// and areas of `positions` (measures.h) and the faces around each vertex
// (validate_mesh's table).
std::vector<int> segment_mesh(const Positions& positions, const Triangles& triangles, const Normals& normals,
                              const Eigen::VectorXd& areas, const VertexFaces& vertex_faces,
                              const SegmentationOptions& options, const Progress& progress);

}  // namespace developable

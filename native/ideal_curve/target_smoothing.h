// Stage 6b of the pipeline: smoothing the target normals inside each patch
// (beyond the paper; docs/segmentation.md has the measurements).
//
// A doubly curved patch (a segmented character, a bulged panel) has a Gauss
// image that is a 2D cloud, not a curve. Projecting every normal onto its
// nearest point of the ideal curve then gives neighbouring faces targets that
// jump back and forth along the curve: no surface has those normals, and the
// least-squares step answers with a crumpled patch (on human_woman the mean
// |defect| inside the patches rose from 0.050 to 0.079 rad). Averaging each
// target with those of the faces around it turns the projection into a
// smooth field that a surface can follow; the same patches then fall to
// about 0.01 rad. Faces of other patches are left out of the average, so the
// curvature still gathers on the seams.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

class TargetSmoother {
 public:
  // The neighbourhood of each face: the faces that share a vertex with it
  // and lie in its patch (itself included).
  //   triangles: a validated mesh; patch_ids: one patch id per face.
  TargetSmoother(const Triangles& triangles, const std::vector<int>& patch_ids);
  // The same from the faces around each vertex (validate_mesh's table).
  TargetSmoother(const Triangles& triangles, const std::vector<int>& patch_ids, const VertexFaces& vertex_faces);

  // `rounds` passes of area-weighted averaging over the neighbourhoods, each
  // result renormalised to a unit vector.
  //   targets: unit target normal per face; areas: face areas (any positive
  //   unit, only ratios count); rounds >= 0 (0 returns the targets).
  // A neighbourhood whose targets cancel out (sum of length 0) keeps the
  // face's own target.
  Normals smooth(const Normals& targets, const Eigen::VectorXd& areas, int rounds) const;

 private:
  // Face f's neighbourhood is neighbours_[offsets_[f] .. offsets_[f + 1]).
  std::vector<size_t> offsets_;
  std::vector<int> neighbours_;
};

}  // namespace developable

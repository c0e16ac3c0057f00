// One deformation step that cannot fold (the paper's stage 7 made safe). A
// step that would turn faces over (against the input's normals) is solved
// again with those faces and their neighbours damped; what still turns over,
// and what the step would crease (the crease guard), then keeps its corners
// at their previous place, ring by ring; a step still folding after
// kFoldRevertRounds rounds is dropped. Thin triangles pull less
// (sliver_trust). Damping only in the decoupled formulation, whose matrix
// does not depend on omega. Every vertex stays within the move limit.
#pragma once

#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "deformation/deformation.h"
#include "pipeline/options.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// 4 sqrt(3) area / (sum of the squared edge lengths): 1 for an equilateral
// triangle, 0.87 for half a square, toward 0 for slivers.
Eigen::VectorXd triangle_quality(const Positions& positions, const Triangles& triangles);

// The weight of each face's pull toward its target, 0..1: thin triangles'
// normals are unreliable (on noisy tangent developables, where a fifth of
// the faces have a corner under 10 degrees, they are 19 degrees off on
// median), so their pull is scaled down with their quality, full from half
// a square's quality 0.87 / 2 upward.
Eigen::VectorXd sliver_trust(const Positions& positions, const Triangles& triangles);

// Per-face damping of the pull toward the targets where steps turned faces
// over: a face whose step would turn it, and every face sharing a vertex with
// it, has its normal weight cut by kFoldDamping; the cut heals by
// kFoldRecovery per step. Multiplies sliver_trust.
class FoldDamping {
 public:
  FoldDamping(const Triangles& triangles, const VertexFaces& vertex_faces);

  const Eigen::VectorXd& factors() const { return damping_; }
  bool any() const { return damped_; }
  void damp_around(const std::vector<Eigen::Index>& turned);
  void recover();

 private:
  const Triangles& triangles_;
  const VertexFaces& vertex_faces_;
  Eigen::VectorXd damping_;
  bool damped_ = false;
};

class FoldSafeStep {
 public:
  // deformation: the step's system (its normal weights are set here);
  // input, input_normals: the user's mesh, the reference of "turned over";
  // limit: the move limit (caller's units, 0: none); crease_guard: the edges
  // no step may crease. The references must outlive this.
  FoldSafeStep(NormalGuidedDeformation& deformation, const Positions& input, const Normals& input_normals,
               const Triangles& triangles, const VertexFaces& connectivity, bool can_damp, double limit, Mode mode,
               CreaseGuard crease_guard);

  // Moves `current` (with face normals `normals`) one step on; both are
  // updated. Returns the extra solves and reverts it took.
  int advance(Positions& current, Normals& normals);

  // Whether an iterate made otherwise (Anderson acceleration) with face
  // normals `normals` turns no face over and creases no edge.
  bool accepts(const Normals& normals) const;

 private:
  Positions propose(const Positions& current, const Normals& normals) const;

  NormalGuidedDeformation& deformation_;
  const Positions& input_;
  const Normals& input_normals_;
  const Triangles& triangles_;
  bool can_damp_;
  double limit_;
  Mode mode_;
  Eigen::VectorXd trust_;
  CreaseGuard crease_guard_;
  FoldDamping damping_;
};

}  // namespace developable

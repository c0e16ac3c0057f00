// The target normal of every face at every iteration of the deformation (the
// paper's stage 6a, repeated). In the refit mode the ideal curves are refit
// from the deformed mesh every kRefitInterval iterations (or when asked) and
// the normals projected onto them in between, each face starting its search
// at its last answer; on pieces the targets are then averaged over each
// face's ring inside its patch (smoothing_rounds in options.h).
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "ideal_curve/curve_search.h"
#include "ideal_curve/target_smoothing.h"
#include "pipeline/options.h"
#include "pipeline/patches.h"

#include <optional>
#include <vector>

namespace developable {

// Iterations between two refits of the curves in the refit mode; in between
// the normals are projected onto the last curves (docs/method.md, "Refit").
inline constexpr int kRefitInterval = 5;

class TargetField {
 public:
  // The targets of `positions` on `patches`' curves (fitted on them).
  //   areas: the face areas of `positions`; piecewise: the run treats the
  //   patches as pieces (smoothing_rounds). The references must outlive this.
  TargetField(Patches patches, const Positions& positions, const Triangles& triangles, const Eigen::VectorXd& areas,
              const VertexFaces& connectivity, const PipelineOptions& options, bool piecewise);

  const Normals& targets() const { return targets_; }
  const std::vector<PatchCurve>& curves() const { return patches_.curves; }

  // The targets for the mesh `current` with face normals `normals` at
  // `iteration` (>= 2; the first step takes the input's): curves refit
  // every kRefitInterval iterations.
  void update(const Positions& current, const Normals& normals, int iteration);

  // The targets of `current` (face normals `normals`) on curves refit on it.
  void refit(const Positions& current, const Normals& normals);

 private:
  Patches patches_;
  const Triangles& triangles_;
  const PipelineOptions& options_;
  std::vector<CurveSearch> searches_;
  // Each face's last answer on its patch's curves: where its next search
  // starts. Kept across refits too, as the refit curves are sampled alike.
  std::vector<std::vector<int>> hints_;
  Normals targets_;
  int smoothing_rounds_;
  std::optional<TargetSmoother> smoother_;
  bool refit_next_ = false;
};

}  // namespace developable

// The patches a run deforms (a label per face), with their ideal curves and
// first targets (paper, stages 3-6 per patch), and the measures the plan
// (plan.h) decides by.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "ideal_curve/curve_search.h"
#include "ideal_curve/ideal_curve.h"
#include "pipeline/options.h"
#include "pipeline/run_result.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// Faces of each patch: entry p lists the faces whose patch id is p, ascending.
using PatchFaces = std::vector<std::vector<Eigen::Index>>;

// Groups the faces by patch. patch_ids: per face in 0 .. patch_count-1.
PatchFaces faces_of_patches(const std::vector<int>& patch_ids, int patch_count);

// The ideal curves of every patch (stages 3-6 per patch).
//   normals, areas: per face; patches: from faces_of_patches.
std::vector<PatchCurve> fit_patch_curves(const Normals& normals, const Eigen::VectorXd& areas,
                                         const PatchFaces& patches, const IdealCurveOptions& options);

// The search structure of each patch's curves (empty for a patch without
// faces), built once per fit and queried by patch_target_normals.
std::vector<CurveSearch> patch_curve_searches(const std::vector<PatchCurve>& curves, int patch_count);

// The target normal of every face: its nearest point on its own patch's curves.
//   normals: per face; patches: from faces_of_patches; searches: from
//   patch_curve_searches, one per patch; hints: null, or the caller's scratch
//   kept between calls (CurveSearch::nearest), one entry per patch;
//   threads: as in CurveSearch::nearest.
Normals patch_target_normals(const Normals& normals, const PatchFaces& patches,
                             const std::vector<CurveSearch>& searches, std::vector<std::vector<int>>* hints = nullptr,
                             int threads = 0);

// A patch alternative of a run: a label per face, each patch's faces, its
// ideal curves fitted on the input and the input's targets on them.
struct Patches {
  std::vector<int> ids;  // per face, 0 .. count-1
  int count = 1;
  PatchFaces faces;
  std::vector<PatchCurve> curves;
  Normals targets;  // of the input's normals
  // The pieces the mesh's curvature cuts it into, each flat inside
  // (developable_pieces.h): nothing to deform.
  bool developable = false;
  // Cut at the input's crease lines (crease_pieces.h): each piece one smooth
  // sheet, its borders the part's mitres and joints.
  bool creased = false;
};

// Patches with ids `ids` (0 .. count-1 per face), their curves and targets.
Patches fitted_patches(std::vector<int> ids, int count, const Normals& normals, const Eigen::VectorXd& areas,
                       const PipelineOptions& options);

// The whole mesh as one patch.
Patches one_patch(const Normals& normals, const Eigen::VectorXd& areas, const PipelineOptions& options);

// The segmentation's patches (segmentation.h, with options.segmentation_options);
// progress: 0 .. 0.05 of the caller's range.
Patches segmented_patches(const Positions& positions, const Triangles& triangles, const Normals& normals,
                          const Eigen::VectorXd& areas, const VertexFaces& connectivity, const PipelineOptions& options,
                          const Progress& progress);

// Root-mean-square angle (rad) between the normals and their targets,
// weighted by area: how far the Gauss image is from its ideal curves.
double curve_fit_error(const Normals& normals, const Normals& targets, const Eigen::VectorXd& areas);

// Vertices where faces of two or more patches meet.
std::vector<bool> patch_border_vertices(const Triangles& triangles, const std::vector<int>& patch_ids,
                                        Eigen::Index vertex_count);

// The vertices inside the patches: interior, not on `border`
// (patch_border_vertices) and, when `pinned` is not empty, not pinned. All
// three masks per vertex (pinned may be empty).
std::vector<bool> inside_patches(const std::vector<bool>& interior, const std::vector<bool>& border,
                                 const std::vector<bool>& pinned);

// Whether every face normal lies within kFlatDefect (rad) of its patch's
// cone (cone_fit.h): each patch's Gauss image is a circle of the sphere, so
// each patch is a plane, a cylinder or a cone as it stands.
bool patches_fit_cones(const std::vector<int>& patch_ids, int patch_count, const Normals& normals,
                       const Eigen::VectorXd& areas);

}  // namespace developable

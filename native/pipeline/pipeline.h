// The whole run on a mesh, as the paper's method plus what makes it safe:
//
//   check_input                   stage 1: options, memory budget, mesh, pins
//   measure_input (run_context.h) stage 2: defects, normals, areas, limits
//   run_plan (plan.h)             the patch alternatives: one patch, the
//                                 developable pieces, or the segmentation's
//   run_patch_alternative         per alternative: the candidates (the
//     (patch_alternative.h)       deformation, stages 6-7, and its polish,
//                                 stage 8; least motion's polishes), held to
//                                 one admissibility rule (selection.h)
//   finish_plan_result            a sheet's chosen result finished flat and
//     (patch_alternative.h)       ruled (ruled_finish.h), when it is crumpled
//                                 and can gain
//
// docs/architecture.md draws the stages; docs/method.md says where and why
// they depart from the paper.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "pipeline/options.h"
#include "pipeline/run_result.h"

#include <vector>

namespace developable {

// The checks of a run's input, in this order, each before anything that
// needs it is allocated: the options (check_options), the memory budget for
// the mesh's counts (check_memory_budget in memory_budget.h:
// out_of_memory), progress 0 "checking input", the mesh (validate_mesh in
// mesh_input.h: its own statuses), and the pin mask's size (empty or one
// entry per vertex: invalid_argument). run_pipeline calls it first.
// Returns validate_mesh's table of the faces around each vertex.
VertexFaces check_input(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                        const PipelineOptions& options, const Progress& progress);

// Runs the pipeline on a mesh.
//   positions, triangles: the caller's mesh (checked by validate_mesh).
//   pinned: empty, or one flag per vertex; pinned vertices never move.
// Returns the best admissible candidate of the plan's alternatives, every
// vertex within the move limit (move_limit in options.h) of its input
// position, or the input with stats.result = unchanged and the reason
// (stats.unchanged_reason, stats.result_message). Admissible (selection.h):
// no face turned over (normal > 90 degrees from the input's, or collapsed),
// no crease inside a patch beyond the crease guard, the mean |defect| not
// above the input's (a closed mesh's up to 5 % above), the flat share not
// below it, and a gain a user sees.
// Throws EngineError: check_input's statuses, no_interior_vertex (naming the
// vertices that share a position when the mesh looks like an unwelded
// polygon soup), no_free_vertex, cancelled (via progress), numerical_failure.
PipelineResult run_pipeline(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                            const PipelineOptions& options, const Progress& progress);

}  // namespace developable

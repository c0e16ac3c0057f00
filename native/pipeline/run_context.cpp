#include "pipeline/run_context.h"

#include "core/mesh_input.h"
#include "pipeline/messages.h"
#include "pipeline/selection.h"

#include <algorithm>

namespace developable {
namespace {

// The pins of a run: the caller's mask, the boundary if asked.
std::vector<bool> pins_of(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                          const PipelineOptions& options) {
  std::vector<bool> pins = pinned.empty() ? std::vector<bool>(static_cast<size_t>(positions.rows()), false) : pinned;
  if (options.pin_boundary) {
    const std::vector<bool> boundary = boundary_vertices(positions, triangles);
    for (size_t v = 0; v < pins.size(); ++v) pins[v] = pins[v] || boundary[v];
  }
  return pins;
}

}  // namespace

double elapsed_ms(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

MeasuredInput measure_input(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                            const std::vector<bool>& pinned, const PipelineOptions& options,
                            Clock::time_point start_time) {
  MeasuredInput input{positions, triangles, connectivity, options, start_time};
  PipelineResult& measured = input.measured;
  PipelineStats& stats = measured.stats;
  stats.vertices = positions.rows();
  stats.faces = triangles.rows();
  measured.interior = interior_vertices(positions, triangles);
  measured.defect_before = angle_defects(positions, triangles, measured.interior);
  input.before = defect_stats(measured.defect_before, measured.interior);
  stats.interior_vertices = input.before.interior_count;
  if (input.before.interior_count == 0)
    throw EngineError(Status::no_interior_vertex, no_interior_vertex_message(positions));
  stats.mean_defect_before = input.before.mean_abs;
  stats.max_defect_before = input.before.max_abs;
  stats.average_edge_length = average_edge_length(positions, triangles);
  stats.flat_share_before = flat_share(measured.defect_before, measured.interior);
  input.limit = move_limit(positions, options, stats.average_edge_length);
  stats.move_limit = input.limit;
  input.pinned = pins_of(positions, triangles, pinned, options);
  input.normals = face_normals(positions, triangles);
  input.areas = face_areas(positions, triangles);
  stats.shares_before = vertex_shares(
      measured.defect_before, ruling_spreads(positions, triangles, input.normals, connectivity, measured.interior),
      measured.interior);
  input.closed = true;
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    input.closed = input.closed && (connectivity.count(v) == 0 || measured.interior[static_cast<size_t>(v)]);
  double total_curvature = 0.0;
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    if (measured.interior[static_cast<size_t>(v)]) total_curvature += measured.defect_before[v];
  input.object = is_object(input.closed, total_curvature);
  return input;
}

PatchRun patch_run(const MeasuredInput& input, const Patches& patches) {
  PatchRun run{input};
  run.patch_ids = patches.ids;
  run.patch_count = patches.count;
  run.piecewise = patches.count > 1 && input.options.mode == Mode::refit;
  run.sheets = !run.piecewise || patches.creased;
  const std::vector<bool> border = patch_border_vertices(input.triangles, patches.ids, input.positions.rows());
  run.pinned = input.pinned;
  if (input.options.seams == Seams::pinned)
    for (size_t v = 0; v < run.pinned.size(); ++v) run.pinned[v] = run.pinned[v] || border[v];
  run.scored = input.measured.interior;
  if (run.piecewise) {
    std::vector<bool> inside = inside_patches(run.scored, border, {});
    if (std::find(inside.begin(), inside.end(), true) != inside.end()) run.scored = std::move(inside);
  }
  run.scored_count = std::count(run.scored.begin(), run.scored.end(), true);
  // A segmented mesh is doubly curved: made flat vertex by vertex within its
  // patches it crumples; one patch may not fold.
  run.crease_guard = CreaseGuard(input.triangles, input.normals, run.patch_ids,
                                 run.piecewise ? kSegmentedCreaseGrowth : kOnePatchCreaseGrowth);
  return run;
}

Choice Choice::input(const MeasuredInput& input, const Measured& measured) {
  Choice choice;
  choice.positions = input.positions;
  choice.measured = measured;
  choice.best_score = (1.0 - kLeastGain) * measured.figures.score;
  return choice;
}

void Choice::keep(const Positions& candidate, Measured candidate_measured, ResultOrigin candidate_origin) {
  improved = true;
  positions = candidate;
  measured = std::move(candidate_measured);
  origin = candidate_origin;
  best_score = measured.figures.score;
}

}  // namespace developable

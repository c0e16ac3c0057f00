// What the stages of one run share: the input and its measures (once per
// run), one patch alternative's setup (once per alternative the plan runs),
// and the choice so far (the mesh the run would return now).
#pragma once

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "pipeline/judge.h"
#include "pipeline/options.h"
#include "pipeline/patches.h"
#include "pipeline/run_result.h"

#include <Eigen/Core>

#include <chrono>
#include <vector>

namespace developable {

using Clock = std::chrono::steady_clock;

// Milliseconds since `since`.
double elapsed_ms(Clock::time_point since);

// The input and its measures (stage 2), shared by the runs on its patches.
// The references must outlive it.
struct MeasuredInput {
  MeasuredInput(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                const PipelineOptions& options, Clock::time_point start_time)
      : positions(positions),
        triangles(triangles),
        connectivity(connectivity),
        options(options),
        start_time(start_time) {}

  const Positions& positions;
  const Triangles& triangles;
  const VertexFaces& connectivity;
  const PipelineOptions& options;
  Clock::time_point start_time;
  PipelineResult measured;  // the input's stats and defects, nothing else yet
  DefectStats before;
  double limit = 0.0;        // move_limit (options.h)
  std::vector<bool> pinned;  // the caller's pins and, with pin_boundary, the boundary
  Normals normals;           // per face
  Eigen::VectorXd areas;     // per face
  bool closed = false;       // every vertex a triangle uses is interior
  bool object = false;       // a whole object, not one sheet (is_object, selection.h)
  // The run's cores no thread of it works on (concurrent_jobs.h), which the
  // polishes' products take while they are spare; null: none taken.
  SpareCores* spare_cores = nullptr;
};

// Measures the input (stage 2). Throws EngineError(no_interior_vertex),
// naming a polygon soup where its vertices share positions.
MeasuredInput measure_input(const Positions& positions, const Triangles& triangles, const VertexFaces& connectivity,
                            const std::vector<bool>& pinned, const PipelineOptions& options,
                            Clock::time_point start_time);

// On a segmented mesh no step (deformation or polish) may grow the angle
// between two faces of one patch by more than this over the input's (the
// crease guard, CreaseGuard in measures.h; seams may fold). Made flat vertex
// by vertex, a doubly curved patch crumples: human_woman with the defaults
// came back 73 % flat with 7.9 % of its edges sharpened by more than 20
// degrees, its face a crumpled mask and its fingers pressed into blades.
// With 20 degrees the face keeps its nose, mouth and ears (40: the nose
// crumples again); docs/method.md, "The crease guard".
inline constexpr double kSegmentedCreaseGrowth = 20.0 * M_PI / 180.0;
// On one patch no step may grow such an angle by more than this: a smooth
// sheet creased at a right angle is folded, whatever its faces' normals say
// (the fold-safe step and the polish check those against the input's only).
// Tangent developables of the families came back with edges folded back by
// 100-152 degrees on their thin faces near the edge of regression (a face
// lying on its neighbour). The cost, on random-curve tangent developables on
// slivers (held-out seeds 100-102): lowest flat share 81 -> 74 %, largest
// Hausdorff ratio to the twin 1.42 -> 1.72; at 60 degrees 60 % and 2.03.
inline constexpr double kOnePatchCreaseGrowth = 90.0 * M_PI / 180.0;

// One patch alternative's run: its patches and what follows from them.
struct PatchRun {
  explicit PatchRun(const MeasuredInput& input) : input(input) {}

  const MeasuredInput& input;
  std::vector<int> patch_ids;  // per face
  int patch_count = 1;
  // The refit mode treats a segmented mesh as pieces meeting at seams: it is
  // scored inside its patches, where the curvature should leave (see
  // IterateScore), and its targets are smoothed. The paper mode stays the
  // paper's: E^mean and raw targets whatever the patches.
  bool piecewise = false;
  // Every patch one smooth sheet: one patch (or the paper mode's), or pieces
  // cut at the input's creases (Patches::creased).
  bool sheets = true;
  std::vector<bool> pinned;  // the input's, and with Seams::pinned the patch borders
  std::vector<bool> scored;  // the interior, or on pieces the vertices inside the patches
  std::ptrdiff_t scored_count = 0;
  // The crease guard on the input's normals and the patches: no step may
  // crease an edge between two faces of one patch by more than its growth
  // over the input. Made once for the run's judge, deformation and polishes
  // (a copy shares it).
  CreaseGuard crease_guard;
};

// The PatchRun of `patches` on `input`.
PatchRun patch_run(const MeasuredInput& input, const Patches& patches);

// The mesh a run would return now and its figures; `improved` once a
// candidate better than the input was kept.
struct Choice {
  bool improved = false;
  Positions positions;
  Measured measured;
  ResultOrigin origin = ResultOrigin::input;
  int polish_iterations = 0;
  // The lowest score kept so far; at first the input's less kLeastGain: a
  // candidate must score below it to be kept.
  double best_score = 0.0;

  // The input as the choice.
  static Choice input(const MeasuredInput& input, const Measured& measured);

  // Makes an admissible, better candidate the choice.
  void keep(const Positions& candidate, Measured candidate_measured, ResultOrigin candidate_origin);
};

}  // namespace developable

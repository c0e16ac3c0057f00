#include "pipeline/pipeline.h"

#include "core/mesh_input.h"
#include "pipeline/memory_budget.h"
#include "pipeline/patch_alternative.h"
#include "pipeline/plan.h"
#include "pipeline/run_context.h"

namespace developable {

VertexFaces check_input(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                        const PipelineOptions& options, const Progress& progress) {
  // Options first: a wild grid_resolution is invalid_argument, not out_of_memory.
  check_options(options);
  check_memory_budget(positions.rows(), triangles.rows(), options);
  progress.report(0.0, "checking input");
  VertexFaces table = validate_mesh(positions, triangles);
  if (!pinned.empty() && static_cast<Eigen::Index>(pinned.size()) != positions.rows())
    throw EngineError(Status::invalid_argument, "the pin mask needs one entry per vertex");
  return table;
}

PipelineResult run_pipeline(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                            const PipelineOptions& options, const Progress& progress) {
  const auto start_time = Clock::now();
  const VertexFaces connectivity = check_input(positions, triangles, pinned, options, progress);
  SpareCores spare_cores(options.threads);
  MeasuredInput input = measure_input(positions, triangles, connectivity, pinned, options, start_time);
  input.spare_cores = &spare_cores;
  progress.report(0.02, "ideal curve");
  PipelineResult result = run_plan(input, progress.sub(0.02, 0.95));
  result = finish_plan_result(input, std::move(result), progress.sub(0.95, 1.0));
  progress.report(1.0, "done");
  return result;
}

}  // namespace developable

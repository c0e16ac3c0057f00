// Limits: refuse a run that would need more memory than the budget, with
// Status::out_of_memory and a message, rather than being killed by the
// operating system inside the user's Blender.
//
// The estimate is a fit to measured peaks (docs/hardening.md, "Memory
// budget") with a safety factor of about 1.5-2; the budget is half of the
// physical memory (the other half stays for Blender and the rest of the
// system), or DEVELOPABLE_MEMORY_BUDGET_MB when that is set (tests, servers).
#pragma once

#include "pipeline/options.h"

#include <cstdint>

namespace developable {

// Estimated peak bytes the engine allocates for one run (the caller's own
// buffers not included).
//   vertices, triangles: the mesh's counts (>= 0);
//   options: the run's options (solver, mode, segmentation, grid resolution).
double estimated_peak_bytes(int64_t vertices, int64_t triangles, const PipelineOptions& options);

// The budget in bytes: DEVELOPABLE_MEMORY_BUDGET_MB (a positive number of
// MiB) when set, else half of the physical memory, else 8 GiB when the
// physical memory cannot be read.
double memory_budget_bytes();

// Throws EngineError(Status::out_of_memory, ...) naming the estimate, the
// budget and what to change when estimated_peak_bytes exceeds
// memory_budget_bytes(). Cheap: call it before anything is allocated.
void check_memory_budget(int64_t vertices, int64_t triangles, const PipelineOptions& options);

}  // namespace developable

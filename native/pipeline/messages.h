// A run's words for the user: why the input came back, or which figure of
// an improved result got worse (PipelineStats::result_message).
#pragma once

#include "core/types.h"
#include "pipeline/run_result.h"
#include "pipeline/selection.h"

#include <string>

namespace developable {

// The message of a run that returned its input for stats.unchanged_reason,
// naming what the rejected candidates broke and what to try.
std::string unchanged_message(const Rejections& rejections, const PipelineStats& stats);

// The result's message: unchanged_message for an unchanged run; for an
// improved one every figure that got worse (mean and largest |defect|, the
// flat-and-ruled share), or empty when none did.
std::string result_message(const PipelineStats& stats, const Rejections& rejections);

// An unchanged run's message once the mesh split twice as finely
// (`finer_patches` patches) came back unchanged too: said before the advice,
// where unchanged_message gives one.
std::string finer_split_also_unchanged(const std::string& message, int finer_patches);

// Why a mesh has no interior vertex, naming the likely cause when its
// vertices share positions (a polygon soup).
std::string no_interior_vertex_message(const Positions& positions);

}  // namespace developable

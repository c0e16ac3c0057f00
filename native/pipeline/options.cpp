#include "pipeline/options.h"

#include <algorithm>
#include <cmath>

namespace developable {

void check_options(const PipelineOptions& o) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw EngineError(Status::invalid_argument, what);
  };
  require(std::isfinite(o.omega) && o.omega > 0.0, "omega must be a positive number");
  require(std::isfinite(o.tolerance), "tolerance must be a finite number (<= 0 for no limit)");
  require(std::isfinite(o.max_move), "max_move must be a finite number (<= 0 for no limit)");
  require(o.max_iterations >= 1 && o.max_iterations <= 100000, "max_iterations must be between 1 and 100000");
  require(std::isfinite(o.stop_relative_change) && o.stop_relative_change >= 0.0,
          "stop_relative_change must be a non-negative number");
  require(std::isfinite(o.developable_threshold) && o.developable_threshold >= 0.0,
          "developable_threshold must be a non-negative number");
  require(o.segmentation >= -1 && o.segmentation <= 1, "segmentation must be -1, 0 or 1");
  require(std::isfinite(o.segmentation_options.max_fit_error) && o.segmentation_options.max_fit_error >= 0.0,
          "segment_max_error must be a non-negative number");
  require(o.segmentation_options.target_patches >= 0 && o.segmentation_options.target_patches <= 100000,
          "target_patches must be between 0 and 100000");
  require(o.target_smoothing >= -1 && o.target_smoothing <= 100,
          "target_smoothing must be -1 (automatic) or between 0 and 100");
  require(o.curve_options.grid_resolution == 0 ||
              (o.curve_options.grid_resolution >= 16 && o.curve_options.grid_resolution <= 2048),
          "grid_resolution must be 0 (automatic) or between 16 and 2048");
  require(o.threads >= 0 && o.threads <= 256, "threads must be 0 (automatic) or between 1 and 256");
  require(o.polish >= -1 && o.polish <= 1, "polish must be -1 (automatic), 0 or 1");
}

bool polish_enabled(const PipelineOptions& options) {
  return options.polish == 1 || (options.polish == -1 && options.mode == Mode::refit);
}

Formulation formulation_of(const PipelineOptions& options) {
  return options.mode == Mode::paper ? Formulation::coupled : options.solver;
}

int smoothing_rounds(const PipelineOptions& options, bool piecewise) {
  if (options.target_smoothing >= 0) return options.target_smoothing;
  return piecewise ? 1 : 0;
}

double move_limit(const Positions& positions, const PipelineOptions& options, double average_edge) {
  double limit = options.tolerance > 0.0 ? options.tolerance * average_edge : 0.0;
  if (options.max_move > 0.0 && positions.rows() > 0) {
    const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    const double size_limit = options.max_move * diagonal;
    limit = limit > 0.0 ? std::min(limit, size_limit) : size_limit;
  }
  return limit;
}

}  // namespace developable

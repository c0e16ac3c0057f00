#include "core/types.h"

namespace developable {

const char* status_name(Status status) {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::empty_input:
      return "empty_input";
    case Status::index_out_of_range:
      return "index_out_of_range";
    case Status::non_finite_coordinate:
      return "non_finite_coordinate";
    case Status::degenerate_triangle:
      return "degenerate_triangle";
    case Status::duplicate_triangle:
      return "duplicate_triangle";
    case Status::non_manifold:
      return "non_manifold";
    case Status::invalid_argument:
      return "invalid_argument";
    case Status::no_free_vertex:
      return "no_free_vertex";
    case Status::cancelled:
      return "cancelled";
    case Status::numerical_failure:
      return "numerical_failure";
    case Status::out_of_memory:
      return "out_of_memory";
    case Status::internal_error:
      return "internal_error";
    case Status::no_interior_vertex:
      return "no_interior_vertex";
  }
  return "unknown";
}

void Progress::report(double fraction, const char* stage) const {
  const double clamped = fraction < 0.0 ? 0.0 : (fraction > 1.0 ? 1.0 : fraction);
  if (fn != nullptr && !fn(from + (to - from) * clamped, stage, user)) {
    throw EngineError(Status::cancelled, std::string("cancelled during ") + stage);
  }
}

}  // namespace developable

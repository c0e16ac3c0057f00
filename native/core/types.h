// Shared value types of the developable engine.
//
// Every stage takes and returns these plain Eigen types, so that a stage can be
// called on its own (tests, benchmarks) without building the whole pipeline.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace developable {

// Vertex positions, one row (x, y, z) per vertex, in the caller's units.
// Row-major so that a caller's packed float64 buffer maps onto it without a copy.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Triangles, one row of three zero-based vertex indices per face.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

// One unit vector per row (face normals, target normals).
using Normals = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Why the engine refused or stopped. The numeric values are part of the C ABI
// (see developable.h) and must never change.
enum class Status : int {
  ok = 0,
  empty_input = 1,            // no vertices or no triangles
  index_out_of_range = 2,     // a triangle names a vertex that does not exist
  non_finite_coordinate = 3,  // NaN or infinite coordinate
  degenerate_triangle = 4,    // zero area, or a vertex repeated inside a triangle
  duplicate_triangle = 5,     // the same three vertices appear twice
  non_manifold = 6,           // an edge with more than two faces, or a non-manifold vertex
  invalid_argument = 7,       // a parameter out of its range, a null pointer, a bad buffer size
  no_free_vertex = 8,         // every vertex is pinned: nothing can move
  cancelled = 9,              // the progress callback asked to stop
  numerical_failure = 10,     // the factorisation failed or the result went non-finite
  out_of_memory = 11,         // an allocation failed or the mesh exceeds the memory budget
  internal_error = 12,        // a bug: please report it with the input mesh
  no_interior_vertex = 13,    // every vertex is on the boundary: no curvature to reduce
};

// Human-readable name of a status, e.g. "non_manifold".
const char* status_name(Status status);

// The one exception type the engine throws; the C ABI turns it into a code and
// a message. Messages name the first offending element ("triangle 17 ...").
class EngineError : public std::runtime_error {
 public:
  EngineError(Status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  Status status() const { return status_; }

 private:
  Status status_;
};

// Progress report: fraction in [0, 1] and the name of the running stage.
// Returns false to cancel the run; the engine then throws Status::cancelled.
using ProgressFn = bool (*)(double fraction, const char* stage, void* user);

// A progress callback plus its user pointer, passed by value through stages.
// A stage reports its own fraction in [0, 1]; `from` and `to` map it into the
// share of the whole run that the caller gave the stage (see sub()).
struct Progress {
  ProgressFn fn = nullptr;
  void* user = nullptr;
  double from = 0.0;
  double to = 1.0;

  // Report and throw EngineError(cancelled) when the callback says stop.
  void report(double fraction, const char* stage) const;

  // The same callback for a stage that runs from `begin` to `end` (fractions
  // of this one's range).
  Progress sub(double begin, double end) const {
    return {fn, user, from + (to - from) * begin, from + (to - from) * end};
  }
};

}  // namespace developable

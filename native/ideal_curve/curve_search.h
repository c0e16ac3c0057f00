// Target normals on the ideal curves (paper, Sec. III): each face normal's
// nearest point on its patch's curves (ideal_curve.h), measured on the sphere.
//
// The curves change only when they are refit (every few iterations of the
// refit mode), while the normals are projected onto them every iteration: the
// search structure is built once per fit and kept (CurveSearch), so the
// iterations in between only query it.
#pragma once

#include "core/types.h"
#include "ideal_curve/ideal_curve.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace developable {

// Nearest points on a fixed set of sphere curves. Segments between
// consecutive polyline points are great-circle arcs, except between points
// 90 degrees or more apart, where only the two points count (no arc: the
// shorter great circle is no longer a sensible curve; fitted curves are
// sampled far more densely); runs of a few
// consecutive arcs form the leaves of a tree of bounding balls, so a query
// costs about log(arcs) ball tests and is exact. Immutable once built; safe
// to query from several threads.
class CurveSearch {
 public:
  // No curves: nearest() throws.
  CurveSearch() = default;

  // curves: non-empty, as returned by fit_ideal_curves; their points need not
  // be exactly unit (they are normalised here).
  // Throws EngineError(invalid_argument) on no curve, an empty curve or a zero
  // or non-finite point. O(points) time and memory.
  explicit CurveSearch(const std::vector<SphereCurve>& curves);

  bool empty() const { return tree_ == nullptr; }

  // The target normal of each row: its nearest point on the curves, a unit
  // vector. A zero row gets the first curve point.
  //   normals: one per row, any length (normalised here), finite.
  //   hints: null, or the caller's scratch kept between calls on the same
  //   search with the same rows: each row's answer (an arc index), from which
  //   the next call starts. A row's normal moves little between iterations,
  //   so its last answer is a tight first guess and saves the descent of the
  //   tree. The answer is exact whatever the hints (resized and reset when
  //   their size does not match).
  // Throws EngineError(invalid_argument) on a non-finite normal or when
  // empty(). Large inputs are split over `threads` threads (0: the
  // machine's, at most 8); the result does not depend on how many run.
  Normals nearest(const Normals& normals, std::vector<int>* hints = nullptr, int threads = 0) const;

 private:
  struct Tree;                        // arcs and balls, in curve_search.cpp
  std::shared_ptr<const Tree> tree_;  // immutable, so copies may share it
};

}  // namespace developable

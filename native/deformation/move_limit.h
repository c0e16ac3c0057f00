// The move limit (E_allow): how far a vertex may go from where the user had
// it. Its value comes from the run's options (move_limit in
// pipeline/options.h); every stage that moves vertices keeps them within it
// through these.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

namespace developable {

// `position` put back onto the ball of radius `limit` around `reference`
// when it left it (caller's units; limit <= 0: no limit, unchanged).
inline Eigen::RowVector3d within_limit(const Eigen::RowVector3d& position, const Eigen::RowVector3d& reference,
                                       double limit) {
  if (limit <= 0.0) return position;
  const Eigen::RowVector3d move = position - reference;
  const double length = move.norm();
  return length > limit ? Eigen::RowVector3d(reference + move * (limit / length)) : position;
}

// Every vertex of `positions` within `limit` of its row in `reference`.
inline void clamp_moves(Positions& positions, const Positions& reference, double limit) {
  if (limit <= 0.0) return;
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    positions.row(v) = within_limit(positions.row(v), reference.row(v), limit);
}

}  // namespace developable

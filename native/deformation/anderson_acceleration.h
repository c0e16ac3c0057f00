// Anderson acceleration of the deformation's iterations (beyond the paper).
//
// The refit mode's iterations are a fixed-point iteration x <- G(x): refit
// the targets on x, then solve the local-global system. Once the mesh is
// flat to the eye they converge linearly and slowly (the 100k-face noisy
// cone: flat at iteration 10, then 45 more for a third of its mean |defect|).
// Anderson acceleration (type II, as Peng et al. 2018 use it on
// local-global geometry solvers) mixes the last few G values so that their
// residuals G(x) - x cancel best in the least-squares sense:
//   x_next = G(x_k) - sum_i gamma_i (G(x_{i+1}) - G(x_i)),
//   gamma = argmin | f_k - sum_i gamma_i (f_{i+1} - f_i) |,  f = G(x) - x.
// The caller checks the mixed iterate (folds, creases, the move limit) and
// calls reset() where it takes the plain step instead.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace developable {

class AndersonAcceleration {
 public:
  // memory >= 1: how many differences of earlier iterates are mixed.
  // Throws EngineError(invalid_argument) otherwise.
  explicit AndersonAcceleration(int memory);

  // The accelerated iterate after the plain step `step` = G(previous), both
  // n x 3 of one size throughout (until reset). Nothing after the first call
  // following construction or reset(), which only records the step: the
  // plain step stands. Deterministic: the same inputs give the same bits
  // whatever ran before on other objects.
  // Throws EngineError(invalid_argument) on a size change without reset().
  std::optional<Positions> next(const Positions& previous, const Positions& step);

  // Forgets the history (after a step whose mixed iterate was refused).
  void reset();

 private:
  int memory_;
  int count_ = 0;                                  // differences held, <= memory_
  int newest_ = -1;                                // slot of the newest difference in the rings
  Eigen::VectorXd last_residual_, last_step_;      // f_k and G(x_k), flattened
  std::vector<Eigen::VectorXd> residual_changes_;  // f_{i+1} - f_i, a ring of memory_
  std::vector<Eigen::VectorXd> step_changes_;      // G(x_{i+1}) - G(x_i), the same slots
  Eigen::MatrixXd gram_;                           // dot products of residual_changes_
};

}  // namespace developable

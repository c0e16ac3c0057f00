#include "deformation/anderson_acceleration.h"

#include "core/types.h"

#include <Eigen/Cholesky>

#include <string>

namespace developable {

namespace {

Eigen::Map<const Eigen::VectorXd> flat(const Positions& p) { return {p.data(), p.size()}; }

}  // namespace

AndersonAcceleration::AndersonAcceleration(int memory) : memory_(memory) {
  if (memory < 1) throw EngineError(Status::invalid_argument, "anderson acceleration: memory must be at least 1");
  residual_changes_.resize(static_cast<size_t>(memory));
  step_changes_.resize(static_cast<size_t>(memory));
  gram_ = Eigen::MatrixXd::Zero(memory, memory);
}

void AndersonAcceleration::reset() {
  count_ = 0;
  newest_ = -1;
  last_residual_.resize(0);
  last_step_.resize(0);
}

std::optional<Positions> AndersonAcceleration::next(const Positions& previous, const Positions& step) {
  if (previous.rows() != step.rows())
    throw EngineError(Status::invalid_argument, "anderson acceleration: iterates of different sizes");
  const Eigen::Index size = step.size();
  if (last_step_.size() != 0 && last_step_.size() != size)
    throw EngineError(Status::invalid_argument, "anderson acceleration: the mesh changed without reset");
  const Eigen::Map<const Eigen::VectorXd> g = flat(step);
  Eigen::VectorXd residual = g - flat(previous);
  if (last_step_.size() == 0) {
    last_residual_ = std::move(residual);
    last_step_ = g;
    return std::nullopt;
  }
  // The newest differences go into the oldest slot; only their row of the
  // Gram matrix is new.
  newest_ = (newest_ + 1) % memory_;
  count_ = std::min(count_ + 1, memory_);
  const size_t slot = static_cast<size_t>(newest_);
  residual_changes_[slot] = residual - last_residual_;
  step_changes_[slot] = g - last_step_;
  for (int i = 0; i < count_; ++i) {
    const double dot = residual_changes_[static_cast<size_t>(i)].dot(residual_changes_[slot]);
    gram_(i, newest_) = dot;
    gram_(newest_, i) = dot;
  }
  last_residual_ = std::move(residual);
  last_step_ = g;

  // gamma = argmin |f_k - dF gamma|: the normal equations, regularised
  // relative to their diagonal so that nearly parallel differences (a
  // stalled run) cannot blow the mix up.
  Eigen::MatrixXd normal = gram_.topLeftCorner(count_, count_);
  Eigen::VectorXd rhs(count_);
  for (int i = 0; i < count_; ++i) rhs[i] = residual_changes_[static_cast<size_t>(i)].dot(last_residual_);
  normal.diagonal().array() += 1e-10 * normal.diagonal().maxCoeff() + 1e-300;
  const Eigen::VectorXd gamma = normal.ldlt().solve(rhs);
  Positions mixed = step;
  Eigen::Map<Eigen::VectorXd> x(mixed.data(), size);
  for (int i = 0; i < count_; ++i) x -= gamma[i] * step_changes_[static_cast<size_t>(i)];
  return mixed;
}

}  // namespace developable

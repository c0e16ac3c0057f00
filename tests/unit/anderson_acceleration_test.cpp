// anderson_acceleration.h: the first call only records the step, a linear
// contraction reaches its fixed point in far fewer mixed steps than plain
// ones, reset() forgets, bad use throws.
#include "deformation/anderson_acceleration.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace developable {
namespace {

// G(x) = M x + b on the flattened positions: a contraction whose slowest
// mode decays by 0.97 per step, the regime of the deformation's late
// iterations.
struct LinearMap {
  Eigen::MatrixXd M;
  Eigen::VectorXd b;
  LinearMap(Eigen::Index rows) {
    const Eigen::Index n = 3 * rows;
    const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(n, n)).householderQ();
    Eigen::VectorXd rates = Eigen::VectorXd::LinSpaced(n, 0.2, 0.97);
    M = q * rates.asDiagonal() * q.transpose();
    b = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  }
  Positions operator()(const Positions& x) const {
    Positions y(x.rows(), 3);
    Eigen::Map<Eigen::VectorXd>(y.data(), y.size()) = M * Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()) + b;
    return y;
  }
  double residual(const Positions& x) const { return ((*this)(x)-x).norm(); }
};

int steps_to_converge(const LinearMap& g, AndersonAcceleration* acceleration) {
  Positions x = Positions::Zero(10, 3);
  for (int k = 1; k <= 2000; ++k) {
    const Positions step = g(x);
    const std::optional<Positions> mixed = acceleration ? acceleration->next(x, step) : std::nullopt;
    x = mixed ? *mixed : step;
    if (g.residual(x) < 1e-8) return k;
  }
  return 2000;
}

TEST(AndersonAcceleration, FirstCallOnlyRecords) {
  AndersonAcceleration acceleration(5);
  const Positions previous = Positions::Random(4, 3), step = Positions::Random(4, 3);
  EXPECT_FALSE(acceleration.next(previous, step));
  EXPECT_TRUE(acceleration.next(step, previous));
  acceleration.reset();
  EXPECT_FALSE(acceleration.next(step, previous));
}

TEST(AndersonAcceleration, ReachesALinearFixedPointInFarFewerSteps) {
  const LinearMap g(10);
  const int plain = steps_to_converge(g, nullptr);
  AndersonAcceleration acceleration(5);
  const int mixed = steps_to_converge(g, &acceleration);
  EXPECT_GT(plain, 400);
  EXPECT_LT(mixed, plain / 4);
}

TEST(AndersonAcceleration, SameInputsSameBits) {
  const LinearMap g(6);
  AndersonAcceleration a(3), b(3);
  Positions x = Positions::Zero(6, 3), y = x;
  for (int k = 0; k < 20; ++k) {
    const Positions gx = g(x), gy = g(y);
    x = a.next(x, gx).value_or(gx);
    y = b.next(y, gy).value_or(gy);
  }
  EXPECT_EQ(x, y);
}

TEST(AndersonAcceleration, BadUseThrows) {
  EXPECT_THROW(AndersonAcceleration(0), EngineError);
  AndersonAcceleration acceleration(2);
  acceleration.next(Positions::Zero(4, 3), Positions::Ones(4, 3));
  EXPECT_THROW(acceleration.next(Positions::Zero(5, 3), Positions::Ones(5, 3)), EngineError);
  EXPECT_THROW(acceleration.next(Positions::Zero(4, 3), Positions::Ones(5, 3)), EngineError);
  acceleration.reset();
  EXPECT_NO_THROW(acceleration.next(Positions::Zero(5, 3), Positions::Ones(5, 3)));
}

}  // namespace
}  // namespace developable

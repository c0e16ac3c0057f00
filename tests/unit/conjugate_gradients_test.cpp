// conjugate_gradients.h: Eigen's conjugate gradients (Lower | Upper, diagonal
// preconditioner) bit for bit, however many spare cores the products take.
#include "deformation/conjugate_gradients.h"

#include <gtest/gtest.h>

#include <Eigen/IterativeLinearSolvers>

#include <random>
#include <vector>

namespace developable {
namespace {

// A symmetric positive definite matrix with the pattern of a grid's
// two-ring (as J J^T has), random values, both triangles stored.
Eigen::SparseMatrix<double> two_ring_matrix(int side, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    const int x = i % side, y = i / side;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int u = x + dx, w = y + dy, j = w * side + u;
        if (u < 0 || u >= side || w < 0 || w >= side || j <= i) continue;
        const double v = value(random);
        entries.emplace_back(i, j, v);
        entries.emplace_back(j, i, v);
      }
    entries.emplace_back(i, i, 30.0 + 10.0 * value(random));
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  m.makeCompressed();
  return m;
}

Eigen::VectorXd eigens_solution(const Eigen::SparseMatrix<double>& m, const Eigen::VectorXd& rhs, int iterations,
                                double tolerance) {
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
  solver.setMaxIterations(iterations);
  solver.setTolerance(tolerance);
  solver.compute(m);
  return solver.solve(rhs);
}

TEST(ConjugateGradients, EigensStepsBitForBitOnAnyNumberOfCores) {
  const Eigen::SparseMatrix<double> m = two_ring_matrix(90, 3);  // 8100 rows: 4 chunks of the product
  std::mt19937 random(5);
  std::normal_distribution<double> normal;
  Eigen::VectorXd rhs(m.rows());
  for (Eigen::Index i = 0; i < rhs.size(); ++i) rhs[i] = normal(random);
  for (const int iterations : {1, 10, 90}) {
    for (const double tolerance : {1e-8, 1e-2}) {
      const Eigen::VectorXd expected = eigens_solution(m, rhs, iterations, tolerance);
      for (const int threads : {1, 2, 3, 8}) {
        SpareCores spare(threads);
        ConjugateGradients solver;
        solver.compute(m);
        const Eigen::VectorXd y = solver.solve(rhs, iterations, tolerance, &spare);
        ASSERT_EQ(y.size(), expected.size());
        for (Eigen::Index i = 0; i < y.size(); ++i)
          ASSERT_EQ(y[i], expected[i]) << "row " << i << ", " << iterations << " iterations, " << threads << " threads";
        EXPECT_EQ(spare.take(64), static_cast<unsigned>(threads - 1)) << "every core given back";
      }
      ConjugateGradients alone;
      alone.compute(m);
      EXPECT_TRUE(alone.solve(rhs, iterations, tolerance, nullptr) == expected);
    }
  }
}

TEST(ConjugateGradients, AZeroRightHandSideGivesZero) {
  const Eigen::SparseMatrix<double> m = two_ring_matrix(10, 1);
  ConjugateGradients solver;
  solver.compute(m);
  EXPECT_TRUE(solver.solve(Eigen::VectorXd::Zero(m.rows()), 10, 1e-8, nullptr).isZero(0.0));
}

}  // namespace
}  // namespace developable

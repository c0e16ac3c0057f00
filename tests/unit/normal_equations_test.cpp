// normal_equations.h: J built row by row, J^T J and J^T b the same bit for
// bit as Eigen's setFromTriplets, SparseMatrix(J.transpose() * J) (with the
// missing diagonal entries inserted) and J.transpose() * b.
#include "deformation/normal_equations.h"

#include "core/types.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace developable {
namespace {

struct Entry {
  int row, column;
  double value;
};

// Rows of a few entries each, some repeated (summed), some rows empty, and
// the last columns reached by no row.
std::vector<Entry> random_entries(int rows, int columns, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> size(0, 8), column(0, columns - 4);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  std::vector<Entry> entries;
  for (int r = 0; r < rows; ++r) {
    const int count = r % 7 == 3 ? 0 : size(random);
    for (int k = 0; k < count; ++k) {
      const int c = column(random);
      entries.push_back({r, c, value(random)});
      if (k % 3 == 0) entries.push_back({r, c, value(random)});  // added twice
    }
  }
  return entries;
}

// The same with every entry a vertex's three columns 3c, 3c + 1, 3c + 2 (as
// the ruled polish adds them): J^T J's columns come in triples.
std::vector<Entry> random_triples(int rows, int columns, unsigned seed) {
  std::vector<Entry> entries;
  for (const Entry& e : random_entries(rows, columns / 3, seed))
    for (int k = 0; k < 3; ++k) entries.push_back({e.row, 3 * e.column + k, e.value * (1.0 + 0.37 * k)});
  return entries;
}

void expect_same_bits(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  ASSERT_TRUE(a.isCompressed());
  ASSERT_TRUE(b.isCompressed());
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  for (Eigen::Index c = 0; c <= a.cols(); ++c) ASSERT_EQ(a.outerIndexPtr()[c], b.outerIndexPtr()[c]);
  for (Eigen::Index k = 0; k < a.nonZeros(); ++k) {
    ASSERT_EQ(a.innerIndexPtr()[k], b.innerIndexPtr()[k]);
    ASSERT_EQ(std::memcmp(a.valuePtr() + k, b.valuePtr() + k, sizeof(double)), 0) << "entry " << k;
  }
}

// Builds J of `entries` into `equations`, weights its rows, and expects
// Eigen's J^T J and J^T b bit for bit.
void expect_eigens_products(NormalEquations& equations, const std::vector<Entry>& entries, int rows, int columns,
                            unsigned seed) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (const Entry& e : entries) triplets.emplace_back(e.row, e.column, e.value);
  Eigen::SparseMatrix<double> jac(rows, columns);
  jac.setFromTriplets(triplets.begin(), triplets.end());

  equations.start(columns);
  int open = -1;
  for (const Entry& e : entries) {
    while (open < e.row) {
      equations.next_row();
      ++open;
    }
    equations.add(e.column, e.value);
  }
  while (open < rows - 1) {
    equations.next_row();
    ++open;
  }
  ASSERT_EQ(equations.rows(), rows);

  std::mt19937 random(seed + 10);
  std::uniform_real_distribution<double> value(0.1, 3.0);
  Eigen::VectorXd weights(rows), b(rows);
  for (int r = 0; r < rows; ++r) {
    weights[r] = value(random);
    b[r] = value(random) - 1.5;
  }
  for (Eigen::Index k = 0; k < jac.nonZeros(); ++k) jac.valuePtr()[k] *= weights[jac.innerIndexPtr()[k]];
  equations.scale_rows(weights);

  Eigen::SparseMatrix<double> expected = Eigen::SparseMatrix<double>(jac.transpose() * jac);
  for (Eigen::Index c = 0; c < expected.rows(); ++c) expected.coeffRef(c, c);
  expected.makeCompressed();
  expect_same_bits(equations.normal_matrix(), expected);

  const Eigen::VectorXd expected_gradient = jac.transpose() * b;
  const Eigen::VectorXd gradient = equations.transposed_times(b);
  ASSERT_EQ(gradient.size(), expected_gradient.size());
  EXPECT_EQ(std::memcmp(gradient.data(), expected_gradient.data(), sizeof(double) * gradient.size()), 0);
}

TEST(NormalEquations, EigensProductsBitForBit) {
  NormalEquations equations;
  // Twice with the same object: the buffers of the first J must not leak
  // into the second (a smaller one).
  for (const auto& [rows, columns, seed] : {std::tuple{400, 300, 1u}, std::tuple{150, 90, 2u}})
    expect_eigens_products(equations, random_entries(rows, columns, seed), rows, columns, seed);
}

TEST(NormalEquations, ColumnsInTriplesGiveEigensProductsBitForBit) {
  NormalEquations equations;
  // Triples, then scattered columns, then triples again with the same object.
  expect_eigens_products(equations, random_triples(400, 300, 3), 400, 300, 3);
  expect_eigens_products(equations, random_entries(150, 90, 4), 150, 90, 4);
  expect_eigens_products(equations, random_triples(150, 93, 5), 150, 93, 5);
  // Triples but for one more row that holds one column of a triple alone.
  std::vector<Entry> broken = random_triples(100, 60, 6);
  broken.push_back({100, 0, 1.5});
  expect_eigens_products(equations, broken, 101, 60, 6);
}

TEST(NormalEquations, RefusesEntriesOutsideJ) {
  NormalEquations equations;
  equations.start(4);
  EXPECT_THROW(equations.add(0, 1.0), EngineError);  // no row open
  equations.next_row();
  EXPECT_THROW(equations.add(4, 1.0), EngineError);
  EXPECT_THROW(equations.add(-1, 1.0), EngineError);
  EXPECT_THROW(equations.scale_rows(Eigen::VectorXd::Ones(2)), EngineError);
}

}  // namespace
}  // namespace developable

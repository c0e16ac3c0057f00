// The normal equations of a Gauss-Newton step whose Jacobian changes shape
// from step to step.
//
// The ruled polish (ruled_polish.cpp) builds a new Jacobian J at every step
// (the vertices it moves change) and solves with J^T J and J^T r. Built with
// Eigen (setFromTriplets, then SparseMatrix(J.transpose() * J)), each step
// allocated the triplets, J, its row-major copy, the product and its
// transposed copy afresh: at 200k faces several hundred MB a step, a third of
// the run's CPU time in the kernel's page faults. Here J goes row by row into
// buffers kept from one step to the next, and J^T J and J^T b are formed from
// them with Eigen's own arithmetic, so the values are Eigen's bit for bit:
//   J        as setFromTriplets of the entries in the order they were added
//            (an entry added twice is the sum in that order);
//   J^T J    as SparseMatrix(J.transpose() * J): entry (i, j) the sum over the
//            rows holding both columns, in ascending order, of J(r, i) J(r, j);
//            compressed, each column's rows ascending, and an explicit 0 on
//            every diagonal entry no row reaches (as coeffRef(c, c) inserts);
//   J^T b    as J.transpose() * b.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace developable {

class NormalEquations {
 public:
  // Starts an empty J of `columns` columns (>= 0); the buffers stay.
  void start(Eigen::Index columns);

  // Opens the next row; rows are numbered from 0 in the order opened.
  void next_row();

  // Adds `value` to J(the open row, column); column in [0, columns).
  void add(int column, double value);

  Eigen::Index rows() const { return static_cast<Eigen::Index>(row_start_.size()) - 1; }

  // Multiplies every entry of row r by weights[r] (weights: one per row).
  void scale_rows(const Eigen::VectorXd& weights);

  // J^T b (b: one value per row).
  Eigen::VectorXd transposed_times(const Eigen::VectorXd& b);

  // J^T J as described above; valid until the next start(). Its values may be
  // changed in place (damping on the diagonal).
  Eigen::SparseMatrix<double>& normal_matrix();

 private:
  // J by columns (rows ascending), from the rows, once per J.
  void index_columns();
  // Whether J's columns come in triples 3c, 3c + 1, 3c + 2 held by the same
  // rows (a vertex's three coordinates, as the ruled polish adds them): then
  // J^T J forms a triple's columns in one pass, with the same sums.
  bool columns_in_triples();

  Eigen::Index columns_ = 0;
  std::vector<Eigen::Index> row_start_{0};  // row r's entries: [row_start_[r], row_start_[r + 1])
  std::vector<int> column_;                 // per entry, in the order first added
  std::vector<double> value_;
  std::vector<Eigen::Index> slot_;  // column -> its entry in the open row, or -1
  bool indexed_ = false;
  std::vector<Eigen::Index> column_start_;  // J by columns
  std::vector<int> column_row_;
  std::vector<double> column_value_;
  std::vector<double> sum_;  // J^T J's accumulators of up to three columns (3 i + k), with their marks and rows
  std::vector<char> touched_;
  std::vector<int> touched_rows_;
  Eigen::SparseMatrix<double> normal_;
};

}  // namespace developable

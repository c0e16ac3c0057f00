#include "deformation/normal_equations.h"

#include "core/types.h"

#include <algorithm>

namespace developable {

void NormalEquations::start(Eigen::Index columns) {
  columns_ = std::max<Eigen::Index>(columns, 0);
  row_start_.assign(1, 0);
  column_.clear();
  value_.clear();
  slot_.assign(static_cast<size_t>(columns_), -1);
  indexed_ = false;
}

void NormalEquations::next_row() {
  // The open row's columns forget their slots before the next row opens.
  if (rows() > 0)
    for (Eigen::Index k = row_start_[row_start_.size() - 2]; k < row_start_.back(); ++k)
      slot_[static_cast<size_t>(column_[static_cast<size_t>(k)])] = -1;
  row_start_.push_back(row_start_.back());
  indexed_ = false;
}

void NormalEquations::add(int column, double value) {
  if (rows() == 0 || column < 0 || column >= columns_)
    throw EngineError(Status::internal_error, "normal equations: an entry outside J");
  Eigen::Index& slot = slot_[static_cast<size_t>(column)];
  if (slot >= 0) {
    value_[static_cast<size_t>(slot)] += value;
    return;
  }
  slot = static_cast<Eigen::Index>(column_.size());
  column_.push_back(column);
  value_.push_back(value);
  row_start_.back() = static_cast<Eigen::Index>(column_.size());
  indexed_ = false;
}

void NormalEquations::scale_rows(const Eigen::VectorXd& weights) {
  if (weights.size() != rows()) throw EngineError(Status::internal_error, "normal equations: a weight per row");
  for (Eigen::Index r = 0; r < rows(); ++r)
    for (Eigen::Index k = row_start_[static_cast<size_t>(r)]; k < row_start_[static_cast<size_t>(r) + 1]; ++k)
      value_[static_cast<size_t>(k)] *= weights[r];
  indexed_ = false;
}

void NormalEquations::index_columns() {
  if (indexed_) return;
  column_start_.assign(static_cast<size_t>(columns_) + 1, 0);
  for (int c : column_) ++column_start_[static_cast<size_t>(c) + 1];
  for (size_t c = 1; c < column_start_.size(); ++c) column_start_[c] += column_start_[c - 1];
  column_row_.resize(column_.size());
  column_value_.resize(column_.size());
  std::vector<Eigen::Index> next(column_start_.begin(), column_start_.end() - 1);
  for (Eigen::Index r = 0; r < rows(); ++r)
    for (Eigen::Index k = row_start_[static_cast<size_t>(r)]; k < row_start_[static_cast<size_t>(r) + 1]; ++k) {
      const auto at = static_cast<size_t>(next[static_cast<size_t>(column_[static_cast<size_t>(k)])]++);
      column_row_[at] = static_cast<int>(r);
      column_value_[at] = value_[static_cast<size_t>(k)];
    }
  indexed_ = true;
}

Eigen::VectorXd NormalEquations::transposed_times(const Eigen::VectorXd& b) {
  if (b.size() != rows()) throw EngineError(Status::internal_error, "normal equations: a value per row");
  index_columns();
  Eigen::VectorXd result(columns_);
  for (Eigen::Index c = 0; c < columns_; ++c) {
    // Eigen's sparse * dense product of a row-major left side: a sum from 0.
    double sum = 0.0;
    for (Eigen::Index k = column_start_[static_cast<size_t>(c)]; k < column_start_[static_cast<size_t>(c) + 1]; ++k)
      sum += column_value_[static_cast<size_t>(k)] * b[column_row_[static_cast<size_t>(k)]];
    result[c] = sum;
  }
  return result;
}

Eigen::SparseMatrix<double>& NormalEquations::normal_matrix() {
  index_columns();
  sum_.resize(static_cast<size_t>(columns_));
  touched_.assign(static_cast<size_t>(columns_), 0);
  normal_.resize(columns_, columns_);  // keeps the storage of the last step
  // Eigen's conservative sparse product, column j of J^T J at a time: over
  // the rows holding column j (ascending), each of their entries' products,
  // the first of a sum assigned, the next ones added.
  for (Eigen::Index j = 0; j < columns_; ++j) {
    touched_rows_.clear();
    for (Eigen::Index a = column_start_[static_cast<size_t>(j)]; a < column_start_[static_cast<size_t>(j) + 1]; ++a) {
      const double y = column_value_[static_cast<size_t>(a)];
      const auto r = static_cast<size_t>(column_row_[static_cast<size_t>(a)]);
      for (Eigen::Index k = row_start_[r]; k < row_start_[r + 1]; ++k) {
        const int i = column_[static_cast<size_t>(k)];
        const double product = value_[static_cast<size_t>(k)] * y;
        if (touched_[static_cast<size_t>(i)]) {
          sum_[static_cast<size_t>(i)] += product;
        } else {
          touched_[static_cast<size_t>(i)] = 1;
          sum_[static_cast<size_t>(i)] = product;
          touched_rows_.push_back(i);
        }
      }
    }
    if (!touched_[static_cast<size_t>(j)]) {
      touched_[static_cast<size_t>(j)] = 1;
      sum_[static_cast<size_t>(j)] = 0.0;
      touched_rows_.push_back(static_cast<int>(j));
    }
    std::sort(touched_rows_.begin(), touched_rows_.end());
    normal_.startVec(j);
    for (int i : touched_rows_) {
      normal_.insertBack(i, j) = sum_[static_cast<size_t>(i)];
      touched_[static_cast<size_t>(i)] = 0;
    }
  }
  normal_.finalize();
  return normal_;
}

}  // namespace developable

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

bool NormalEquations::columns_in_triples() {
  index_columns();
  if (columns_ % 3 != 0) return false;
  const auto at = [&](Eigen::Index j) { return column_start_[static_cast<size_t>(j)]; };
  for (Eigen::Index c = 0; c < columns_; c += 3) {
    const Eigen::Index length = at(c + 1) - at(c);
    if (at(c + 2) - at(c + 1) != length || at(c + 3) - at(c + 2) != length) return false;
    for (Eigen::Index a = 0; a < length; ++a) {
      const int r = column_row_[static_cast<size_t>(at(c) + a)];
      if (column_row_[static_cast<size_t>(at(c + 1) + a)] != r || column_row_[static_cast<size_t>(at(c + 2) + a)] != r)
        return false;
    }
  }
  return true;
}

Eigen::SparseMatrix<double>& NormalEquations::normal_matrix() {
  const bool triples = columns_in_triples();
  sum_.resize(static_cast<size_t>(3 * columns_));
  touched_.assign(static_cast<size_t>(columns_), 0);
  normal_.resize(columns_, columns_);  // keeps the storage of the last step
  // Eigen's conservative sparse product, column j of J^T J at a time: over
  // the rows holding column j (ascending), each of their entries' products,
  // the first of a sum assigned, the next ones added. Columns in triples
  // share their rows, so a triple's three columns are summed side by side,
  // each entry's terms in the same order as alone.
  const Eigen::Index width = triples ? 3 : 1;
  for (Eigen::Index j = 0; j < columns_; j += width) {
    touched_rows_.clear();
    const Eigen::Index first = column_start_[static_cast<size_t>(j)];
    const Eigen::Index last = column_start_[static_cast<size_t>(j) + 1];
    for (Eigen::Index a = first; a < last; ++a) {
      double y[3];
      for (Eigen::Index k = 0; k < width; ++k)
        y[k] = column_value_[static_cast<size_t>(column_start_[static_cast<size_t>(j + k)] + (a - first))];
      const auto r = static_cast<size_t>(column_row_[static_cast<size_t>(a)]);
      for (Eigen::Index e = row_start_[r]; e < row_start_[r + 1]; ++e) {
        const int i = column_[static_cast<size_t>(e)];
        const double x = value_[static_cast<size_t>(e)];
        double* sum = &sum_[static_cast<size_t>(3 * i)];
        if (touched_[static_cast<size_t>(i)]) {
          for (Eigen::Index k = 0; k < width; ++k) sum[k] += x * y[k];
        } else {
          touched_[static_cast<size_t>(i)] = 1;
          for (Eigen::Index k = 0; k < width; ++k) sum[k] = x * y[k];
          touched_rows_.push_back(i);
        }
      }
    }
    std::sort(touched_rows_.begin(), touched_rows_.end());
    // A column no row holds gets its explicit zero diagonal (one that a row
    // holds is among the touched rows: so are the rest of its triple).
    const bool empty = touched_rows_.empty();
    for (Eigen::Index k = 0; k < width; ++k) {
      normal_.startVec(j + k);
      if (empty) normal_.insertBack(j + k, j + k) = 0.0;
      for (int i : touched_rows_) normal_.insertBack(i, j + k) = sum_[static_cast<size_t>(3 * i + k)];
    }
    for (int i : touched_rows_) touched_[static_cast<size_t>(i)] = 0;
  }
  normal_.finalize();
  return normal_;
}

}  // namespace developable

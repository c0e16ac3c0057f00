#include "deformation/conjugate_gradients.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace developable {
namespace {

// Rows of a product per chunk: a 40k-row J J^T (about 20 entries a row) is
// 20 chunks, each long against the start of a thread.
constexpr Eigen::Index kProductRows = 2048;

}  // namespace

void ConjugateGradients::compute(const Eigen::SparseMatrix<double>& matrix) {
  matrix_ = &matrix;
  preconditioner_.compute(matrix);
}

void ConjugateGradients::product(const Eigen::VectorXd& x, Eigen::VectorXd& out, SpareCores* spare) const {
  const Eigen::SparseMatrix<double>& m = *matrix_;
  out.resize(m.rows());
  // Row i is column i (the matrix is symmetric), summed in the order of its
  // stored entries from 0, then added to a zero: Eigen's row-major product
  // of the transpose (what its solver multiplies by) to the last bit.
  parallel_for(m.outerSize(), kProductRows, spare, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) {
      double sum = 0.0;
      for (Eigen::SparseMatrix<double>::InnerIterator it(m, i); it; ++it) sum += it.value() * x[it.index()];
      out[i] = 0.0 + sum;
    }
  });
}

// Eigen's internal::conjugate_gradient (Eigen 3.4), with the product above.
Eigen::VectorXd ConjugateGradients::solve(const Eigen::VectorXd& rhs, int max_iterations, double tolerance,
                                          SpareCores* spare) const {
  const Eigen::Index n = matrix_->cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd tmp(n);
  // Eigen's first residual is rhs - matrix * x at x = 0: that product is
  // zero for finite values (each row 0 + 0), and rhs - 0 is rhs, bit for
  // bit; one product fewer a solve (of 11 at the polish's 10 iterations).
  Eigen::VectorXd residual = rhs;
  const double rhs_norm2 = rhs.squaredNorm();
  if (rhs_norm2 == 0) return Eigen::VectorXd::Zero(n);
  const double threshold = std::max(tolerance * tolerance * rhs_norm2, std::numeric_limits<double>::min());
  double residual_norm2 = residual.squaredNorm();
  if (residual_norm2 < threshold) return x;

  Eigen::VectorXd p(n);
  p = preconditioner_.solve(residual);
  Eigen::VectorXd z(n);
  double abs_new = residual.dot(p);
  for (int i = 0; i < max_iterations; ++i) {
    product(p, tmp, spare);
    const double alpha = abs_new / p.dot(tmp);
    x += alpha * p;
    residual -= alpha * tmp;
    residual_norm2 = residual.squaredNorm();
    if (residual_norm2 < threshold) break;
    z = preconditioner_.solve(residual);
    const double abs_old = abs_new;
    abs_new = residual.dot(z);
    const double beta = abs_new / abs_old;
    p = z + beta * p;
  }
  return x;
}

}  // namespace developable

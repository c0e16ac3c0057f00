// Conjugate gradients on the spare cores.
//
// The angle-defect polish solves its damped systems (J J^T + damping) y = K
// above a few thousand rows by truncated conjugate gradients with a diagonal
// preconditioner (defect_polish.cpp), the ruled polish its normal equations;
// the products are most of their time. These are Eigen's conjugate gradients
// (ConjugateGradient<SparseMatrix, Lower | Upper>, DiagonalPreconditioner)
// step for step and bit for bit, but each product row by row in fixed chunks
// on the calling thread and on whatever cores are spare (SpareCores in
// concurrent_jobs.h): the same arithmetic per row as Eigen's row-major
// product, so the result does not depend on how many cores helped.
#pragma once

#include "core/concurrent_jobs.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

namespace developable {

class ConjugateGradients {
 public:
  // Prepares `matrix` (symmetric, both triangles stored, compressed), which
  // must outlive the solver and keep its values until the next compute: its
  // inverse diagonal (1 where the diagonal is zero or missing).
  void compute(const Eigen::SparseMatrix<double>& matrix);

  // y with matrix y = rhs, from y = 0, stopping after `max_iterations`
  // iterations or once |residual| <= tolerance |rhs|.
  //   spare: null, or the cores the products may take while they are spare.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs, int max_iterations, double tolerance, SpareCores* spare) const;

 private:
  // out = matrix * x, row by row.
  void product(const Eigen::VectorXd& x, Eigen::VectorXd& out, SpareCores* spare) const;

  const Eigen::SparseMatrix<double>* matrix_ = nullptr;
  Eigen::DiagonalPreconditioner<double> preconditioner_;
};

}  // namespace developable

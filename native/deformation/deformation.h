// Stage 7 of the pipeline: normal-guided deformation (paper, Sec. IV, Eqs. 2-7).
//
// Each triangle t = (i, j, k) with target normal n contributes 11 rows:
//   2 normal rows   omega * n . (v_j - v_i) = 0,  omega * n . (v_k - v_i) = 0
//   6 edge rows     v_j - v_i = e_ij,  v_k - v_i = e_ik
//   3 centroid rows sqrt(lambda) (v_i + v_j + v_k) / 3 = sqrt(lambda) centroid
// where e and the centroid are taken from the current positions (each
// iteration updates c, Eq. 3). The paper weighs the centroid rows like the
// others (lambda = 1). They only hold each triangle where it is, so they
// also damp every step; the refit mode uses lambda = 0.3, which converges in
// fewer iterations and to flatter results (docs/method.md has the figures). All 11 rows of t are scaled by the square
// root of its moving-least-squares weight (Eq. 5; see mls_row_weights). Pinned vertices are not unknowns: they keep
// their input coordinates bit for bit.
//
// Two formulations: the paper's least-squares problem, and an approximation
// of it that decouples x, y and z (docs/method.md measures the difference):
//   coupled    the paper's: one 3n x 3n normal matrix W A^T A W (Eq. 7) whose
//              values depend on the targets; the symbolic analysis is done
//              once and a change of targets only refactors numerically;
//   decoupled  the normal rows moved into the right-hand side: each
//              triangle's current edges are rotated toward its target normal
//              by about the angle fraction f = omega^2 / (1 + omega^2) (the
//              optimum of the 2 normal rows + 6 edge rows of that triangle
//              alone removes f of the normal component; the rotation takes
//              the normal onto the normalised blend (1 - f) normal + f target,
//              exact to O(angle^3) and free of trigonometry), and
//              the remaining 9 rows, the same for x, y and z, form one n x n
//              matrix that never changes: factored once, three solves a step.
//              Not the coupled problem's minimiser: each triangle's normal
//              rows are solved alone and the rotated edges are then fitted
//              in the least-squares sense with the centroid rows.
#pragma once

#include "core/types.h"

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace developable {

// The values are DEV_SOLVER_* of the C ABI (developable.h; checked in c_api.cpp).
enum class Formulation { decoupled = 0, coupled = 1 };

// The sparse Cholesky factorisation of both formulations: P A P^T = L D L^T
// with Eigen's approximate-minimum-degree ordering P (bench/solvers.py
// measures it against CHOLMOD; docs/solvers.md).
using CholeskySolver = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

// x = A^-1 b for the three coordinate columns of b at once, given A's
// factorisation `solver` (n x n, computed); b has n rows. Eigen's own solve
// with a 3-column right-hand side sweeps L once per column; this one sweeps
// it once for all three, with x, y and z of an unknown side by side. Above
// ~100k faces L no longer fits in the cache and reading it once makes the
// solve about twice as fast. Same operations in the same order per column as
// Eigen's solve: the result is bit-identical to solver.solve(b).
Positions solve_three_columns(const CholeskySolver& solver, const Positions& b);

// Eq. 5's weight per triangle, applied to the triangle's rows:
//   w(v) = 1 / (d(v)^2 + eps^2),  d = edge-path distance from v to the nearest
//   pinned vertex in units of AE (so the weights do not depend on the mesh's
//   scale), eps = 0.001 as in the paper; row weight s_t = 1 + max over t's
//   vertices of w. Far from pins s_t -> 1; triangles at the pins are stiff,
//   which fades the deformation out smoothly toward the constraints.
// Without pins every weight is 1.
//   positions, triangles: a validated mesh; pinned: one flag per vertex;
//   average_edge_length: AE, > 0.
Eigen::VectorXd mls_row_weights(const Positions& positions, const Triangles& triangles, const std::vector<bool>& pinned,
                                double average_edge_length);

class NormalGuidedDeformation {
 public:
  // Builds and factors the normal matrix (the paper's t_D).
  //   triangles: the validated mesh; pinned: one flag per vertex (at least one
  //   vertex must be free, else EngineError(no_free_vertex));
  //   row_weights: one positive weight per triangle (mls_row_weights, or ones);
  //   omega > 0: weight of the normal rows; centroid_weight > 0: lambda
  //   above; targets: unit target normal per triangle (only the coupled
  //   formulation needs them here); threads: for the per-triangle work of a
  //   step (0: one per core; the result does not depend on it).
  // Throws EngineError(invalid_argument) for a weight out of range,
  // EngineError(numerical_failure) if the factorisation fails.
  NormalGuidedDeformation(const Triangles& triangles, const std::vector<bool>& pinned, Eigen::VectorXd row_weights,
                          double omega, double centroid_weight, Formulation formulation, const Normals& targets,
                          int threads = 0);
  NormalGuidedDeformation(NormalGuidedDeformation&&) = default;
  NormalGuidedDeformation& operator=(NormalGuidedDeformation&&) = default;

  // New target normals, e.g. after the ideal curve was refit. The coupled
  // formulation refactors numerically (same sparsity pattern); the decoupled
  // one only stores them.
  void set_targets(const Normals& targets);
  // The target normals the next step pulls toward (one row per triangle).
  const Normals& targets() const { return targets_; }

  // Per-triangle factors in [0, 1] on omega (decoupled formulation only; the
  // coupled one keeps omega, as refactoring for each change would cost a
  // factorisation): a triangle with factor s is turned by the fraction
  // (s omega)^2 / (1 + (s omega)^2) toward its target, 0 keeps its shape.
  // Empty: all 1. Used to trust thin triangles' normals less and to damp
  // triangles that a step would turn over (pipeline.cpp).
  void set_normal_weights(Eigen::VectorXd weights);

  // One iteration: the positions minimising Eq. 4 with c from `current`.
  // Pinned vertices are copied from `current`. Throws
  // EngineError(numerical_failure) when the solve fails or gives non-finite values.
  Positions step(const Positions& current) const;
  // The same, given the unit face normals of `current` (face_normals in
  // measures.h, one row per triangle), which the refit loop has at hand: the
  // decoupled formulation rotates each triangle from its normal and would
  // otherwise compute them again; the coupled one ignores them.
  Positions step(const Positions& current, const Normals& normals) const;

  // A deformation of the same mesh, pins, row weights, omega and centroid
  // weight, with this one's targets, sharing this one's factorisation
  // instead of computing it again (decoupled formulation only: its matrix
  // does not depend on the targets): its steps are those of a deformation
  // built from the same arguments, bit for bit. The factor is freed when the
  // last deformation sharing it is released or destroyed; a shared factor is
  // only read, so deformations sharing it may step on different threads.
  // Throws EngineError(internal_error) when this one is coupled or released.
  NormalGuidedDeformation sharing_factor() const;

  // Frees the factorisation, the normal matrix and the rest of the system
  // (the largest part of a run's memory after the iterations: 400 MB of a
  // 1M-face sheet's), or this deformation's share of them; a step after it
  // throws EngineError(internal_error), targets() is empty.
  void release();

  // The normal matrix on the free unknowns (n_free x n_free in the decoupled
  // formulation, built anew: the run keeps only its factor; 3 n_free square
  // in the coupled one), for benchmarks of the linear solve
  // (bench/solvers.cpp). Throws EngineError(internal_error) after release().
  Eigen::SparseMatrix<double> system_matrix() const;

 private:
  // The unknowns, the normal matrix on them, its coupling to the pinned
  // coordinates and its factorisation: shared by sharing_factor's copies.
  struct System {
    std::vector<int> free_index;  // vertex -> unknown number, -1 when pinned
    Eigen::Index free_count = 0;
    Eigen::SparseMatrix<double> free_free;    // normal matrix on the free unknowns (coupled only)
    Eigen::SparseMatrix<double> free_pinned;  // its coupling to the pinned coordinates
    CholeskySolver solver;
  };

  NormalGuidedDeformation(const NormalGuidedDeformation&) = default;  // shares the system (sharing_factor)

  // The normal matrix on the free unknowns and its coupling to the pinned
  // coordinates: decoupled (one unknown per free vertex, the same matrix for
  // x, y and z) and coupled (three per free vertex, at the current targets).
  void decoupled_matrices(Eigen::SparseMatrix<double>& free_free, Eigen::SparseMatrix<double>& free_pinned) const;
  void coupled_matrices(Eigen::SparseMatrix<double>& free_free, Eigen::SparseMatrix<double>& free_pinned) const;
  // Builds the coupled matrices at the current targets and factors them.
  void factor_coupled();
  Positions step_coupled(const Positions& current) const;
  Positions step_decoupled(const Positions& current, const Normals& normals) const;

  Triangles triangles_;
  Eigen::VectorXd row_weights_;
  double omega_;
  double centroid_weight_;
  Formulation formulation_;
  Normals targets_;
  int threads_;
  Eigen::VectorXd normal_weights_;  // per triangle in [0, 1], or empty (all 1)
  std::shared_ptr<System> system_;
};

}  // namespace developable

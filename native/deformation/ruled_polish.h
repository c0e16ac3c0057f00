// The ruled polish (beyond the paper; issue 35): the angle defects driven to
// zero together with the ruling spread, so that a vertex is made flat by
// bending its faces about one line, not by triangle-scale zigzags.
//
// The angle-defect polish (defect_polish.h) has one residual per vertex,
// K_v; a vertex can be made flat in many ways, and the least-motion one on a
// doubly curved surface is a zigzag of its faces (flat but crumpled: its
// faces' normals off any great circle). Here every scored vertex v has a
// group of residuals:
//   wK K_v                                   its angle defect (rad)
//   wR sqrt(theta_vf / Theta_v) (u_v . n_f)   for each face f around v
// where theta_vf is f's angle at v, Theta_v their sum and u_v the axis of
// the great circle that fits the normals of v's faces best (held fixed in a
// step, refit after it; ruling_spreads in measures.h measures the same). A
// vertex whose group is zero is flat and ruled (Stein, Grinspun and Crane
// 2018 use the same axis as their energy).
// Each step is a Levenberg-Marquardt step on the iteratively reweighted
// groups: a group of norm rho weighs c = sqrt(eps / sqrt(rho^2 + eps^2))
// (smoothed group L1), so a vertex that cannot be made flat and ruled gives
// up instead of spreading its residual over its neighbours; plain least
// squares leaves every vertex a little off, and the thresholds count
// vertices. A step solves (J^T J + mu mean(diag) I) dx = -J^T r on the
// vertices of the stars of the scored vertices not yet within
// kActiveShare of both thresholds, is tried at full, half and quarter
// length, every vertex put back within `limit` of `reference`, faces turned
// over or creased beyond the crease guard keeping their corners (ring by
// ring); kept when the reweighted sum of squares falls.
// With a fit weight wF > 0 every vertex a step moves also has the rows
//   wF (x_v - reference_v) / AE                (AE: the reference's mean edge length)
// which hold the polish near the reference: flat and ruled alone have every
// developable shape as a minimum, and from a noisy sheet the steps drift
// along them (a noisy cylinder patch polished by the engine's ruled finish
// without the fit: vertices up to 8 times the noise from their places on
// the noise-free twin; ruled_polish_test: 0.53 of the input's RMS distance
// from its cylinder without the fit, 0.36 with it).
// This is the prototype's robust ruled polish (docs/segmentation.md,
// "Thinned pieces") without its soft crease and move barrier rows: the hard
// guard and the clamp hold those.
#pragma once

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

struct RuledPolishOptions {
  int max_iterations = 200;    // Levenberg-Marquardt steps, >= 1
  double defect_weight = 5.0;  // wK
  double ruled_weight = 1.0;   // wR
  double robust = 0.01;        // eps of the group reweighting; 0: plain least squares
  double fit_weight = 0.0;     // wF, the fit to `reference`; 0: none
  double limit = 0.0;          // largest distance from `reference` (caller's units); <= 0: none
  CreaseGuard crease_guard;    // over reference_normals (measures.h); off by default
  // Stop when the robust objective fell by less than stall_decrease over
  // the last stall_window steps.
  int stall_window = 10;
  double stall_decrease = 0.003;
  // Null, or the run's spare cores, which the conjugate gradients' products
  // take while they are spare (conjugate_gradients.h; the same result).
  SpareCores* spare_cores = nullptr;
};

struct RuledPolishResult {
  Positions positions;  // == start when no step was kept
  int iterations = 0;   // steps kept
};

// The ruled polish.
//   start: positions to polish from; reference: the positions the limit is
//   measured from (the user's input); reference_normals: unit face normals a
//   face may not turn more than 90 degrees from, and the crease guard's
//   reference; triangles: a validated mesh; scored: the vertices made flat
//   and ruled (interior ones; others ignored); pinned: empty or one flag per
//   vertex (never moved).
// Returns `start` (iterations 0) when nothing is scored or free or no step
// could be kept. Throws EngineError(internal_error) when the sizes disagree,
// EngineError(cancelled) through `progress`. A factorisation that fails
// counts as a step not kept.
RuledPolishResult polish_ruled(const Positions& start, const Positions& reference, const Normals& reference_normals,
                               const Triangles& triangles, const std::vector<bool>& scored,
                               const std::vector<bool>& pinned, const RuledPolishOptions& options,
                               const Progress& progress);

// The objective polish_ruled lowers, at `positions`: the robust sum over the
// scored vertices' groups (axes fitted at `positions`) plus the fit rows'
// sum of squares against `reference` (dimensionless). Arguments as
// polish_ruled's (the crease guard and the limit play no part). Throws
// EngineError(internal_error) when the sizes disagree.
double ruled_polish_objective(const Positions& positions, const Positions& reference, const Triangles& triangles,
                              const std::vector<bool>& scored, const RuledPolishOptions& options);

}  // namespace developable

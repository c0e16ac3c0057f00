// Stage 8 of the pipeline (beyond the paper): the angle-defect polish.
//
// The normal-guided deformation (stage 7) pulls the face normals onto the
// ideal curves; it controls the angle defect only through them. Where the
// normals are on their curves and the defect still is not zero (the crease
// of a curved fold, irregular connectivity, one-diagonal grids, whose quads
// cannot hold the staircase of normals their rulings need) it stalls, at
// -60 % to -92 % of the mean |defect| on issue 11's families
// (docs/families.md). The polish works on the defects themselves: it moves
// the vertices so that the angle defect K_v of every constrained vertex goes
// to zero, by the least motion.
//
// Each iteration is a Levenberg-Marquardt step on the residual K (one entry
// per constrained vertex), in its minimum-norm form:
//   (J J^T + mu I) y = K,   step = -J^T y
// where J = dK/dx (rows: constrained vertices; columns: the coordinates of
// the free vertices). The gradient of a corner angle theta at a of the
// triangle (a, b, c) with unit normal n is d theta / d b = -(n x (b - a)) /
// |b - a|^2, d theta / d c = (n x (c - a)) / |c - a|^2, d theta / d a = -(sum
// of the two); K_v = 2 pi - sum of v's corner angles. J J^T couples vertices
// that share a neighbour; its pattern never changes, so it is analysed once
// and factored numerically each iteration (Eigen's SimplicialLDLT). A step
// is kept only when it lowers sum K^2, turns no face more than 90 degrees
// from its reference normal and, after moving every vertex back within
// `limit` of its reference position, still lowers it; else mu grows. mu
// (relative to the mean diagonal of J J^T) falls after good steps, down to
// 1e-12, or to `spread_damping` while defects are large.
//
// Only the vertices around the active ones (|K| >= active_defect) move, and
// where they are not the whole mesh the iterations run on the submesh of
// their faces (same result, bit for bit): a deformed 1M-face iterate that is
// flat but for a few vertices is polished in 2 s instead of 12.
//
// The minimum-norm form moves the vertices as little as the linearisation
// allows; it is not the closest developable mesh (that projection was tried
// and measured no closer to the noise-free surfaces: docs/method.md).
#pragma once

#include "core/concurrent_jobs.h"
#include "core/measures.h"
#include "core/types.h"

#include <Eigen/Core>

#include <atomic>
#include <vector>

namespace developable {

struct PolishOptions {
  int max_iterations = 100;     // Levenberg-Marquardt iterations, >= 1
  double target_defect = 1e-7;  // stop once every |K| the polish works on is below this (rad)
  // > 0: a polish solved by conjugate gradients (above direct_rows) also
  // stops once every |K| it works on is below the flat threshold
  // (kFlatDefect) and their RMS below this (rad): the order its result goes
  // to cannot tell it from a longer polish (polish_plan), and inexact steps
  // do not finish quadratically as factored ones do (those go on to
  // target_defect in a few steps).
  double settled_defect = 0.0;
  // > 0: a polish solved by conjugate gradients also stalls where its stall
  // window of steps did not halve sum K^2 and made at most this share of its
  // rows flat (without, and factored: where they made none flat). Inexact steps can
  // take a vertex or two at a time for as long as they are let.
  double stall_flat_share = 0.0;
  // Only vertices with |K| at or above this move, with their stars (rad); by
  // default a tenth of the flat threshold 1e-3.
  double active_defect = 1e-4;
  double limit = 0.0;  // largest distance from `reference`, caller's units; <= 0: none
  // Rows of the damped system up to which it is factored (sparse Cholesky);
  // above, conjugate gradients (the factor of a larger one fills in).
  int direct_rows = 20000;
  // While some |K| the polish works on is at or above `spread_until` (rad),
  // the Levenberg-Marquardt damping mu stays at least `spread_damping`
  // (relative to the mean diagonal of J J^T): the steps stay nearer the
  // gradient, which spreads the motion over more vertices (the polishes of
  // the input, see run_pipeline). Then, and with the default 0 throughout,
  // mu may fall to Gauss-Newton's, which finishes quadratically.
  double spread_damping = 0.0;
  double spread_until = 1e-3;
  // The crease guard (measures.h) over `reference_normals`: a step may not
  // open the angle between two faces of one group by more than its growth;
  // such faces keep their corners, as those that turn over. Off by default.
  // Copies share its edges (24 MB at 1M faces): a run's polishes hold the
  // one it made (PatchRun::crease_guard).
  CreaseGuard crease_guard;
  // > 0: the polish gives up (PolishResult::gave_up) once a kept step leaves
  // the vertices farther from `reference` than this, RMS over the whole mesh
  // (caller's units): least motion's candidates win only by moving less than
  // the result, and past it they had lost.
  double give_up_move = 0.0;
  // The same bound when it is known only while the polish runs (least
  // motion's polish of the input runs beside the result's polishes, whose
  // move it is): read at every kept step, <= 0 until known, then fixed. The
  // polish then keeps PolishResult::largest_move from its first step, so
  // whether it went past the bound does not depend on when it became known.
  const std::atomic<double>* late_give_up_move = nullptr;
  // > 0: the first `pull_steps` steps are Gauss-Newton steps of the
  // projection onto the developable meshes nearest `reference`: each moves
  // the free vertices toward `reference` as far as the linearised defects
  // allow and takes K to zero to first order,
  //   step = r - J^T (J J^T + mu I)^{-1} (K + J r),  r = reference - x,
  // kept whatever sum K^2 does (a face turned over or creased keeps its
  // corners, as in the other steps, or the step is halved); then the polish
  // goes on as without.
  // From a smoothed start this finds the developable mesh nearest the input
  // in the smooth start's basin, not in the noisy input's, where a vertex
  // whose angle sum hardly depends on its height is pushed out (least
  // motion's projected candidate, docs/method.md "Projected smoothed
  // input"). The give-up bounds and largest_move count from the first step
  // after the pull.
  int pull_steps = 0;
  // Null, or the run's spare cores: the conjugate gradients' products take
  // them while they are spare (conjugate_gradients.h); the result is the
  // same whatever they take.
  SpareCores* spare_cores = nullptr;
};

struct PolishResult {
  Positions positions;           // the polished mesh (== start when no step was kept)
  int iterations = 0;            // steps kept
  double residual_before = 0.0;  // RMS of K over the constrained vertices at the start, rad
  double residual_after = 0.0;   // the same at the end
  bool gave_up = false;          // stopped by a give-up bound; `positions` is where it was
  // With a give-up bound (either): the largest RMS move from `reference` over
  // the whole mesh after any kept step (caller's units); else 0.
  double largest_move = 0.0;
};

// The angle-defect polish.
//   start: positions to polish from; reference: positions the tolerance
//   `options.limit` is measured from (the user's input); reference_normals:
//   unit face normals a face may not turn more than 90 degrees from (the
//   input's; zero rows are not checked); triangles: a validated mesh;
//   constrained: the vertices whose defect is driven to zero (interior ones;
//   others are ignored); pinned: empty or one flag per vertex, pinned
//   vertices never move. The sizes must agree (else
//   EngineError(internal_error)).
// Returns `start` unchanged (iterations = 0) when nothing is constrained,
// nothing is free, or no step could be kept. Throws EngineError(cancelled)
// through `progress`; a factorisation that fails counts as a step not kept.
PolishResult polish_defects(const Positions& start, const Positions& reference, const Normals& reference_normals,
                            const Triangles& triangles, const std::vector<bool>& constrained,
                            const std::vector<bool>& pinned, const PolishOptions& options, const Progress& progress);

}  // namespace developable

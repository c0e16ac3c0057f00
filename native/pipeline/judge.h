// Measures candidate meshes and holds them to the admissibility rule
// (selection.h), keeping the reasons of those it turns away for the
// message of a run that returns its input.
#pragma once

#include "core/measures.h"
#include "core/types.h"
#include "pipeline/selection.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// How good an iterate is, lower is better (rad). On one patch: the paper's
// mean |defect| over the scored vertices. On a segmented mesh (`median`): the
// median |defect| over the vertices inside the patches. The curvature of a
// closed surface cannot go (Gauss-Bonnet fixes its total), only gather on the
// seams, so there the mean hardly moves while the share of flat vertices
// grows; the median follows that share (below 1e-3 rad once half the
// vertices are flat) and, unlike the share, also rewards progress above the
// threshold. 0 when no vertex is scored.
class IterateScore {
 public:
  IterateScore(std::vector<bool> scored, bool median);

  // The vertices the score reads.
  const std::vector<bool>& scored() const { return scored_; }
  double operator()(const Eigen::VectorXd& defects) const;
  // The mean |defect| over the scored vertices (rad; Figures::mean_inside),
  // 0 when none is scored.
  double mean(const Eigen::VectorXd& defects) const;

 private:
  std::vector<bool> scored_;
  bool median_;
  size_t count_ = 0;
  mutable std::vector<double> values_;  // scratch, reused across iterations
};

// Share of the interior vertices whose |defect| is under kFlatDefect, 0..1.
double flat_share(const Eigen::VectorXd& defects, const std::vector<bool>& interior);

// How far `positions` moved from `input`: RMS and largest over the vertices.
Motion motion_of(const Positions& positions, const Positions& input);

// A candidate's angle defects (per vertex, rad, 0 off the interior) and figures.
struct Measured {
  Eigen::VectorXd defects;
  Figures figures;
};

class Judge {
 public:
  // input: the input's defects and figures (score by `score`); connectivity:
  // the faces around each vertex (the rulings); closed: the mesh has no
  // boundary (admit); object: a whole object (is_object), whose rulings the
  // order reads and whose mean |defect| admit holds inside the pieces;
  // crease_guard: the run's (its patches and growth). The references must
  // outlive this.
  Judge(const Triangles& triangles, const std::vector<bool>& interior, const VertexFaces& connectivity,
        const Normals& input_normals, IterateScore score, Measured input, bool closed, bool object,
        CreaseGuard crease_guard);

  // How much of a mesh measure() reads: a candidate's every figure, or a
  // deformation iterate's defects and score only (its fold-safe steps crease
  // nothing by construction, and iterates are chosen by score: the rulings
  // of the one kept are read once, by complete()).
  enum class Detail { candidate, iterate };

  // The defects and figures of `positions` (face normals `normals`): with
  // Detail::candidate also the faces the crease guard finds creased and, on
  // an object, the flat-and-ruled share (the order reads it only there:
  // more_developable).
  Measured measure(const Positions& positions, const Normals& normals, Detail detail = Detail::candidate) const;

  // The figures measure() leaves out for Detail::iterate, filled into
  // `measured` of `positions`.
  void complete(Measured& measured, const Positions& positions, const Normals& normals) const;

  // The flat-and-ruled share of `positions` filled into `measured`, on any
  // surface (measure() and complete() read it on objects only; a sheet's
  // ruled finish reads it too).
  void measure_rulings(Measured& measured, const Positions& positions, const Normals& normals) const;

  // Whether a measured candidate may be returned (admit); the reasons of one
  // that scored better than the input but may not are kept.
  bool admissible(const Measured& candidate);

  const Measured& input() const { return input_; }
  const IterateScore& score() const { return score_; }
  const Rejections& rejected() const { return rejected_; }

 private:
  const Triangles& triangles_;
  const std::vector<bool>& interior_;
  const VertexFaces& connectivity_;
  const Normals& input_normals_;
  IterateScore score_;
  Measured input_;
  bool closed_;
  bool object_;
  CreaseGuard crease_guard_;
  Rejections rejected_;
};

}  // namespace developable

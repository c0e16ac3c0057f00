// Local Gauss-image thinning (beyond the paper; Binninger et al. 2021's
// neighbourhood fit): a target normal per face that pulls the Gauss image of
// a doubly curved region onto curves, so that the surface becomes ruled
// pieces meeting at creases instead of flat-by-zigzag facets.
//
// Each face f takes the faces whose centroids lie within `radius` of its own
// (and, with pieces, in its own piece) and whose normals lie within `cone`
// of its normal; their normals, weighted by exp(-(angle / (2 cone))^2), give
// the great circle that fits them best (the axis u: the eigenvector of the
// smallest eigenvalue of sum w n n^T, as the ruling spread of measures.h).
// f's target is its normal projected onto that circle: n - (n . u) u,
// normalised. A ruled surface's normals lie on one great circle locally, so
// its targets are its normals; a sphere's are pulled apart into bands whose
// borders become creases. Iterated with a shrinking cone (the deformation
// step in between), the neighbourhoods stop reaching across the creases
// that form.
//
// The paper's ideal curve is one global curve per patch; this is a local
// fit per face and needs no patches (docs/method.md, "Thinned pieces").
#pragma once

#include "core/concurrent_jobs.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// The neighbourhoods of every face, found once from the centroids of the
// positions given (the caller's units) and kept while the normals change.
class GaussThinning {
 public:
  // positions, triangles: a validated mesh; radius > 0 (caller's units):
  // faces whose centroids are at most this far apart are neighbours (every
  // face is its own); pieces: empty, or one id per face, and then only faces
  // of one piece are neighbours. Throws EngineError(invalid_argument) for a
  // radius <= 0 or pieces of the wrong size.
  GaussThinning(const Positions& positions, const Triangles& triangles, double radius, const std::vector<int>& pieces);

  // The unit target normal of every face for unit face normals `normals`
  // (one row per face) and a cone half-angle `cone` (rad, > 0): each face's
  // normal projected onto the great circle of its neighbours within the
  // cone. A face whose normal is the circle's axis (no projection defined)
  // keeps its normal. threads: 0 one per core; spare: null, or cores to weigh
  // the pairs on while they are spare (up to two threads, where each pair is
  // weighed once). The result depends on neither.
  Normals targets(const Normals& normals, double cone, int threads = 0, SpareCores* spare = nullptr) const;

  // Neighbours of face f, itself included, ascending.
  const int* begin(Eigen::Index f) const { return neighbours_.data() + offsets_[static_cast<size_t>(f)]; }
  const int* end(Eigen::Index f) const { return neighbours_.data() + offsets_[static_cast<size_t>(f) + 1]; }

 private:
  std::vector<size_t> offsets_;  // face count + 1
  std::vector<int> neighbours_;
};

}  // namespace developable

// Stage 2 of the pipeline: the measures the paper's tables report, and the
// per-face quantities the later stages use.
#pragma once

#include "core/concurrent_jobs.h"
#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <vector>

namespace developable {

// |defect| (rad) under which an interior vertex counts as flat: the one flat
// threshold of the engine, its messages and its reports.
inline constexpr double kFlatDefect = 1e-3;

// Spread (rad) of a vertex's face normals off their best great circle
// (ruling_spreads) under which it counts as ruled: its faces bend about one
// axis, as on a plane, a cylinder, a cone or a tangent developable. A vertex
// flat but not ruled is crumpled: zero angle defect bought with a zigzag of
// facets (Stein, Grinspun, Crane 2018 use the same covariance as their
// energy). devkit/measures.py's ruled_spread measures the same.
inline constexpr double kRuledSpread = 0.02;

// Unit normal of each triangle (right-handed in the triangle's vertex order).
// A zero-area triangle gets the zero vector.
//   spare: null, or cores to share the faces out to while they are spare
//   (concurrent_jobs.h); the same result whatever it takes. So for the
//   other measures that take one.
Normals face_normals(const Positions& positions, const Triangles& triangles, SpareCores* spare = nullptr);

// Centroid of triangle f (the mean of its corners), caller's units.
inline Eigen::Vector3d face_centroid(const Positions& positions, const Triangles& triangles, Eigen::Index f) {
  return (positions.row(triangles(f, 0)) + positions.row(triangles(f, 1)) + positions.row(triangles(f, 2)))
             .transpose() /
         3.0;
}

// Area of each triangle, in the caller's units squared.
Eigen::VectorXd face_areas(const Positions& positions, const Triangles& triangles);

// AE: the mean length over the mesh's undirected edges, caller's units.
double average_edge_length(const Positions& positions, const Triangles& triangles);

// Discrete Gaussian curvature: the angle defect 2*pi - (sum of the corner
// angles at the vertex), in radians, for each interior vertex; 0 for boundary
// vertices and for vertices no triangle uses (`interior` says which is which).
Eigen::VectorXd angle_defects(const Positions& positions, const Triangles& triangles, const std::vector<bool>& interior,
                              SpareCores* spare = nullptr);

// How much vertex v's angle defect answers noise on the vertices: the sum,
// over v and the vertices around it, of the squared length of the gradient
// of K_v with respect to each one's position (rad^2 per unit length^2).
// Independent noise of standard deviation s per coordinate on every vertex
// gives K_v a variance of about s^2 times this, to first order. Where the
// faces around v lie in one plane it is 0 (a flat vertex's defect is of
// second order in the noise); across a fold whose sides meet at dihedral
// angle phi it grows as sin^2(phi / 2) over the edge lengths squared, so
// noise gives the vertices of a curved fold angle defects of first order
// that a crease of real curvature must exceed. The corner angle gradient is
// defect_polish.h's.
//   normals: face_normals of positions; connectivity: vertex_faces of the
//   same triangles; v: any vertex (a boundary vertex's sum is of its corner
//   angles alone). Zero-area faces add nothing.
double angle_defect_noise_gain(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, Eigen::Index v);

struct DefectStats {
  double mean_abs = 0.0;  // E^mean of the paper: mean |defect| over interior vertices, rad
  double max_abs = 0.0;
  Eigen::Index interior_count = 0;
};

// Mean and max of |defect| over the vertices marked interior.
DefectStats defect_stats(const Eigen::VectorXd& defects, const std::vector<bool>& interior);

// Faces turned over: those whose unit normal is more than 90 degrees from
// `reference`'s, or zero (collapsed) where the reference's is not; faces
// whose reference normal is zero are not checked. Ascending face indices.
//   normals, reference: one row per face (face_normals).
std::vector<Eigen::Index> turned_over_faces(const Normals& normals, const Normals& reference,
                                            SpareCores* spare = nullptr);

// The crease guard: a deformation may bend the surface, but not crumple it.
// It watches every edge between two faces of one group (a patch; edges on
// a seam between groups may fold, that is where a piecewise developable
// surface keeps its curvature) and reports the faces of those whose angle
// between the face normals grew by more than `growth` (rad) over the
// reference's. A doubly curved region made flat vertex by vertex crumples
// into such creases (the face and the fingers of human_woman), which no
// figure of the angle defect shows.
//   triangles: a validated mesh; reference: its face normals (zero rows are
//   not watched); groups: one id per face, or empty for one group;
//   growth <= 0: the guard is off and reports nothing.
class CreaseGuard {
 public:
  CreaseGuard() = default;  // off
  CreaseGuard(const Triangles& triangles, const Normals& reference, const std::vector<int>& groups, double growth);

  bool active() const { return edges_ && !edges_->empty(); }

  // The same guard on the submesh of `faces` (ascending ids of this guard's
  // mesh of `mesh_faces` faces; submesh face i is faces[i]): the watched
  // edges between two of them, renumbered. The guard a constructor would
  // build on the submesh itself, without its triangles.
  CreaseGuard restricted(const std::vector<Eigen::Index>& faces, Eigen::Index mesh_faces) const;

  // The faces of the watched edges creased at `normals` (face_normals of
  // the same triangles), ascending and unique.
  std::vector<Eigen::Index> creased_faces(const Normals& normals, SpareCores* spare = nullptr) const;

 private:
  struct Edge {
    int f, g;             // 16 bytes an edge: a guard of a 1M-face mesh holds 1.5M of them
    double limit_cosine;  // cosine of the reference angle plus the growth (edges where that is < pi)
  };
  // Shared by copies: a 1M-face mesh's is 24 MB, and a run's judge,
  // deformation and polishes hold the same one (PatchRun::crease_guard).
  std::shared_ptr<const std::vector<Edge>> edges_;
};

// The faces a step must put back: those turned over against `reference`
// (turned_over_faces) and those `guard` finds creased, ascending and unique.
std::vector<Eigen::Index> folded_faces(const Normals& normals, const Normals& reference, const CreaseGuard& guard,
                                       SpareCores* spare = nullptr);

// Puts the corners of the folded faces of `positions` (folded_faces against
// `reference` normals and `guard`) back where `fallback` has them, ring by
// ring: at most `rounds` rounds, each followed by a fresh look. Returns
// whether no face is left folded. Where `fallback` folds nothing, enough
// rounds always succeed (each puts back at least one more vertex).
bool put_back_folded_corners(Positions& positions, const Positions& fallback, const Triangles& triangles,
                             const Normals& reference, const CreaseGuard& guard, int rounds,
                             SpareCores* spare = nullptr);

// Roughness of the normal field: the mean over the faces of the angle (rad)
// between a face's unit normal and the normalised sum of its own and its
// edge neighbours' normals. Noise raises it; a smooth surface's comes from
// its curvature alone (a 2 % AE noisy cylinder grid: about twice the
// noise-free one's). Zero normals are skipped; 0 for an empty mesh.
//   normals: face_normals; connectivity: vertex_faces of the same triangles.
double normal_roughness(const Normals& normals, const Triangles& triangles, const VertexFaces& connectivity);

// How far the faces around each vertex are from bending about one axis: the
// root-mean-square sine of their unit normals' angles off the great circle
// that fits them best, as an angle (rad): asin(sqrt(lambda_min / W)), where
// lambda_min is the smallest eigenvalue of the sum of w n n^T over the faces
// of the vertex, w each face's angle at the vertex and W their sum (Stein et
// al.'s weights: a fan of thin triangles weighs what one triangle over the
// same angle weighs, so the figure does not depend on how the star is cut).
// 0 where the normals lie on one great circle (plane, cylinder, cone, any
// developable's smooth part), at vertices of fewer than 3 faces and off the
// interior.
//   normals: face_normals of positions; connectivity: vertex_faces of the
//   same triangles; interior: interior_vertices.
Eigen::VectorXd ruling_spreads(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, const std::vector<bool>& interior);

// Whether a vertex of angle defect `defect` (rad) and ruling spread `spread`
// (ruling_spreads) is flat and ruled: developable, not crumpled.
inline bool flat_and_ruled(double defect, double spread) {
  return std::abs(defect) < kFlatDefect && spread < kRuledSpread;
}

// The developability a user sees, as shares (0..1) of the interior vertices:
// flat (|defect| < kFlatDefect), flat and ruled (spread < kRuledSpread too)
// and crumpled (flat, not ruled). All 0 without interior vertices.
struct VertexShares {
  double flat = 0.0, ruled = 0.0, crumpled = 0.0;
};
VertexShares vertex_shares(const Eigen::VectorXd& defects, const Eigen::VectorXd& spreads,
                           const std::vector<bool>& interior);

// Interior vertices: used by some triangle and not on the boundary.
std::vector<bool> interior_vertices(const Positions& positions, const Triangles& triangles);

}  // namespace developable

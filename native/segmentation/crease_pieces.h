// The pieces the crease lines of a noisy mesh part it into, each fitted with
// a cone of normals (a plane, a cylinder or a cone), and how well each fits
// within the mesh's own noise: sheet-metal assemblies (mitred elbows, tees,
// Y-branches, reducers, cups) as their natural pieces.
//
// developable_pieces.h finds such pieces on an exact mesh, where every vertex
// off the seams is flat; under noise every vertex is curved, and the
// segmentation's cone fits (segmentation.h) cut across mitres. Here the
// crease lines (crease_lines.h) part the mesh; the pieces are what falls
// apart, cleaned in four steps:
//   1. pieces under kMinPieceFaces (or 0.5 % of the faces) join the
//      neighbour they share most edges with (slivers between two lines);
//   2. faces along a border move to the neighbouring piece whose cone fits
//      their normal at least twice as well (a line traced one row off);
//   3. neighbours whose union fits one cone (its RMS angle to the cone at
//      most kSameCone times their own, and within the noise) become one
//      piece (a false line across a cylinder);
//   4. step 2 again;
//   5. where there are two pieces or more, a piece that fits no cone
//      (above kCreasePieceFit: a line was missed, two gores of an elbow or a
//      branch and its pipe joined through its gap) is parted by a plane
//      (plane_parting) when both parts fit better, and step 2 runs again.
// Each piece's fit is the RMS angle of its normals to its cone over the RMS
// that the noise alone would give them off the cone (the noise of
// crease_strength.h carried through each face's shape): about 1 or less for
// a plane, cylinder or cone with noise, far above for two cylinders meeting
// at a mitre. The plan (pipeline/plan.h) decides whether the pieces are
// taken.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// Pieces smaller than this many faces (or 0.5 % of the mesh) join a
// neighbour.
inline constexpr int kMinPieceFaces = 10;

// Two neighbouring pieces are one when their union's RMS angle to its cone is
// at most this many times their own (pooled by area) ...
inline constexpr double kSameCone = 1.5;
// ... and their union fits its cone within this many times what the noise
// gives (the fit below). True pieces of seeds 0-19 fit within 1.04; two
// gores of an elbow joined, 1.6 and more.
inline constexpr double kCreasePieceFit = 1.5;

struct CreasePieces {
  std::vector<int> ids;     // per face, 0 .. count-1, numbered in the order of each piece's first face
  int count = 0;            // 0 for an empty mesh
  std::vector<double> fit;  // per piece: RMS angle to its cone over the noise's (dimensionless)
  double noise = 0.0;       // crease_strength.h's, caller's units
  // The vertex noise along the normal (standard deviation, caller's units)
  // that explains how far the faces' normals leave their pieces' cones: on
  // pieces that are planes, cylinders and cones the noise's own, where the
  // noise above also holds what the facets make of the fits (at 0.5-1 % noise
  // 2-5 times the noise).
  double cone_noise = 0.0;
  std::vector<bool> cut;  // per mesh_edges edge: on a crease line
};

// A piece is parted by step 5 at most this many times (a six-gore elbow
// whose every mitre line was missed: five).
inline constexpr int kMostPartings = 8;

// Step 5's parting of one piece: the plane that leaves the two sets of faces
// fitting two cones best (the least summed residual of fit_cone, cone_fit.h).
// Mitres, branch seams and reducer rings are plane curves (crease_lines.h,
// step 5), so one plane parts two such pieces; the faces along it are then
// settled by their cones (step 2). Planes are tried across 128 directions
// spread over a hemisphere, each at 64 evenly spaced offsets of the face
// centroids' extent along it, then across 81 directions within the
// lattice's spacing of the best, at 256 offsets; cones come from additive
// moments, so a direction costs one pass over the faces.
//   faces: the piece's face indices into `triangles`; positions, triangles,
//   normals, areas: the mesh, its face_normals and face_areas; min_faces:
//   the least number of faces on either side (>= 1).
// Returns per entry of `faces` whether it lies beyond the plane; empty when
// no plane leaves both sides min_faces faces. Deterministic.
std::vector<bool> plane_parting(const std::vector<int>& faces, const Positions& positions, const Triangles& triangles,
                                const Normals& normals, const Eigen::VectorXd& areas, int min_faces);

// The crease pieces of a mesh.
//   positions, triangles: a mesh that passed validate_mesh; normals, areas:
//   its face_normals and face_areas; connectivity: its vertex_faces;
//   threads: as parallel_for's (the result does not depend on it).
// No failure mode: a mesh without crease lines is one piece. Deterministic.
// O(faces x 2-ring) for the lines, O(faces x pieces^2) for the merges,
// O(faces x 209) per parting.
CreasePieces crease_pieces(const Positions& positions, const Triangles& triangles, const Normals& normals,
                           const Eigen::VectorXd& areas, const VertexFaces& connectivity, int threads = 0);

}  // namespace developable

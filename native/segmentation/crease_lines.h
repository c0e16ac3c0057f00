// The crease lines of a mesh: the edges along which its surface creases,
// chained into lines that part it (crease_pieces.h cuts the mesh along them).
//
// From the crease strengths (crease_strength.h), in six steps:
//   1. Candidates: edges whose score stands out against the noise
//      (kLineScore) and whose dihedral angle stands out against the facets
//      beside them (kRidgeRatio): a cylinder's rulings are creases of the
//      facet angle, and so are the tangent seams of a square-to-round
//      transition; a crease is sharper than the facets around it.
//   2. One edge across (non-maximum suppression): of two parallel candidates
//      side by side, the weaker goes.
//   3. Chains: loops around one or two faces are opened at their weakest edge
//      (what is left of a line two edges wide); spurs (short branches off a
//      line or the boundary) are dropped.
//   4. Lines grown on (hysteresis, as Canny's edges): from each loose end,
//      the weak candidate that goes on most nearly straight (steps 1 and 2
//      with kWeakLineScore and kWeakRidgeRatio), and does not run into the
//      middle of another line, joins, until none does. Under
//      noise of 3-5 % of the edge length a mitre's edges score 2-5 and the
//      strong candidates are stretches a few edges long; grown, they meet.
//      Then chains whose evidence (the sum of their scores above kLineScore)
//      or extent is too small to be a line rather than noise are dropped; a
//      closed ring of kRingEdges or more without a junction is a line
//      whatever its extent (a thin branch's seam).
//   5. Gaps bridged: a line ends inside the mesh where its crease fades
//      below the noise (a mitre at the sides of the pipe, where the two
//      cylinders are tangent). Each such end is traced on, over mesh edges,
//      along the plane of its branch (mitres, reducer and cup rings are plane
//      curves; a straight branch continues along its normal section) until
//      it meets another line or the boundary, shortest bridge first.
//   6. Spurs dropped again.
// The constants were tuned on seeds 0-19 of devkit/assemblies.py (every part,
// triangulation and noise 0.5-5 %), the weak candidates' and the rings' on
// seeds 0-19 and 200-239, and are held to seeds 100-119 by
// tests/test_assemblies_engine.py; docs/method.md ("Crease pieces") has the
// figures.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"
#include "segmentation/crease_strength.h"

#include <vector>

namespace developable {

// Score (crease_strength.h: jump over its standard deviation) above which
// an edge may be on a crease line. A two-dimensional Gaussian's norm exceeds
// 3 once in 90 edges; the lines' evidence and extent sort out the rest.
inline constexpr double kLineScore = 3.0;

// A candidate's dihedral angle must be at least this many times that of the
// parallel edges beside it (per side the median, the larger side). Measured
// on the candidates of seeds 0-12 after step 3: true crease edges 3.4 (5th
// percentile), other edges 0.97 (median), 2.8 (90th percentile).
inline constexpr double kRidgeRatio = 2.5;

// Weak candidates (step 4): a score above this and a dihedral angle this many
// times the facets'. Measured on seeds 0-19 and 200-239, the share of parts
// in their natural pieces is flat from 1 to 2 (score) and 0.7 to 0.8 (the
// cosine of the turn, kept at the parallels' 0.7), and falls below 1.5
// (ridge: 1.2 lets noise edges grow lines across the pieces).
inline constexpr double kWeakLineScore = 1.5;
inline constexpr double kWeakRidgeRatio = 1.5;

// A closed ring of cut edges, every vertex on two, is a line from this many
// edges on: a branch pipe of eight facets around meets its main pipe along a
// ring 3.6 edges across, under kLineExtent; the apex fans are webs.
inline constexpr int kRingEdges = 6;

// Branches of fewer edges than this hanging off a junction or the boundary
// are spurs (noise edges touching a line).
inline constexpr int kSpurEdges = 2;

// A chain must carry at least this much evidence: the sum over its edges of
// their scores less kLineScore. Of the true chains of seeds 0-19, those with
// less hold 3 % of the true crease edges; of the others (noise, the fans at
// the transitions' apexes) 22 of 2962 have more.
inline constexpr double kLineEvidence = 15.0;

// ... and span at least this many of its median edge lengths (the diagonal of
// its bounding box): the apex fans of transitions are webs of strong edges
// 1.3-3.3 edges across; true crease chains span 4.5 and more (5th percentile).
inline constexpr double kLineExtent = 4.0;

// A branch is traced along the plane of its vertices when their spread off
// that plane is under this share of their spread along the branch's second
// direction (square roots of the covariance's smallest and middle
// eigenvalues); straighter branches follow their normal section.
inline constexpr double kPlanarBranch = 0.3;

// A trace gives up after this many times its branch's length.
inline constexpr double kBridgeReach = 3.0;

// The crease lines: one flag per edge (mesh_edges order), true where the
// mesh is cut. Boundary edges are never cut.
//   positions, triangles: a mesh that passed validate_mesh; normals: its
//   face_normals; connectivity: its vertex_faces; edges: its mesh_edges;
//   strengths: crease_strengths of the same.
// No failure mode; a mesh without creases gets no cut. Deterministic.
std::vector<bool> crease_lines(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, const std::vector<MeshEdge>& edges,
                               const CreaseStrengths& strengths);

}  // namespace developable

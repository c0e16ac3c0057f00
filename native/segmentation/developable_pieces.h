// Developable pieces as the mesh stands: where the curvature already sits on
// cuts that part the mesh into pieces flat inside.
//
// A lobster-back pipe elbow (straight cylinder pieces joined by mitres, the
// sheet-metal classic) is developable piecewise: its angle defect sits on
// the mitre rings, every other vertex is flat. Segmentation by cone fits
// (segmentation.h) does not find its pieces: at the sides of a mitre the two
// cylinders are tangent, so strips of both fit one cone. The curvature itself
// shows the pieces: cut the mesh along the edges between curved vertices and
// what falls apart is the pieces.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace developable {

// The pieces of a mesh cut along its curvature, when they are developable.
//   triangles: a validated manifold mesh; connectivity: its vertex_faces;
//   interior: one flag per vertex (not on the boundary); defects: the angle
//   defect of every vertex (rad; read at interior vertices only);
//   flat_defect: |defect| under which a vertex counts as flat (rad).
// A vertex is curved when it is interior and not flat. An edge is cut when
// both its ends are curved, or one is curved and the other on the boundary
// (so that a cut may end there). The pieces are the faces connected across
// edges that are not cut.
// Returns one piece id per face, 0 .. count-1 numbered in the order of each
// piece's first face, when there is a curved vertex and
//   - every curved vertex lies on a cut: its faces belong to at least two
//     pieces (no curvature is left inside a piece), and
//   - every piece has an inside vertex: interior, flat, with all its faces in
//     that piece (so a noisy mesh, whose every vertex is curved and whose
//     every edge is cut, does not pass as pieces of one triangle each).
// Else nothing. O(faces) time and memory; no failure mode beyond the
// preconditions.
std::optional<std::vector<int>> developable_pieces(const Triangles& triangles, const VertexFaces& connectivity,
                                                   const std::vector<bool>& interior, const Eigen::VectorXd& defects,
                                                   double flat_defect);

}  // namespace developable

// Stage 1 of the pipeline: checking the caller's mesh before anything uses it.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <vector>

namespace developable {

// Validates a triangle mesh. Checks run in this order and the first failure is
// thrown as EngineError with its own status and a message naming the element:
//   empty_input            no vertex or no triangle;
//   index_out_of_range     a triangle index < 0 or >= #vertices;
//   non_finite_coordinate  a NaN or infinite coordinate;
//   degenerate_triangle    a vertex repeated in a triangle, or zero area
//                          (area <= 1e-14 * bbox diagonal^2);
//   duplicate_triangle     two triangles on the same three vertices;
//   non_manifold           an edge shared by more than two triangles (named
//                          as "edge (a, b)", a < b, the first in that order),
//                          or a vertex whose triangles form more than one fan.
// Vertices that no triangle uses are allowed (they are never moved). So is
// either winding of every triangle: neighbours that run their shared edge the
// same way are no error, whether turning faces over can make them all agree
// (an inconsistently wound mesh) or not (a one-sided surface, a Möbius
// strip); orient_faces (orientation.h) tells the two apart and turns the
// faces, and the C ABI runs the engine on the turned faces.
// Returns the faces around each vertex, which the checks build anyway and
// the later stages share (mesh_connectivity.h).
VertexFaces validate_mesh(const Positions& positions, const Triangles& triangles);

// How many vertices sit at exactly the same position as another vertex. A
// mesh whose triangles each have their own three vertices (a polygon soup:
// STL, some OBJ exports) has many, and no interior vertex; the pipeline
// names them when it refuses such a mesh. O(n log n).
Eigen::Index coincident_vertices(const Positions& positions);

// The vertices on the mesh boundary (on an edge with one triangle), as a mask.
// Requires a mesh that passed validate_mesh.
std::vector<bool> boundary_vertices(const Positions& positions, const Triangles& triangles);

}  // namespace developable

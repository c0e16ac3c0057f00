// Pieces where the normals jump: the patches a thinned Gauss image parts a
// mesh into (ideal_curve/gauss_thinning.h pulls a doubly curved surface into
// ruled bands meeting at creases; those creases are the seams).
//
// Two faces across an edge are in one piece when the angle between their
// normals is at most `crease` (rad); the pieces are what falls apart.
// Pieces smaller than `min_faces` faces are merged, smallest first (ties:
// the lower id), into the neighbouring piece they share the smoothest
// border with (lowest mean normal jump along it; ties: the lower id), until
// none is small or a small one has no neighbour it may join (a small
// component of its own). With reference normals, a border may be merged
// across only if none of its edges is wider than its reference angle plus
// `growth` (the crease guard of measures.h: a piece holds no edge the guard
// would call creased), unless the small piece has no vertex of its own
// (every corner also a corner of another piece's face): such a piece is no
// surface to make developable, only faces a thinning turned (human_woman's
// single-face pieces), and joins its smoothest neighbour whatever the border;
// the caller puts the creased faces back (thinned_pieces.h).
//
// Unlike segmentation.h, nothing here fits a cone: a piece is whatever the
// creases enclose. On a mesh before thinning this gives one piece per smooth
// region; after thinning, one per ruled band (docs/segmentation.md,
// "Pieces from the thinned Gauss image").
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// The pieces of `triangles` (a validated manifold mesh with its
// vertex_faces `connectivity`) parted where the unit face `normals` (one row
// per face) jump by more than `crease` rad (>= 0), small pieces merged
// (min_faces >= 1; 1 merges nothing); `reference`: empty (0 rows) or unit
// normals per face (the input's) that merges are held to with `growth` (rad).
// Returns one piece id per face, 0 .. count-1, numbered by each piece's
// lowest face; every piece is edge-connected. Deterministic. Throws
// EngineError(invalid_argument) for a negative crease, min_faces < 1 or
// sizes that disagree.
std::vector<int> normal_jump_pieces(const Triangles& triangles, const VertexFaces& connectivity, const Normals& normals,
                                    double crease, int min_faces, const Normals& reference = Normals(),
                                    double growth = 0.0);

}  // namespace developable

// Flat patterns, inside unfold (unfold.h): the seams as chains of mesh edges,
// and the curves the pieces' outlines are drawn along.
#pragma once

#include "core/types.h"
#include "pattern/unfold.h"
#include "pattern/unfold_mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace developable::unfolding {

// The seams of an unfolding whose pieces (piece_of_face, corners) are set:
// mesh edges with a different piece on each side, or cut inside one piece
// (their keys in `cut_keys`, sorted), grouped by the pair of pieces and
// chained; a chain ends where the seam does not go on uniquely. Side a: the
// faces left of the directed edges. Lengths in model units.
std::vector<UnfoldSeam> seam_chains(const Positions& positions, const Triangles& triangles,
                                    const std::vector<int>& patch_ids, const EdgeTable& mesh_edges,
                                    const std::vector<uint64_t>& cut_keys, const UnfoldResult& result);

// Which points of a seam polyline (its turns, signed, rad, at its points
// 0 .. n-1; an open chain's ends fixed) lie on a zigzag of triangle edges:
// a turn of more than `min_turn` next to one of the opposite sense, and the
// points between two such turns at most `max_gap` points apart. A smooth
// curve (turns of one sense) and a single corner are not zigzags.
std::vector<char> zigzag_points(const std::vector<double>& turns, bool closed, double min_turn = 0.26, int max_gap = 3);

// `rounds` Jacobi rounds of (p[i-1] + 2 p[i] + p[i+1]) / 4 on the points
// with movable[i], the others fixed (a closed polyline wraps around). A
// linear map of the points: applied to two near-isometric images of one
// polyline it gives the images of one curve.
void smooth_polyline(std::vector<Eigen::Vector2d>& points, const std::vector<char>& movable, bool closed,
                     int rounds = 4);

// Sets every piece's outline_curve: its outline corners, except that along
// a seam whose chain is a zigzag of triangle edges (zigzag_points, turns
// measured on side a's flat map) both sides follow the same smoothed curve
// (smooth_polyline with the same points moved on each). A piece whose
// smoothed outline would cross itself keeps its corners, and so do the
// other sides of its seams.
void smooth_outlines(const Triangles& triangles, const std::vector<UnfoldSeam>& seams, UnfoldResult& result);

}  // namespace developable::unfolding

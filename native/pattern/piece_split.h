// Flat patterns, inside unfold (unfold.h): where a piece that cannot lie flat
// whole is cut in two.
#pragma once

#include "core/types.h"
#include "pattern/unfold_mesh.h"

#include <array>
#include <vector>

namespace developable::unfolding {

// The vertex a chord runs through.
enum class SplitThrough {
  largest_defect,  // not flat, of largest |angle defect| x distance from the border; if all are flat, the middle
  middle,          // halfway along the piece's longest shortest path
};

// The two sides of a chord: a short cut along the piece's edges from its
// border through one vertex back to its border. The piece is first opened
// into a disc (choose_cuts, Holes::join); from the chosen vertex the chord
// follows the shortest edge path to the nearest border vertex b1, and the
// shortest one, leaving the vertex by another edge, to the border vertex b2
// of least chord length per length of border between b1 and b2 (the
// shorter way round): a ratio cut, so that it cuts across rather than off a
// sliver. It never runs inside a face group. Returns the faces (global ids)
// of the two sides, each connected, or two empty lists when the piece has
// no such chord (no inner vertex off a group, or not a surface).
std::array<std::vector<int>, 2> split_along_chord(const Positions& positions, const LocalPiece& piece,
                                                  SplitThrough through);

// The former split, for pieces without a chord: two halves across the
// principal axis of the face centroids, a group's faces on one side (they
// take the group's mean place) unless the piece is one group. The halves may
// fall apart into several connected parts.
std::array<std::vector<int>, 2> split_across_axis(const Positions& positions, const Triangles& triangles,
                                                  const std::vector<int>& faces, const std::vector<int>& face_groups);

}  // namespace developable::unfolding

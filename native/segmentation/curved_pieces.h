// Pieces still curved inside, split in two (beyond the paper; issue 35).
//
// The thinned-pieces generator (pipeline/thinned_pieces.h) cuts an object
// where its thinned Gauss image parts; a piece whose inside stays doubly
// curved after the ruled polish (a rounded box's corner, the belly of a blob)
// cannot be made flat and ruled within the move limit, and the pattern then
// shatters it. Measured by rings from the nearest seam, such a piece fails
// in its interior, not along its seams (docs/segmentation.md, "Pieces still
// curved inside"): the cut is what is missing, not more polish. So a piece
// with too few flat and ruled vertices inside is parted in two where its
// normals fit two cones best (the segmentation's own criterion, run on that
// piece's faces alone), and the caller thins and polishes the new pieces.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <vector>

namespace developable {

// Which pieces to split: those with at least `min_inside` inside vertices
// (interior, off every seam) of which fewer than `share` (0..1) are
// developable (flat and ruled, measures.h).
//   pieces: a piece id per face, 0 .. count-1; connectivity: vertex_faces of
//   the same triangles; inside, developable: one flag per vertex (a vertex
//   inside a piece has every face in it).
// Returns one flag per piece.
std::vector<bool> curved_pieces(const std::vector<int>& pieces, int count, const VertexFaces& connectivity,
                                const std::vector<bool>& inside, const std::vector<bool>& developable, double share,
                                int min_inside);

// `pieces` (0 .. count-1 per face) with every piece flagged in `split` parted
// in two by the segmentation (segmentation.h, two patches wanted) of its
// faces at `positions`: the part holding the piece's lowest face keeps its
// id, the other is numbered from `count` on, in the order of the pieces. A
// piece the segmentation leaves whole (too small to part) stays as it is.
// Each part is edge-connected. Deterministic. Throws EngineError(cancelled)
// through `progress`.
std::vector<int> split_in_two(const Positions& positions, const Triangles& triangles, const std::vector<int>& pieces,
                              int count, const std::vector<bool>& split, const Progress& progress);

}  // namespace developable

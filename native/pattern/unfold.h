// Flat patterns, step 1 of 3 (unfold -> pattern_layout -> pattern_svg): every
// patch of the mesh laid flat, keeping edge lengths as well as the patch allows.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace developable {

// Flat position of every face corner: row 3 f + k is corner k of face f.
using FlatCorners = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct UnfoldOptions {
  // Local/global as-rigid-as-possible rounds after the conformal start; a
  // round costs one back-substitution. Stops earlier when the energy changes
  // by less than arap_tolerance (relative) between rounds.
  int arap_iterations = 50;
  double arap_tolerance = 1e-6;
  // Strain (|l_flat / l_3d - 1|) a piece's flat map may keep: a piece that is
  // not developable (some inner vertex with |angle defect| >= kFlatDefect,
  // core/measures.h) is split while an edge strains beyond it, so that the
  // two sides of every seam keep their lengths within twice this; a
  // developable piece is kept whole while no edge strains beyond the larger
  // of this and its inner vertices' sum of |defect| / (2 pi) (flatten.h,
  // strain_limit). 0: no limit (a piece is split only when its flat map
  // overlaps itself).
  double seam_tolerance = 0.0025;
};

// One flat piece: a disc cut from one patch.
struct UnfoldPiece {
  int patch = 0;  // the patch the faces came from
  Eigen::Index faces = 0;
  int cut_edges = 0;         // edges cut inside the piece to make it a disc
  int splits = 0;            // how often its patch was split to get here
  double max_strain = 0.0;   // largest |l_flat / l_3d - 1| over the piece's face edges
  double mean_strain = 0.0;  // mean of the same over the 3 edges of every face
  double area_3d = 0.0;      // model units squared
  double area_flat = 0.0;
  double area_change = 0.0;     // area_flat / area_3d - 1
  double outline_length = 0.0;  // length of the flat outline, model units
  int arap_iterations = 0;      // rounds the refinement ran
  // The outline: closed loops of corner rows (3 f + k) in order, the piece on
  // the left; the outer loop first, then one per hole (a piece is a disc
  // with holes: the holes of a piece that lies flat with them are kept).
  std::vector<std::vector<Eigen::Index>> outline;
  // The outline as drawn, model units in the piece's frame, one point per
  // outline corner: the corners, except along a seam whose edges zigzag,
  // where both of its sides follow the same smoothed curve.
  std::vector<std::vector<Eigen::Vector2d>> outline_curve;
};

// A seam: a chain of mesh edges along which the pattern is cut, either a
// border between two pieces or a cut inside one piece (piece_a == piece_b).
// The edges run in chain order; side a is the face left of each directed edge.
struct UnfoldSeam {
  int piece_a = 0, piece_b = 0;
  bool cut = false;                       // true: both sides belong to the same patch (a cut or a split)
  std::vector<std::array<int, 2>> edges;  // (from, to) vertex ids of the mesh
  std::vector<std::array<int, 2>> faces;  // (face on side a, face on side b) per edge
  double length_3d = 0.0;
  double length_a = 0.0;  // flat length on piece a, model units
  double length_b = 0.0;
};

struct UnfoldResult {
  FlatCorners corners;             // #faces * 3 rows, model units, each piece in its own frame
  std::vector<int> piece_of_face;  // 0 .. pieces-1
  Eigen::VectorXd face_strain;     // per face: largest |l_flat / l_3d - 1| of its edges
  std::vector<UnfoldPiece> pieces;
  std::vector<UnfoldSeam> seams;
  int split_count = 0;  // pieces split because no flat map of theirs kept the rule
};

// Unfolds every patch.
//   positions, triangles: a mesh that passed validate_mesh (mesh_input.h),
//     model units.
//   patch_ids: per face, >= 0 (any ids; faces of one id that are not joined
//     by edges become separate pieces); empty = one patch.
//   face_groups: empty, or per face a group id (e.g. the polygon a triangle
//     was cut from): faces of one group are never cut apart, nor split apart
//     unless the group alone cannot lie flat.
// Each piece is a connected set of faces of one patch, laid flat
// (flatten.h): a piece with holes is laid flat with them when that map does
// not overlap itself, else cut into a disc along short interior edge paths
// (every further boundary loop joined to the first, a closed piece opened
// along its longest shortest path, handles cut along the short edges a
// maximum spanning tree of the dual graph leaves). The map: triangles laid
// down breadth first from a central face by their edge lengths (exact on a
// developable disc), refined by as-rigid-as-possible rounds (the cotangent
// Laplacian factored once), from least-squares conformal maps when that
// start is far from isometric on a piece that is not developable or when it
// leads nowhere valid. A flat map is kept when no triangle is turned, the
// angles around every inner vertex sum to 2 pi, no two outline edges cross
// and its strain keeps the rule of UnfoldOptions::seam_tolerance: so a
// developable piece (every inner vertex flat) is one piece unless its flat
// map overlaps itself. A piece that fails is split in two along a chord
// (piece_split.h): the shortest edge path from its border through its inner
// vertex of largest |defect| (if not flat; else through its middle) back
// to its border, and each side is unfolded again, down to single triangles,
// which always lie flat. Exact developables therefore come back isometric
// up to rounding.
// Progress: the share of the faces laid flat (within a large piece, between
// refinement rounds and every 2^17 faces of the linear passes).
// Throws EngineError(invalid_argument) for a patch_ids or face_groups of the wrong size or a
// negative id, numerical_failure if a factorisation fails on every split,
// cancelled when `progress` says stop.
UnfoldResult unfold(const Positions& positions, const Triangles& triangles, const std::vector<int>& patch_ids,
                    const UnfoldOptions& options = {}, const std::vector<int>& face_groups = {},
                    const Progress& progress = {});

}  // namespace developable

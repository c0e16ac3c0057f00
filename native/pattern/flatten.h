// Flat patterns, inside unfold (unfold.h): one piece laid flat, and the rule
// that says whether its flat map is kept or the piece is split.
#pragma once

#include "core/types.h"
#include "pattern/unfold.h"
#include "pattern/unfold_mesh.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace developable::unfolding {

// The angle defects (2 pi minus the 3D angles around the vertex, rad) of the
// vertices strictly inside a piece as it is given (uncut): its vertices on
// the piece's border are free to open and carry no constraint.
struct PieceDefects {
  std::vector<double> of_vertex;  // per vertex of the uncut piece; 0 on its border
  double largest = 0.0;           // max |defect| inside
  double sum = 0.0;               // sum of |defect| inside
  double curved_sum = 0.0;        // the same over the vertices that are not flat
  int largest_vertex = -1;        // where the largest is, -1 without inner vertices
  // Every inner vertex flat (|defect| < kFlatDefect, core/measures.h): the
  // piece is developable by the engine's own measure.
  bool flat() const;
};

PieceDefects piece_defects(const Positions& positions, const LocalPiece& piece, const PieceTopology& uncut);

// The largest strain (|l_flat / l_3d - 1| of any edge) a piece's flat map
// may keep, the rule of unfold.h: with seam_tolerance 0 no limit; a flat
// piece (every inner |defect| < kFlatDefect) max(seam_tolerance, sum |defect|
// / (2 pi)), the strain that gathering all its curvature into one cone
// vertex would need (a cone of defect d is laid flat by stretching its
// circles by d / (2 pi - d), its rulings kept); so too a piece whose
// vertices that are not flat need no more than the tolerance together
// (curved_sum / (2 pi) <= seam_tolerance: one vertex at 3e-3 rad left by
// the engine costs 5e-4); any other piece seam_tolerance, so that the two
// sides of a seam match within twice it.
double strain_limit(double seam_tolerance, const PieceDefects& defects);

// One piece laid flat.
struct FlatPiece {
  std::vector<Eigen::Vector2d> corner_uv;  // per local corner (3 f + k), model units
  std::vector<std::vector<int>> outline;   // loops of local face-edges, the outer one first
  std::vector<uint64_t> cut_keys;          // mesh edges cut inside the piece
  int arap_iterations = 0;
};

// Lays a piece flat: with its holes kept when it has any (a disc with holes
// needs no slit when its flat map does not overlap), else (or when that map
// fails) cut into a disc (choose_cuts). The map: triangles laid down breadth
// first from a central face by their edge lengths (exact on a developable
// disc), else least-squares conformal maps with two far outline vertices
// pinned, scaled to the 3D area, refined by as-rigid-as-possible rounds
// (the cotangent Laplacian factored once); on a piece held to more than the
// tolerance (nearly developable) the breadth-first map is the refinement's
// first start whatever its strain. A piece none of whose maps keeps the
// limit, and whose vertices that are not flat are at most 8 cones, gets a
// dart to each (a slit along the shortest edge path to the border, which
// opens there) and is tried once more, held then to the limit of its flat
// inner vertices. A map is kept when
// every flat triangle is positive, the angles around every inner vertex sum
// to 2 pi (at most 2 pi on the outline), no two outline edges cross, and
// no edge strains beyond `strain_limit`. Returns false when none is: the piece must
// be split. Reports `progress` between refinement rounds.
bool flatten_piece(const Positions& positions, const LocalPiece& piece, const UnfoldOptions& options,
                   const Progress& progress, FlatPiece* out);

// Whether two outline segments (vertex index pairs into uv) cross properly;
// segments sharing a vertex do not count. Uniform grid: about linear in the
// segments when they have similar lengths.
bool outline_is_simple(const std::vector<Eigen::Vector2d>& uv, const std::vector<std::array<int, 2>>& segments);

}  // namespace developable::unfolding

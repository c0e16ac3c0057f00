// Which way round each triangle runs: the faces turned so that neighbours
// agree, as far as the surface allows. Done at the C ABI, before the engine
// sees the mesh, and undone on what it hands back.
//
// Two faces agree on the edge they share when they run it in opposite
// directions; their normals then point to the same side of the surface. The
// engine's stages compare neighbouring normals (the crease guard, the
// segmentation's dihedral angles, target smoothing) and the unfolding lays
// every face down counter-clockwise, so they need agreeing neighbours. A
// caller's mesh need not have them: an import or a Blender mesh may wind
// some faces the other way (orientable, merely inconsistent), and a one-sided
// surface (a Möbius strip) has no consistent winding at all: going once
// round the strip brings a face back turned over (non-orientable). Neither is
// an error. orient_faces turns faces over so that every edge agrees on an
// orientable component, and on a non-orientable one every edge but those of a
// short cut: a path of edges across the surface (one across a strip), along
// which the two sides' normals point to opposite sides. The engine runs on
// the turned faces; every per-face output is handed back in the caller's
// winding (to_caller_normals, to_caller_corners).
#pragma once

#include "core/types.h"

#include <array>
#include <string>
#include <vector>

namespace developable {

enum class Orientability {
  consistent = 0,      // every edge of two faces agrees as given
  inconsistent = 1,    // orientable: turning some faces over makes every edge agree
  non_orientable = 2,  // one-sided: some component agrees everywhere but along a cut
};

struct FaceOrientation {
  // The faces as the engine runs them: a turned face (a, b, c) is (a, c, b)
  // (its corner 0 stays, corners 1 and 2 swap).
  Triangles triangles;
  std::vector<bool> turned;  // per face: turned over against the caller's winding
  Eigen::Index turned_count = 0;
  // The cut of the non-orientable components: edges (from, to) of two faces
  // that both run them from -> to, ascending by (from, to). Empty on an
  // orientable mesh.
  std::vector<std::array<int, 2>> cut;
  std::vector<std::array<int, 2>> cut_faces;  // per cut edge: its two faces, ascending
  double cut_length = 0.0;                    // caller's units
  int non_orientable_components = 0;
  Orientability orientability = Orientability::consistent;
};

// Turns faces over so that neighbours agree (see above). Per component
// (faces joined across edges of exactly two faces):
//  - orientable: every edge agrees, and of the two windings that do, the one
//    that turns fewer faces (on a tie, the one that keeps the component's
//    first face); a consistently wound component comes back untouched, and a
//    component with fewer than half its faces wound the other way comes back
//    exactly as its consistently wound twin;
//  - non-orientable: the faces are turned along a shortest-path tree of the
//    dual graph (face centroids, from the component's first face), so that
//    the edges that disagree are where the paths going round the surface one
//    way meet those going the other way: across a strip, opposite the first
//    face. The cut is then shortened by turning single faces while that
//    makes it shorter (a face two of whose edges are on the cut always does:
//    the triangle inequality). On a component with a rim it is replaced by
//    the shortest path of edges of two faces from the rim back to it that
//    crosses that tree's loop through the cut an odd number of times (a loop
//    going once round against the orientation), when that path is a cut
//    (checked: with a hole it may not be) and shorter: across a strip, the
//    shortest way across. The component gets the winding of the two with
//    this cut that turns fewer faces, as above.
//   positions, triangles: any mesh. Edges of more than two faces join no
//   faces; a mesh with an index out of range or a non-finite coordinate (which
//   validate_mesh refuses) comes back as given. O(faces) for a consistent
//   mesh, O(faces log faces) otherwise. Throws nothing but std::bad_alloc.
FaceOrientation orient_faces(const Positions& positions, const Triangles& triangles);

// What the turning did, in words for a user: "" when nothing was turned;
// else how many faces were turned, or that the surface is one-sided and
// where it is cut (edges and length). At most 243 bytes for fewer than 2^31
// faces (the C ABI's limit), which dev_stats.orientation_note[256] relies on.
std::string orientation_note(const FaceOrientation& orientation);

// Per-face vectors (target normals) the engine computed on `turned`'s
// faces, in the caller's winding: the rows of turned faces negated.
void to_caller_normals(Normals& normals, const std::vector<bool>& turned);

// Per-corner rows (row 3 f + k: corner k of face f as the engine ran it, e.g.
// the unfolding's flat corners) in the caller's corner order: rows 3 f + 1
// and 3 f + 2 of turned faces swapped. A turned face's flat corners then run
// clockwise in the caller's order (the pattern shows the side the engine's
// normals point to).
template <typename Matrix>
Matrix to_caller_corners(const Matrix& rows, const std::vector<bool>& turned) {
  Matrix out = rows;
  for (size_t f = 0; f < turned.size(); ++f)
    if (turned[f]) {
      const auto r = static_cast<Eigen::Index>(3 * f);
      out.row(r + 1) = rows.row(r + 2);
      out.row(r + 2) = rows.row(r + 1);
    }
  return out;
}

// The mesh opened along the cut: every vertex on the cut gets one copy per
// fan of its faces that the cut parts (two for a vertex inside the cut), so
// that the cut's edges become boundary edges and every edge agrees: an
// orientable mesh, for the stages that need one (the unfolding).
struct OpenedMesh {
  Positions positions;        // the caller's, then the copies
  Triangles triangles;        // orientation.triangles with the copies on one side of the cut
  std::vector<int> original;  // per vertex: the caller's vertex it is (itself for the caller's)
};

// orientation: from orient_faces(positions, ...). The copies are numbered
// after the caller's vertices in the order of the faces that first use them;
// the fan holding a vertex's first corner keeps the vertex. Without a cut,
// the mesh as orientation runs it.
OpenedMesh open_along_cut(const Positions& positions, const FaceOrientation& orientation);

// One chain of the cut: edges (from, to) in order, each run from -> to by
// both its faces (the chain's direction: consecutive edges share a vertex),
// and per edge its faces (side a, side b), side a's on one side of the chain
// all along it where the surface allows.
struct CutChain {
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 2>> faces;
  double length = 0.0;  // caller's units
};

// The cut in chains: each ends where the cut forks or ends (a vertex on
// other than two cut edges); chains from such vertices in ascending order,
// then closed loops, each from the first vertex of its first cut edge. opened: open_along_cut of the
// same mesh, to tell the sides apart.
std::vector<CutChain> cut_chains(const Positions& positions, const FaceOrientation& orientation,
                                 const OpenedMesh& opened);

}  // namespace developable

// Flat patterns, inside unfold (unfold.h): the connectivity of one piece (its
// edges, its vertices as classes of face corners, its boundary loops), the
// shortest paths along its edges, and the cuts that open it for flattening.
#pragma once

#include "core/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace developable::unfolding {

// The undirected key of the edge (a, b): lower id in the high half.
uint64_t edge_key(int a, int b);

// The undirected edges of a set of faces. Edge k of a face runs from its
// corner k to corner k + 1; `uses` of an edge holds the face-edge uses
// (3 f + k, f local), at most two on a manifold mesh.
struct EdgeTable {
  std::vector<uint64_t> keys;
  std::vector<std::array<int, 2>> uses;  // -1 when the edge has one face
  std::vector<int> of_face_edge;         // per 3 f + k: edge id
};

// O(#faces log #faces).
EdgeTable edge_table(const std::vector<std::array<int, 3>>& tris);

// One piece being unfolded: its faces (global ids) and local triangles.
struct LocalPiece {
  std::vector<int> faces;
  std::vector<std::array<int, 3>> tris;  // vertex ids of the mesh
  std::vector<int> groups;               // per face: its group, -1 for none
  // An edge inside a group (both faces in one polygon) is never cut.
  bool inner(const std::array<int, 2>& uses) const {
    return uses[1] >= 0 && groups[uses[0] / 3] >= 0 && groups[uses[0] / 3] == groups[uses[1] / 3];
  }
};

// face_groups: empty (no groups) or one id per face of the mesh.
LocalPiece local_piece(const Triangles& triangles, std::vector<int> faces, const std::vector<int>& face_groups);

// Vertices of a piece as classes of corners joined across the edges that are
// neither on the border nor cut. Pinched vertices (two fans of the piece meet
// there) become separate vertices; so do the two sides of a cut.
struct CornerVertices {
  std::vector<int> of_corner;  // 3 f + k -> vertex 0 .. count-1
  int count = 0;
};

CornerVertices corner_vertices(const LocalPiece& piece, const EdgeTable& edges, const std::vector<char>& is_cut);

// The face-edge that follows face-edge fe (3 f + k) in its face.
inline int next_in_face(int fe) { return 3 * (fe / 3) + (fe % 3 + 1) % 3; }

// A piece's vertices, boundary loops (face-edges 3 f + k in order, the piece
// on their left) and Euler characteristic once `is_cut` is cut open.
struct PieceTopology {
  CornerVertices verts;
  std::vector<std::vector<int>> loops;
  bool manifold = true;  // every boundary vertex on one boundary fan
  long euler = 0;        // vertices - edges (a cut edge counts twice) + faces
  // A disc with holes (genus 0, at least one loop), or a disc when
  // loops.size() == 1: what the flattening takes.
  bool flattenable() const { return manifold && !loops.empty() && euler == 2 - static_cast<long>(loops.size()); }
};

PieceTopology piece_topology(const LocalPiece& piece, const EdgeTable& edges, const std::vector<char>& is_cut);

// Graph of the piece's vertices (corner classes) along the edges inside the
// piece (not on its border, not cut, not inside a face group).
struct VertexGraph {
  std::vector<int> offsets, neighbour, edge;
  std::vector<double> length;  // per edge of the table, model units
};

VertexGraph vertex_graph(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges,
                         const CornerVertices& verts, const std::vector<char>& is_cut);

// Dijkstra from `sources` until a vertex with stop[v] is settled (or all, when
// stop is empty); vertices with `blocked[v]` (if not empty) are settled but not
// left. `reached`: the settled stop vertex (-1 if none), or with stop empty
// the farthest vertex; prev_edge / prev_vertex give the paths back.
struct ShortestPaths {
  std::vector<double> dist;
  std::vector<int> prev_vertex, prev_edge;
  int reached = -1;
};

ShortestPaths dijkstra(const VertexGraph& g, const std::vector<int>& sources, const std::vector<char>& stop,
                       const std::vector<char>& blocked = {});

// What choose_cuts opens besides handles and closed pieces.
enum class Holes {
  keep,  // further boundary loops stay holes (a flat annulus needs no slit)
  join,  // every further loop is joined to the first by a shortest path
};

// Interior edges to cut (is_cut, per edge of the table, set on return) so
// that the piece becomes a disc, or with Holes::keep a disc with holes: a
// closed piece is opened along its longest shortest path (two sweeps),
// handles along the short edges a maximum spanning tree of the dual graph
// leaves (pruned of dangling branches), and with Holes::join every further
// boundary loop is joined to the first along the shortest interior path.
// Returns false when the piece's topology is not that of a surface.
bool choose_cuts(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges, Holes holes,
                 std::vector<char>& is_cut);

}  // namespace developable::unfolding

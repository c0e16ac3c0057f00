// How strongly the surface creases across each edge, measured against the
// mesh's own noise: the first stage of the crease pieces (crease_pieces.h).
//
// On a noisy mesh the face normals jump across every edge, and on a coarse
// cylinder or cone they jump by the facet angle across every ruling, so the
// dihedral angle of one edge tells a crease from neither (on the sheet-metal
// assemblies of devkit/assemblies.py the facet angles of the twins reach
// 0.1-0.3 rad, as much as the mitres of an elbow). Here each side of an edge
// gets its own smooth normal field, a least-squares plane n = a + b u + c w
// per tangent component over that side's faces of the edge's 2-ring (u along
// the edge, w across it, from its midpoint); the crease's jump is the
// difference of the two fields at the midpoint. A crease jumps by its angle;
// curvature hardly does: the facet staircase of a cylinder fits a line on
// either side (on 24 facets, away from its ends, jumps of at most 0.22 times
// the facet angle, where the edges' dihedral angles are 0 or the whole facet
// angle; crease_lines.h's ridge test takes care of the rest). Each face's normal is weighted by the inverse of the
// variance a unit noise of its corners along the normal gives that component (a thin face tilts far more across its
// length than along it), so the fit also gives the jump's variance per unit noise, and its score is the jump over its
// standard deviation.
//
// The noise is not an input: it is read off the mesh as the median score per
// unit noise over the edges (most edges are not on a crease), over the median
// of a two-dimensional standard normal's norm. Faces that noise of that size
// would tilt by more than kUnreliableTilt, and that tilt far more than the
// mesh's typical face (the sliver fan at a cone's apex, edges as short as the
// noise), carry no direction and are left out of the fits.
#pragma once

#include "core/mesh_connectivity.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// An edge of a triangle mesh: its vertices a < b and the faces on either
// side; g is -1 on the boundary.
struct MeshEdge {
  int a = 0, b = 0;
  int f = 0, g = -1;
};

// Every undirected edge of a validated manifold mesh, each once, in the order
// of its first face and corner. O(faces).
std::vector<MeshEdge> mesh_edges(const Triangles& triangles, const VertexFaces& connectivity);

// The gradients (columns, 1/length) of a face's three barycentric functions,
// in its plane: a unit move of corner i along the normal tilts the face's
// normal by minus column i, so the variance a unit corner noise gives its
// normal's component along a unit vector u of its plane is
// |gradients^T u|^2. Zero for a face without area.
Eigen::Matrix3d barycentric_gradients(const Positions& positions, const Triangles& triangles, Eigen::Index face);

// Faces whose normals a vertex noise of this standard deviation (along the
// normal) would tilt by more than this (rad, RMS) are left out of the fits:
// their normals say nothing of the surface's. On the square-to-round
// transitions of devkit/assemblies.py the fans at the cones' apexes have edges
// as short as 1/20 of the mean; with 3 % noise their normals turned by up to
// 1.4 rad and made lines of scores above 30 (tuning seeds 0-19).
inline constexpr double kUnreliableTilt = 0.3;

// ... and whose tilt per unit noise is above this many times the median
// face's. On a mesh of slivers every face tilts alike, and the noise read off
// it holds what the slivers' facets make of the fits (2.1-2.7 times the
// noise on the sliver cups of devkit/assemblies.py, seeds 100-119): by the
// rule above a third of the faces went, with them every score along a cup's
// rim, and a 77-degree crease was not found. The apex fans' faces tilt 20
// times the median and more.
inline constexpr double kOutlierTilt = 3.0;

// A side's fit needs this many faces (three unknowns per component and one
// to spare); an edge with fewer on a side (on or next to the boundary) gets
// no score.
inline constexpr int kMinSideFaces = 4;

struct CreaseStrengths {
  // Per edge (mesh_edges order): the angle (rad) between the two sides'
  // normal fields at the edge's midpoint, and that jump over its standard
  // deviation (dimensionless); both 0 on boundary edges and on edges without
  // a score (a side with fewer than kMinSideFaces usable faces, or an
  // unusable face of its own).
  Eigen::VectorXd jump, score;
  // The vertex noise along the normal read off the mesh (caller's units):
  // its standard deviation. Never below kNoiseFloor times the mean edge
  // length (a noise-free mesh's fits are exact to rounding).
  double noise = 0.0;
};

// The least noise (in mean edge lengths) the scores assume.
inline constexpr double kNoiseFloor = 1e-6;

// The crease strengths of a mesh.
//   positions, triangles: a mesh that passed validate_mesh; normals: its
//   face_normals; connectivity: its vertex_faces; edges: its mesh_edges;
//   threads: as parallel_for's (concurrent_jobs.h); the result does not
//   depend on it.
// No failure mode: a mesh without an edge that can be scored gets all zeros
// (and the noise floor). O(edges x 2-ring size) time, two passes.
CreaseStrengths crease_strengths(const Positions& positions, const Triangles& triangles, const Normals& normals,
                                 const VertexFaces& connectivity, const std::vector<MeshEdge>& edges, int threads = 0);

}  // namespace developable

// Meshes with creases for the unit tests of the crease stages and the
// developable pieces: a plane folded along a line and a pipe mitred in two,
// exact or with noise (test_meshes.h's add_noise).
#pragma once

#include "test_meshes.h"

#include <Eigen/Geometry>

#include <cmath>

namespace developable::test {

// The unit square's grid (rows odd) folded by `angle` (rad) along its middle
// row u = 0.5: the half u > 0.5 turned up about that line. The fold's edges
// are those of row (rows - 1) / 2.
inline Mesh folded_plane(int rows, int cols, double angle) {
  return grid(rows, cols, false, [=](double u, double v) {
    if (u <= 0.5) return Eigen::Vector3d(v, u, 0.0);
    return Eigen::Vector3d(v, 0.5 + (u - 0.5) * std::cos(angle), (u - 0.5) * std::sin(angle));
  });
}

// A pipe of radius 1 along +z, bent at z = 1 by `turn` (rad) in the x-z plane
// and going on for 1 along its new axis; the joint ring lies in the mitre
// plane (it halves the turn). `rows` (odd) rings, the middle one the joint;
// `cols` columns around, the first at +x (so with cols a multiple of 4 a
// column sits at y = +-1, where the two cylinders are tangent and the ring's
// vertex is flat).
inline Mesh mitred_pipe(int rows, int cols, double turn) {
  const Eigen::Vector3d a0(0, 0, 1), a1(std::sin(turn), 0, std::cos(turn)), joint(0, 0, 1);
  const Eigen::Vector3d mitre = (a0 + a1).normalized();
  return grid(rows, cols, true, [&](double u, double v) {
    const double t = 2.0 * M_PI * v;
    const Eigen::Vector3d offset(std::cos(t), std::sin(t), 0.0);
    const double to_mitre = (joint - offset).dot(mitre) / a0.dot(mitre);
    if (u <= 0.5) return Eigen::Vector3d(offset + (u / 0.5) * to_mitre * a0);
    return Eigen::Vector3d(offset + to_mitre * a0 + ((u - 0.5) / 0.5) * a1);
  });
}

// Whether a face of mitred_pipe(.., turn) lies below the mitre plane (on the
// first cylinder).
inline bool below_mitre(const Mesh& m, Eigen::Index face, double turn) {
  const Eigen::Vector3d mitre =
      (Eigen::Vector3d(0, 0, 1) + Eigen::Vector3d(std::sin(turn), 0, std::cos(turn))).normalized();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int c = 0; c < 3; ++c) centroid += m.positions.row(m.triangles(face, c)).transpose() / 3.0;
  return (centroid - Eigen::Vector3d(0, 0, 1)).dot(mitre) < 0.0;
}

}  // namespace developable::test

// Small exact meshes for the unit tests (plane grid, cylinder, cone, cube,
// octahedron, subdivided-octahedron sphere), built in code so that each test states what it runs on.
#pragma once

#include "core/types.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>
#include <random>

namespace developable::test {

struct Mesh {
  Positions positions;
  Triangles triangles;
};

// rows x cols vertices on the grid (i, j) -> point(i / (rows-1), j / (cols-1)),
// two triangles per cell, counter-clockwise seen from +z for the plane. With
// wrap, column cols-1 joins column 0 (a closed band).
template <typename Point>
Mesh grid(int rows, int cols, bool wrap, Point point) {
  Mesh m;
  const int columns = cols;
  m.positions.resize(rows * columns, 3);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) {
      const Eigen::Vector3d p = point(double(i) / (rows - 1), wrap ? double(j) / cols : double(j) / (cols - 1));
      m.positions.row(i * columns + j) = p.transpose();
    }
  const int cells = wrap ? cols : cols - 1;
  m.triangles.resize(2 * (rows - 1) * cells, 3);
  int f = 0;
  for (int i = 0; i + 1 < rows; ++i)
    for (int j = 0; j < cells; ++j) {
      const int a = i * columns + j, b = i * columns + (j + 1) % columns;
      const int c = (i + 1) * columns + j, d = (i + 1) * columns + (j + 1) % columns;
      m.triangles.row(f++) << a, b, d;
      m.triangles.row(f++) << a, d, c;
    }
  return m;
}

// The unit square [0,1]^2 in the plane z = 0 (normal +z).
inline Mesh plane(int rows = 8, int cols = 9) {
  return grid(rows, cols, false, [](double u, double v) { return Eigen::Vector3d(v, u, 0.0); });
}

// An open cylinder of radius `radius` around z, height 1, closed around.
inline Mesh cylinder(int rows = 8, int cols = 24, double radius = 1.0) {
  return grid(rows, cols, true, [=](double u, double v) {
    const double t = 2.0 * M_PI * v;
    return Eigen::Vector3d(radius * std::cos(t), radius * std::sin(t), u);
  });
}

// A frustum of a cone around z (radius r0 at z = 0 to r1 at z = height),
// closed around: every face normal makes the same angle with the axis.
inline Mesh cone(int rows = 8, int cols = 24, double r0 = 1.5, double r1 = 0.6, double height = 1.5) {
  return grid(rows, cols, true, [=](double u, double v) {
    const double t = 2.0 * M_PI * v, r = r0 + (r1 - r0) * u;
    return Eigen::Vector3d(r * std::cos(t), r * std::sin(t), height * u);
  });
}

// The surface of the unit cube [0,1]^3, 8 vertices, 12 outward triangles.
inline Mesh cube() {
  Mesh m;
  m.positions.resize(8, 3);
  for (int v = 0; v < 8; ++v) m.positions.row(v) << (v & 1), (v >> 1) & 1, (v >> 2) & 1;
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 3, 0, 3, 1,  // z = 0
      4, 5, 7, 4, 7, 6,             // z = 1
      0, 1, 5, 0, 5, 4,             // y = 0
      2, 6, 7, 2, 7, 3,             // y = 1
      0, 4, 6, 0, 6, 2,             // x = 0
      1, 3, 7, 1, 7, 5;             // x = 1
  return m;
}

// A closed sphere of radius 1 around the origin: an octahedron subdivided
// `levels` times (8 * 4^levels faces), its vertices pushed onto the sphere.
inline Mesh sphere(int levels) {
  Mesh m;
  m.positions.resize(6, 3);
  m.positions << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  m.triangles.resize(8, 3);
  m.triangles << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  for (int level = 0; level < levels; ++level) {
    std::vector<Eigen::RowVector3d> points;
    for (Eigen::Index v = 0; v < m.positions.rows(); ++v) points.push_back(m.positions.row(v));
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      points.push_back((points[static_cast<size_t>(a)] + points[static_cast<size_t>(b)]).normalized());
      return middle[key] = static_cast<int>(points.size()) - 1;
    };
    Triangles next(4 * m.triangles.rows(), 3);
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
      const int a = m.triangles(f, 0), b = m.triangles(f, 1), c = m.triangles(f, 2);
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.row(4 * f) << a, ab, ca;
      next.row(4 * f + 1) << ab, b, bc;
      next.row(4 * f + 2) << ca, bc, c;
      next.row(4 * f + 3) << ab, bc, ca;
    }
    m.triangles = next;
    m.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t v = 0; v < points.size(); ++v) m.positions.row(static_cast<Eigen::Index>(v)) = points[v];
  }
  return m;
}

// A random unit vector, uniform on the sphere.
inline Eigen::Vector3d random_unit(std::mt19937& random) {
  std::normal_distribution<double> g;
  return Eigen::Vector3d(g(random), g(random), g(random)).normalized();
}

// Uniform noise of `amplitude` on every coordinate, seeded.
inline void add_noise(Positions& positions, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Eigen::Index i = 0; i < positions.size(); ++i) positions.data()[i] += u(random);
}

}  // namespace developable::test

// Synthetic Gauss images for the tests of stages 3-6: the normals of an exact
// circular cone about `axis` with half-opening `angle` (pi/2: a cylinder,
// whose normals are a great circle), at `count` random azimuths in
// [0, sweep), with random weights.
#pragma once

#include "core/types.h"
#include "test_meshes.h"

#include <Eigen/Geometry>

#include <random>

namespace developable::test {

struct GaussImage {
  Normals normals;
  Eigen::VectorXd weights;
  Eigen::Vector3d axis;
  double angle = 0.0;
};

inline GaussImage cone_gauss_image(unsigned seed, double angle, double sweep = 2 * M_PI, int count = 2000) {
  std::mt19937 random(seed);
  GaussImage image;
  image.axis = random_unit(random);
  image.angle = angle;
  const Eigen::Vector3d e1 = image.axis.unitOrthogonal(), e2 = image.axis.cross(e1);
  std::uniform_real_distribution<double> azimuth(0.0, sweep), weight(0.5, 1.5);
  image.normals.resize(count, 3);
  image.weights.resize(count);
  for (int i = 0; i < count; ++i) {
    const double t = azimuth(random);
    image.normals.row(i) =
        (std::cos(angle) * image.axis + std::sin(angle) * (std::cos(t) * e1 + std::sin(t) * e2)).transpose();
    image.weights[i] = weight(random);
  }
  return image;
}

// Angle (rad) between n and the image's circle.
inline double angle_to_circle(const GaussImage& image, const Eigen::Vector3d& n) {
  return std::abs(std::acos(std::clamp(image.axis.dot(n.normalized()), -1.0, 1.0)) - image.angle);
}

}  // namespace developable::test

#include "core/measures.h"

#include "core/mesh_input.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace developable {
namespace {

Eigen::Vector3d corner(const Positions& positions, const Triangles& triangles, Eigen::Index f, int c) {
  return positions.row(triangles(f, c)).transpose();
}

// Faces (or edges) a chunk of the measures shared out to spare cores: a
// 100k-face mesh is 13 chunks.
constexpr Eigen::Index kChunk = 8192;

// The items of [0, count) that `picked` picks, ascending, the chunks looked
// at on `spare` cores.
template <typename Pick>
std::vector<Eigen::Index> picked_items(Eigen::Index count, SpareCores* spare, const Pick& picked) {
  std::vector<std::vector<Eigen::Index>> chunks(static_cast<size_t>((count + kChunk - 1) / kChunk));
  parallel_for(count, kChunk, spare, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i)
      if (picked(i)) chunks[static_cast<size_t>(begin / kChunk)].push_back(i);
  });
  std::vector<Eigen::Index> items;
  for (const auto& chunk : chunks) items.insert(items.end(), chunk.begin(), chunk.end());
  return items;
}

}  // namespace

Normals face_normals(const Positions& positions, const Triangles& triangles, SpareCores* spare) {
  Normals normals(triangles.rows(), 3);
  parallel_for(triangles.rows(), kChunk, spare, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index f = begin; f < end; ++f) {
      const Eigen::Vector3d a = corner(positions, triangles, f, 0);
      const Eigen::Vector3d n = (corner(positions, triangles, f, 1) - a).cross(corner(positions, triangles, f, 2) - a);
      const double length = n.norm();
      normals.row(f) = length > 0.0 ? Eigen::RowVector3d(n.transpose() / length) : Eigen::RowVector3d::Zero();
    }
  });
  return normals;
}

Eigen::VectorXd face_areas(const Positions& positions, const Triangles& triangles) {
  Eigen::VectorXd areas(triangles.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::Vector3d a = corner(positions, triangles, f, 0);
    areas[f] = 0.5 * (corner(positions, triangles, f, 1) - a).cross(corner(positions, triangles, f, 2) - a).norm();
  }
  return areas;
}

std::vector<Eigen::Index> turned_over_faces(const Normals& normals, const Normals& reference, SpareCores* spare) {
  return picked_items(normals.rows(), spare, [&](Eigen::Index f) {
    return reference.row(f).squaredNorm() != 0.0 &&
           (normals.row(f).dot(reference.row(f)) < 0.0 || normals.row(f).squaredNorm() == 0.0);
  });
}

double average_edge_length(const Positions& positions, const Triangles& triangles) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double sum = 0.0;
  for (const auto& [a, b] : edges) sum += (positions.row(a) - positions.row(b)).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

namespace {

// Running product of a vertex's corner rotations: the angle sum is
// arg(re + i im) + 2 pi wraps.
struct AngleProduct {
  double re = 1.0, im = 0.0;
  int wraps = 0;
};

// Turns `product` further by the corner angle with unit cosine `c` and sine
// `s` (s >= 0: corner angles are in [0, pi], so the true motion is
// counter-clockwise). A wrap is counted where the product passes the
// negative real axis; since rounding can move it a hair clockwise, the
// crossing is told apart from one of the positive real axis by the signs of
// the real parts (a genuine turn is at most pi).
inline void turn(AngleProduct& product, double c, double s) {
  const double re = product.re * c - product.im * s;
  const double im = product.re * s + product.im * c;
  if (product.im >= 0.0) {
    // Into the lower half through pi; or, for a corner of pi at pi, all the
    // way round to the upper half's positive side.
    if (im < 0.0 ? (product.re <= 0.0 || re < 0.0) : (product.re < 0.0 && re > 0.0)) ++product.wraps;
  } else if (im >= 0.0 && product.re < 0.0 && re < 0.0) {
    --product.wraps;  // rounding took it back clockwise through pi
  }
  product.re = re;
  product.im = im;
}

// The cosines and sines of face f's corner angles, corner by corner; false
// where an edge has collapsed, which makes every corner angle 0 (atan2(0,
// 0)): no turn. A triangle needs just its edge lengths, one cross product
// and three dots: cos and sin of a corner are u.w and |u x w| (the same for
// all three corners) over |u| |w|.
inline bool corner_turns(const Positions& positions, const Triangles& triangles, Eigen::Index f, double* cosines,
                         double* sines) {
  const Eigen::Vector3d p[3] = {corner(positions, triangles, f, 0), corner(positions, triangles, f, 1),
                                corner(positions, triangles, f, 2)};
  // Edge k runs from corner k to corner k + 1.
  const Eigen::Vector3d e[3] = {p[1] - p[0], p[2] - p[1], p[0] - p[2]};
  const double length[3] = {e[0].norm(), e[1].norm(), e[2].norm()};
  if (!(length[0] > 0.0 && length[1] > 0.0 && length[2] > 0.0)) return false;
  const double inverse[3] = {1.0 / length[0], 1.0 / length[1], 1.0 / length[2]};
  const double sine_area = e[0].cross(e[2]).norm();  // |u x w| at every corner
  for (int c = 0; c < 3; ++c) {
    // Corner c: u = e[c], w = -e[c + 2].
    const int back = (c + 2) % 3;
    const double scale = inverse[c] * inverse[back];
    cosines[c] = -e[c].dot(e[back]) * scale;
    sines[c] = sine_area * scale;
  }
  return true;
}

}  // namespace

Eigen::VectorXd angle_defects(const Positions& positions, const Triangles& triangles, const std::vector<bool>& interior,
                              SpareCores* spare) {
  // Each corner turns its vertex's running product by the corner angle, so
  // a vertex needs one atan2 instead of one per corner. Agrees with summing
  // per-corner atan2 to ~1e-15 rad.
  const Eigen::Index faces = triangles.rows();
  std::vector<AngleProduct> products(static_cast<size_t>(positions.rows()));
  const CoreLease lease(faces > kChunk ? spare : nullptr, kMostLoopThreads - 1);
  if (lease.threads() == 1) {
    for (Eigen::Index f = 0; f < faces; ++f) {
      double cosines[3], sines[3];
      if (!corner_turns(positions, triangles, f, cosines, sines)) continue;
      for (int c = 0; c < 3; ++c) turn(products[static_cast<size_t>(triangles(f, c))], cosines[c], sines[c]);
    }
  } else {
    // On spare cores the corners are found face by face, then turned in face
    // order on this thread (a product's bits depend on the order); the
    // buffers only then, as several polishes measure at once.
    std::vector<double> cosines(static_cast<size_t>(3 * faces)), sines(static_cast<size_t>(3 * faces));
    std::vector<char> turns(static_cast<size_t>(faces));
    parallel_for(faces, kChunk, lease.threads(), [&](Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index f = begin; f < end; ++f)
        turns[static_cast<size_t>(f)] = corner_turns(positions, triangles, f, &cosines[static_cast<size_t>(3 * f)],
                                                     &sines[static_cast<size_t>(3 * f)]);
    });
    for (Eigen::Index f = 0; f < faces; ++f) {
      if (!turns[static_cast<size_t>(f)]) continue;
      for (int c = 0; c < 3; ++c) {
        const auto at = static_cast<size_t>(3 * f + c);
        turn(products[static_cast<size_t>(triangles(f, c))], cosines[at], sines[at]);
      }
    }
  }
  Eigen::VectorXd defects = Eigen::VectorXd::Zero(positions.rows());
  parallel_for(positions.rows(), kChunk, lease.threads(), [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index v = begin; v < end; ++v) {
      if (!interior[static_cast<size_t>(v)]) continue;
      const AngleProduct& product = products[static_cast<size_t>(v)];
      defects[v] = -std::atan2(product.im, product.re) - 2.0 * M_PI * (product.wraps - 1);
    }
  });
  return defects;
}

DefectStats defect_stats(const Eigen::VectorXd& defects, const std::vector<bool>& interior) {
  DefectStats stats;
  double sum = 0.0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    const double value = std::abs(defects[v]);
    sum += value;
    stats.max_abs = std::max(stats.max_abs, value);
    ++stats.interior_count;
  }
  if (stats.interior_count > 0) stats.mean_abs = sum / static_cast<double>(stats.interior_count);
  return stats;
}

std::vector<bool> interior_vertices(const Positions& positions, const Triangles& triangles) {
  std::vector<bool> interior = boundary_vertices(positions, triangles);
  std::vector<bool> used(interior.size(), false);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) used[static_cast<size_t>(triangles(f, c))] = true;
  for (size_t v = 0; v < interior.size(); ++v) interior[v] = used[v] && !interior[v];
  return interior;
}

namespace {

// Angle (rad) between two unit vectors, accurate near 0 and pi.
double angle_between(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

CreaseGuard::CreaseGuard(const Triangles& triangles, const Normals& reference, const std::vector<int>& groups,
                         double growth) {
  if (!(growth > 0.0) || triangles.rows() == 0) return;
  const VertexFaces table = vertex_faces(triangles, triangles.maxCoeff() + 1);
  std::vector<Edge> edges;
  edges.reserve(static_cast<size_t>(3 * triangles.rows() / 2));  // inner edges, each seen once
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int g = face_across(table, triangles, static_cast<int>(f), triangles(f, k), triangles(f, (k + 1) % 3));
      if (g <= f) continue;  // a boundary edge, or seen from g
      const bool one_group = groups.empty() || groups[static_cast<size_t>(f)] == groups[static_cast<size_t>(g)];
      if (!one_group || reference.row(f).squaredNorm() == 0.0 || reference.row(g).squaredNorm() == 0.0) continue;
      const double limit = angle_between(reference.row(f), reference.row(g)) + growth;
      if (limit < M_PI) edges.push_back({static_cast<int>(f), g, std::cos(limit)});  // else no angle is wider
    }
  edges_ = std::make_shared<const std::vector<Edge>>(std::move(edges));
}

CreaseGuard CreaseGuard::restricted(const std::vector<Eigen::Index>& faces, Eigen::Index mesh_faces) const {
  CreaseGuard out;
  if (!edges_) return out;
  std::vector<int> local_of(static_cast<size_t>(mesh_faces), -1);
  for (size_t i = 0; i < faces.size(); ++i) local_of[static_cast<size_t>(faces[i])] = static_cast<int>(i);
  std::vector<Edge> edges;
  for (const Edge& e : *edges_) {
    const int f = local_of[static_cast<size_t>(e.f)], g = local_of[static_cast<size_t>(e.g)];
    if (f >= 0 && g >= 0) edges.push_back({f, g, e.limit_cosine});
  }
  out.edges_ = std::make_shared<const std::vector<Edge>>(std::move(edges));
  return out;
}

namespace {

// Whether the angle between a and b is wider than the angle whose cosine is
// `c`: a.b < c |a| |b|, squared to save the roots (a zero vector is never
// wider). An atan2 per watched edge and step was a tenth of a 100k-face
// run.
bool wider_than(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, double c) {
  const double dot = a.dot(b);
  const double bound = c * c * a.squaredNorm() * b.squaredNorm();
  return c >= 0.0 ? dot < 0.0 || dot * dot < bound : dot < 0.0 && dot * dot > bound;
}

}  // namespace

std::vector<Eigen::Index> CreaseGuard::creased_faces(const Normals& normals, SpareCores* spare) const {
  if (!active()) return {};
  const std::vector<Edge>& edges = *edges_;
  const std::vector<Eigen::Index> creased =
      picked_items(static_cast<Eigen::Index>(edges.size()), spare, [&](Eigen::Index k) {
        const Edge& e = edges[static_cast<size_t>(k)];
        return wider_than(normals.row(e.f), normals.row(e.g), e.limit_cosine);
      });
  std::vector<Eigen::Index> faces;
  for (const Eigen::Index k : creased) {
    faces.push_back(edges[static_cast<size_t>(k)].f);
    faces.push_back(edges[static_cast<size_t>(k)].g);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

std::vector<Eigen::Index> folded_faces(const Normals& normals, const Normals& reference, const CreaseGuard& guard,
                                       SpareCores* spare) {
  std::vector<Eigen::Index> faces = turned_over_faces(normals, reference, spare);
  if (!guard.active()) return faces;
  const std::vector<Eigen::Index> creased = guard.creased_faces(normals, spare);
  faces.insert(faces.end(), creased.begin(), creased.end());
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

bool put_back_folded_corners(Positions& positions, const Positions& fallback, const Triangles& triangles,
                             const Normals& reference, const CreaseGuard& guard, int rounds, SpareCores* spare) {
  for (int round = 0;; ++round) {
    const std::vector<Eigen::Index> folded =
        folded_faces(face_normals(positions, triangles, spare), reference, guard, spare);
    if (folded.empty()) return true;
    if (round == rounds) return false;
    for (Eigen::Index f : folded)
      for (int c = 0; c < 3; ++c) positions.row(triangles(f, c)) = fallback.row(triangles(f, c));
  }
}

double normal_roughness(const Normals& normals, const Triangles& triangles, const VertexFaces& connectivity) {
  double sum = 0.0;
  Eigen::Index counted = 0;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::RowVector3d n = normals.row(f);
    if (n.squaredNorm() == 0.0) continue;
    Eigen::RowVector3d around = n;
    for (int k = 0; k < 3; ++k) {
      const int g =
          face_across(connectivity, triangles, static_cast<int>(f), triangles(f, k), triangles(f, (k + 1) % 3));
      if (g >= 0) around += normals.row(g);
    }
    const double length = around.norm();
    if (length == 0.0) continue;
    sum += std::acos(std::clamp(n.dot(around) / length, -1.0, 1.0));
    ++counted;
  }
  return counted > 0 ? sum / static_cast<double>(counted) : 0.0;
}

Eigen::VectorXd ruling_spreads(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, const std::vector<bool>& interior) {
  Eigen::VectorXd spreads = Eigen::VectorXd::Zero(connectivity.vertex_count());
  for (Eigen::Index v = 0; v < connectivity.vertex_count(); ++v) {
    if (!interior[static_cast<size_t>(v)] || connectivity.count(v) < 3) continue;  // two normals share a circle
    Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
    double total = 0.0;
    for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
      int c = 0;
      while (triangles(*f, c) != v) ++c;
      const Eigen::Vector3d p = corner(positions, triangles, *f, c);
      const Eigen::Vector3d a = corner(positions, triangles, *f, (c + 1) % 3) - p;
      const Eigen::Vector3d b = corner(positions, triangles, *f, (c + 2) % 3) - p;
      const double tip = std::atan2(a.cross(b).norm(), a.dot(b));
      const Eigen::Vector3d n = normals.row(*f).transpose();
      moments.noalias() += tip * (n * n.transpose());
      total += tip;
    }
    const double smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(moments, Eigen::EigenvaluesOnly).eigenvalues()[0];
    spreads[v] = std::asin(std::sqrt(std::clamp(smallest / std::max(total, 1e-300), 0.0, 1.0)));
  }
  return spreads;
}

VertexShares vertex_shares(const Eigen::VectorXd& defects, const Eigen::VectorXd& spreads,
                           const std::vector<bool>& interior) {
  Eigen::Index count = 0, flat = 0, ruled = 0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    ++count;
    if (!(std::abs(defects[v]) < kFlatDefect)) continue;
    ++flat;
    if (flat_and_ruled(defects[v], spreads[v])) ++ruled;
  }
  if (count == 0) return {};
  const double total = static_cast<double>(count);
  return {flat / total, ruled / total, (flat - ruled) / total};
}

double angle_defect_noise_gain(const Positions& positions, const Triangles& triangles, const Normals& normals,
                               const VertexFaces& connectivity, Eigen::Index v) {
  // The gradients of K_v with respect to v and each neighbour, gathered per
  // vertex (a neighbour is in two of v's faces on a closed star).
  std::vector<std::pair<int, Eigen::Vector3d>> gradients;
  const Eigen::Vector3d a = positions.row(v).transpose();
  for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
    int c = 0;
    while (triangles(*f, c) != v) ++c;
    const int b = triangles(*f, (c + 1) % 3), d = triangles(*f, (c + 2) % 3);
    const Eigen::Vector3d n = normals.row(*f).transpose();
    const Eigen::Vector3d u = positions.row(b).transpose() - a, w = positions.row(d).transpose() - a;
    if (n.squaredNorm() == 0.0 || u.squaredNorm() == 0.0 || w.squaredNorm() == 0.0) continue;
    // K_v = 2 pi - sum theta: dK/dx = -d theta/dx.
    const Eigen::Vector3d grad_b = n.cross(u) / u.squaredNorm();
    const Eigen::Vector3d grad_d = -n.cross(w) / w.squaredNorm();
    gradients.emplace_back(b, grad_b);
    gradients.emplace_back(d, grad_d);
    gradients.emplace_back(static_cast<int>(v), -(grad_b + grad_d));
  }
  std::sort(gradients.begin(), gradients.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  double gain = 0.0;
  for (size_t i = 0; i < gradients.size();) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const int vertex = gradients[i].first;
    for (; i < gradients.size() && gradients[i].first == vertex; ++i) sum += gradients[i].second;
    gain += sum.squaredNorm();
  }
  return gain;
}

}  // namespace developable

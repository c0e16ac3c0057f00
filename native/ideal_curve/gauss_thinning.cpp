#include "ideal_curve/gauss_thinning.h"

#include "core/concurrent_jobs.h"
#include "core/measures.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>

namespace developable {
namespace {

// Faces per chunk of the parallel loop (fixed, so the result does not depend
// on the thread count).
constexpr Eigen::Index kChunk = 4096;
// The Gaussian weight's width in cones: exp(-(angle / (kConeWidth cone))^2).
constexpr double kConeWidth = 2.0;
// Up to this many threads each pair of neighbours is weighed once, on the
// calling thread (a whole object's thinning at half the CPU, in the wall
// time two threads take to sweep every face's own list); with more, every
// face sweeps its own list, the faces split among the threads. The same
// targets bit for bit either way.
constexpr unsigned kPairSweepThreads = 2;
// Faces whose pairs are weighed at once on spare cores before this thread
// sums them (a buffer of about 30 weights a face).
constexpr Eigen::Index kPairBlock = 8192;
// The weight of a pair outside the cone (weights are never negative).
constexpr double kOutsideCone = -1.0;

}  // namespace

GaussThinning::GaussThinning(const Positions& positions, const Triangles& triangles, double radius,
                             const std::vector<int>& pieces) {
  const Eigen::Index m = triangles.rows();
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw EngineError(Status::invalid_argument, "gauss thinning: the radius must be positive");
  if (!pieces.empty() && static_cast<Eigen::Index>(pieces.size()) != m)
    throw EngineError(Status::invalid_argument, "gauss thinning: one piece id per face");
  Positions centroids(m, 3);
  for (Eigen::Index f = 0; f < m; ++f) centroids.row(f) = face_centroid(positions, triangles, f).transpose();
  // A grid of cells of side `radius`: each face's neighbours are in the 27
  // cells around its own. Cells are keyed and sorted, not hashed, so the
  // lists come out the same on every run.
  const Eigen::RowVector3d low =
      m > 0 ? Eigen::RowVector3d(centroids.colwise().minCoeff()) : Eigen::RowVector3d::Zero();
  std::array<std::int64_t, 3> dims{1, 1, 1};
  std::vector<std::array<std::int64_t, 3>> cell(static_cast<size_t>(m));
  for (Eigen::Index f = 0; f < m; ++f)
    for (int d = 0; d < 3; ++d) {
      cell[static_cast<size_t>(f)][static_cast<size_t>(d)] =
          static_cast<std::int64_t>(std::floor((centroids(f, d) - low[d]) / radius));
      dims[static_cast<size_t>(d)] =
          std::max(dims[static_cast<size_t>(d)], cell[static_cast<size_t>(f)][static_cast<size_t>(d)] + 1);
    }
  const auto key = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return (x * dims[1] + y) * dims[2] + z; };
  std::vector<std::pair<std::int64_t, int>> keyed(static_cast<size_t>(m));
  for (Eigen::Index f = 0; f < m; ++f) {
    const auto& c = cell[static_cast<size_t>(f)];
    keyed[static_cast<size_t>(f)] = {key(c[0], c[1], c[2]), static_cast<int>(f)};
  }
  std::sort(keyed.begin(), keyed.end());
  const double radius2 = radius * radius;
  offsets_.assign(static_cast<size_t>(m) + 1, 0);
  std::vector<int> found;
  for (Eigen::Index f = 0; f < m; ++f) {
    found.clear();
    const auto& c = cell[static_cast<size_t>(f)];
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const std::int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) continue;
          const std::int64_t k = key(x, y, z);
          auto it = std::lower_bound(keyed.begin(), keyed.end(), std::make_pair(k, -1));
          for (; it != keyed.end() && it->first == k; ++it) {
            const int g = it->second;
            if (!pieces.empty() && pieces[static_cast<size_t>(g)] != pieces[static_cast<size_t>(f)]) continue;
            if ((centroids.row(g) - centroids.row(f)).squaredNorm() <= radius2) found.push_back(g);
          }
        }
    std::sort(found.begin(), found.end());
    neighbours_.insert(neighbours_.end(), found.begin(), found.end());
    offsets_[static_cast<size_t>(f) + 1] = neighbours_.size();
  }
}

Normals GaussThinning::targets(const Normals& normals, double cone, int threads, SpareCores* spare) const {
  const Eigen::Index m = static_cast<Eigen::Index>(offsets_.size()) - 1;
  if (normals.rows() != m) throw EngineError(Status::internal_error, "gauss thinning: one normal per face");
  if (!(cone > 0.0)) throw EngineError(Status::invalid_argument, "gauss thinning: the cone must be positive");
  const double cos_cone = std::cos(cone);
  const double width = kConeWidth * cone;
  // The weight of a neighbour whose normal's cosine with f's is c (within
  // the cone); the cosine of (f, g) is the one of (g, f), bit for bit.
  const auto weight = [&](double c) {
    const double angle = std::acos(c) / width;
    return std::exp(-angle * angle);
  };
  // f's target from the sum of its neighbours' weighted n n^T.
  const auto target = [&](Eigen::Index f, const Eigen::Matrix3d& moments) -> Eigen::RowVector3d {
    const Eigen::Vector3d n = normals.row(f).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(moments);  // closed form: half the iterative solver's time
    const Eigen::Vector3d axis = solver.eigenvectors().col(0);
    const Eigen::Vector3d projected = n - n.dot(axis) * axis;
    const double length = projected.norm();
    return length > 1e-12 ? Eigen::RowVector3d((projected / length).transpose()) : Eigen::RowVector3d(n.transpose());
  };
  Normals out(m, 3);
  if (thread_count(threads) > kPairSweepThreads) {
    // Each face sweeps its own list, the faces split among the threads.
    parallel_for(m, kChunk, threads, [&](Eigen::Index first, Eigen::Index last) {
      for (Eigen::Index f = first; f < last; ++f) {
        const Eigen::Vector3d n = normals.row(f).transpose();
        Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
        for (const int* g = begin(f); g != end(f); ++g) {
          const Eigen::Vector3d ng = normals.row(*g).transpose();
          const double c = std::clamp(n.dot(ng), -1.0, 1.0);
          if (c >= cos_cone) moments.noalias() += weight(c) * ng * ng.transpose();
        }
        out.row(f) = target(f, moments);
      }
    });
    return out;
  }
  // Each pair once: the pair (f, g), f <= g, adds to f's moments and to
  // g's. f's terms still come in ascending order of the neighbour (those of
  // e < f when e was visited, then its own sweep), so every sum is the one
  // above, bit for bit, at half the acos and exp. On spare cores the pairs'
  // weights (the acos and exp, most of the time) are found block by block
  // beforehand, and this thread sums them in the same order.
  std::vector<Eigen::Matrix3d> moments(static_cast<size_t>(m), Eigen::Matrix3d::Zero());
  const auto pair_weight = [&](Eigen::Index f, int g) {
    const Eigen::Vector3d n = normals.row(f).transpose();
    const Eigen::Vector3d ng = normals.row(g).transpose();
    const double c = std::clamp(n.dot(ng), -1.0, 1.0);
    return c < cos_cone ? kOutsideCone : weight(c);
  };
  const auto add_pair = [&](Eigen::Index f, int g, double w) {
    if (w == kOutsideCone) return;
    const Eigen::Vector3d n = normals.row(f).transpose();
    const Eigen::Vector3d ng = normals.row(g).transpose();
    moments[static_cast<size_t>(f)].noalias() += w * ng * ng.transpose();
    if (g != f) moments[static_cast<size_t>(g)].noalias() += w * n * n.transpose();
  };
  const auto own_half = [&](Eigen::Index f) { return std::lower_bound(begin(f), end(f), static_cast<int>(f)); };
  const CoreLease lease(m > kChunk ? spare : nullptr, kMostLoopThreads - 1);
  if (lease.threads() == 1) {
    for (Eigen::Index f = 0; f < m; ++f)
      for (const int* g = own_half(f); g != end(f); ++g) add_pair(f, *g, pair_weight(f, *g));
  } else {
    std::vector<size_t> first_weight;
    std::vector<double> weights;
    for (Eigen::Index block = 0; block < m; block += kPairBlock) {
      const Eigen::Index block_end = std::min(m, block + kPairBlock);
      first_weight.assign(1, 0);
      for (Eigen::Index f = block; f < block_end; ++f)
        first_weight.push_back(first_weight.back() + static_cast<size_t>(end(f) - own_half(f)));
      weights.resize(first_weight.back());
      parallel_for(block_end - block, kChunk, lease.threads(), [&](Eigen::Index first, Eigen::Index last) {
        for (Eigen::Index k = first; k < last; ++k) {
          size_t at = first_weight[static_cast<size_t>(k)];
          for (const int* g = own_half(block + k); g != end(block + k); ++g) weights[at++] = pair_weight(block + k, *g);
        }
      });
      for (Eigen::Index f = block; f < block_end; ++f) {
        size_t at = first_weight[static_cast<size_t>(f - block)];
        for (const int* g = own_half(f); g != end(f); ++g) add_pair(f, *g, weights[at++]);
      }
    }
  }
  parallel_for(m, kChunk, threads, [&](Eigen::Index first, Eigen::Index last) {
    for (Eigen::Index f = first; f < last; ++f) out.row(f) = target(f, moments[static_cast<size_t>(f)]);
  });
  return out;
}

}  // namespace developable

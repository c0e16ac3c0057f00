#include "curve_search.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

namespace developable {

// Runs of kLeafArcs consecutive arcs (close on the sphere, so tight) form the
// leaves of a complete binary tree of bounding balls in heap order, built
// bottom-up (each parent encloses its two children). A query first scans the
// leaf reached by descending to the nearer child centre, then walks up to the
// root and searches each sibling subtree whose ball may hold a nearer point:
// every other leaf lies in exactly one of them, so the answer is exact, and a
// good first guess costs one ball test per level.

namespace {

struct Arc {
  Eigen::Vector3d a, m;   // start (unit), unit normal of the arc's plane (0 for a point)
  Eigen::Vector3d ua, ub;  // m x a and b x m: q is between the ends iff q.ua >= 0 and q.ub >= 0
  Eigen::Vector3d b;       // end (unit)
};

struct Ball {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = -1.0;  // < 0: empty (padding of the complete tree)
};

constexpr int kLeafArcs = 4;

struct ArcTree {
  std::vector<Arc> arcs;
  std::vector<Ball> balls;  // heap order: root 1, children 2i and 2i+1, leaves from `leaves`
  int leaves = 1;           // a power of two; leaf l holds arcs kLeafArcs * l ..
};

// How near q is to the arc, as the signed square c |c| of the cosine c of
// the angle to its nearest point (larger is nearer, no square root).
inline double nearness(const Arc& arc, const Eigen::Vector3d& q) {
  if (arc.m.squaredNorm() > 0.0 && q.dot(arc.ua) >= 0.0 && q.dot(arc.ub) >= 0.0) {
    const double h = q.dot(arc.m);
    return 1.0 - h * h;  // |q - (q.m) m|^2: the foot is inside the arc
  }
  const double c = std::max(q.dot(arc.a), q.dot(arc.b));
  return c * std::abs(c);
}

Eigen::Vector3d closest_point(const Arc& arc, const Eigen::Vector3d& q) {
  if (arc.m.squaredNorm() > 0.0 && q.dot(arc.ua) >= 0.0 && q.dot(arc.ub) >= 0.0) {
    const Eigen::Vector3d foot = q - q.dot(arc.m) * arc.m;
    const double len = foot.norm();
    if (len > 1e-300) return foot / len;
  }
  return q.dot(arc.a) >= q.dot(arc.b) ? arc.a : arc.b;
}

// Smallest ball holding both balls (either may be empty).
Ball enclose(const Ball& x, const Ball& y) {
  if (y.radius < 0.0) return x;
  if (x.radius < 0.0) return y;
  const double d = (y.center - x.center).norm();
  if (d + y.radius <= x.radius) return x;
  if (d + x.radius <= y.radius) return y;
  Ball ball;
  ball.radius = 0.5 * (d + x.radius + y.radius);
  ball.center = x.center + ((ball.radius - x.radius) / d) * (y.center - x.center);
  ball.radius += 1e-12;  // rounding of the centre
  return ball;
}

ArcTree build_tree(std::vector<Arc> arcs) {
  ArcTree tree;
  tree.arcs = std::move(arcs);
  const int count = static_cast<int>(tree.arcs.size());
  while (tree.leaves * kLeafArcs < count) tree.leaves *= 2;
  tree.balls.resize(2 * static_cast<size_t>(tree.leaves));
  for (int l = 0; l < tree.leaves; ++l) {
    const int begin = l * kLeafArcs, end = std::min(count, begin + kLeafArcs);
    if (begin >= end) continue;
    Eigen::Vector3d lo = tree.arcs[begin].a, hi = lo;
    double bulge = 0.0;
    for (int s = begin; s < end; ++s) {
      const Arc& arc = tree.arcs[s];
      lo = lo.cwiseMin(arc.a).cwiseMin(arc.b);
      hi = hi.cwiseMax(arc.a).cwiseMax(arc.b);
      // An arc leaves its chord by at most 1 - cos(half its angle).
      bulge = std::max(bulge, 1.0 - std::sqrt(std::max(0.0, 0.5 * (1.0 + arc.a.dot(arc.b)))));
    }
    Ball& ball = tree.balls[static_cast<size_t>(tree.leaves + l)];
    ball.center = 0.5 * (lo + hi);
    ball.radius = 0.0;
    for (int s = begin; s < end; ++s) {
      ball.radius = std::max({ball.radius, (tree.arcs[s].a - ball.center).norm(),
                              (tree.arcs[s].b - ball.center).norm()});
    }
    ball.radius += bulge + 1e-12;
  }
  for (int i = tree.leaves - 1; i >= 1; --i)
    tree.balls[static_cast<size_t>(i)] = enclose(tree.balls[2 * static_cast<size_t>(i)],
                                                 tree.balls[2 * static_cast<size_t>(i) + 1]);
  return tree;
}

// The best so far of one query: nearness, arc, and the chord length it means
// (chord^2 = 2 - 2 cos), which prunes balls.
struct Best {
  double nearness = -2.0;
  int arc = -1;
  double chord = 3.0;  // more than any chord of the unit sphere

  void update_chord() {
    const double c = std::copysign(std::sqrt(std::abs(nearness)), nearness);
    chord = std::sqrt(std::max(0.0, 2.0 - 2.0 * c));
  }
};

void scan_leaf(const ArcTree& tree, int leaf, const Eigen::Vector3d& q, Best& best) {
  const int begin = leaf * kLeafArcs;
  const int end = std::min(static_cast<int>(tree.arcs.size()), begin + kLeafArcs);
  const double before = best.nearness;
  for (int s = begin; s < end; ++s) {
    const double near = nearness(tree.arcs[s], q);
    if (near > best.nearness) {
      best.nearness = near;
      best.arc = s;
    }
  }
  if (best.nearness > before) best.update_chord();
}

// May the ball hold a point nearer than the best (in chord length)?
inline bool may_hold_nearer(const Ball& ball, const Eigen::Vector3d& q, const Best& best) {
  if (ball.radius < 0.0) return false;
  const double reach = ball.radius + best.chord;
  return (q - ball.center).squaredNorm() < reach * reach;
}

// Depth-first search of the subtree at `node`, nearer child first.
void search_subtree(const ArcTree& tree, int node, const Eigen::Vector3d& q, Best& best) {
  int stack[64];  // depth <= log2 of the node count, < 32
  int top = 0;
  stack[top++] = node;
  while (top > 0) {
    const int i = stack[--top];
    if (!may_hold_nearer(tree.balls[static_cast<size_t>(i)], q, best)) continue;
    if (i >= tree.leaves) {
      scan_leaf(tree, i - tree.leaves, q, best);
      continue;
    }
    const double dl = (q - tree.balls[2 * static_cast<size_t>(i)].center).squaredNorm();
    const double dr = (q - tree.balls[2 * static_cast<size_t>(i) + 1].center).squaredNorm();
    // Push the farther child first so the nearer one is searched first.
    stack[top++] = dl <= dr ? 2 * i + 1 : 2 * i;
    stack[top++] = dl <= dr ? 2 * i : 2 * i + 1;
  }
}

// Targets of rows begin .. end-1 (unit queries already checked finite).
void nearest_rows(const Normals& normals, const ArcTree& tree, Eigen::Index begin, Eigen::Index end,
                  Normals& targets) {
  for (Eigen::Index i = begin; i < end; ++i) {
    const Eigen::Vector3d n = normals.row(i).transpose();
    const double len = n.norm();
    if (!(len > 0.0)) {
      targets.row(i) = tree.arcs.front().a.transpose();
      continue;
    }
    const Eigen::Vector3d q = n / len;
    // First guess: down from the root to the nearer child centre.
    int node = 1;
    while (node < tree.leaves) {
      const Ball& left = tree.balls[2 * static_cast<size_t>(node)];
      const Ball& right = tree.balls[2 * static_cast<size_t>(node) + 1];
      node = right.radius >= 0.0 && (left.radius < 0.0 || (q - right.center).squaredNorm() <
                                                               (q - left.center).squaredNorm())
                 ? 2 * node + 1
                 : 2 * node;
    }
    Best best;
    scan_leaf(tree, node - tree.leaves, q, best);
    for (; node > 1; node /= 2) search_subtree(tree, node ^ 1, q, best);
    targets.row(i) = closest_point(tree.arcs[static_cast<size_t>(best.arc)], q).transpose();
  }
}

// Targets of all rows, over a few threads for large inputs.
Normals nearest_on_curves(const Normals& normals, const ArcTree& tree) {
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    if (!normals.row(i).allFinite()) {
      throw EngineError(Status::invalid_argument, "nearest on curves: normal " + std::to_string(i) + " is not finite");
    }
  }
  Normals targets(normals.rows(), 3);
  // Fixed chunks, independent of the thread count.
  constexpr Eigen::Index kChunk = 8192;
  const Eigen::Index chunks = (normals.rows() + kChunk - 1) / kChunk;
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  const int workers = static_cast<int>(std::min<Eigen::Index>(std::min(hardware, 8u), chunks));
  std::atomic<Eigen::Index> next{0};
  auto work = [&]() {
    for (Eigen::Index k = next++; k < chunks; k = next++) {
      nearest_rows(normals, tree, k * kChunk, std::min(normals.rows(), (k + 1) * kChunk), targets);
    }
  };
  if (workers <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    try {
      for (int t = 1; t < workers; ++t) pool.emplace_back(work);
    } catch (...) {
      // Could not start a thread: the ones that did, and this one, finish the work.
    }
    work();
    for (auto& t : pool) t.join();
  }
  return targets;
}

}  // namespace

struct CurveSearch::Tree {
  ArcTree tree;
};

CurveSearch::CurveSearch(const std::vector<SphereCurve>& curves) {
  if (curves.empty()) throw EngineError(Status::invalid_argument, "nearest on curves: no curve");
  std::vector<Arc> arcs;
  auto point_arc = [](const Eigen::Vector3d& p) {
    return Arc{p, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), p};
  };
  for (size_t c = 0; c < curves.size(); ++c) {
    const auto& pts = curves[c].points;
    if (pts.empty()) {
      throw EngineError(Status::invalid_argument, "nearest on curves: curve " + std::to_string(c) + " is empty");
    }
    std::vector<Eigen::Vector3d> unit;
    for (const auto& p : pts) {
      const double len = p.norm();
      if (!p.allFinite() || !(len > 0.0)) {
        throw EngineError(Status::invalid_argument,
                          "nearest on curves: curve " + std::to_string(c) + " has a zero or non-finite point");
      }
      unit.push_back(p / len);
    }
    const size_t n = unit.size();
    if (n == 1) {
      arcs.push_back(point_arc(unit[0]));
      continue;
    }
    const size_t segs = (curves[c].closed && n > 2) ? n : n - 1;
    for (size_t s = 0; s < segs; ++s) {
      const Eigen::Vector3d& a = unit[s];
      const Eigen::Vector3d& b = unit[(s + 1) % n];
      const Eigen::Vector3d m = a.cross(b);
      // Coincident or far-apart (>= 90 degrees) ends: keep just the ends.
      if (m.norm() < 1e-12 || a.dot(b) <= 0.0) {
        arcs.push_back({a, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), b});
        continue;
      }
      const Eigen::Vector3d mu = m.normalized();
      arcs.push_back({a, mu, mu.cross(a), b.cross(mu), b});
    }
  }
  tree_ = std::make_shared<const Tree>(Tree{build_tree(std::move(arcs))});
}

Normals CurveSearch::nearest(const Normals& normals) const {
  if (!tree_) throw EngineError(Status::invalid_argument, "nearest on curves: no curve");
  return nearest_on_curves(normals, tree_->tree);
}

}  // namespace developable

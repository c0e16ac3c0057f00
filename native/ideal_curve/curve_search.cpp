#include "ideal_curve/curve_search.h"

#include "core/concurrent_jobs.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace developable {

// Runs of kLeafArcs consecutive arcs (close on the sphere, so tight) form the
// leaves of a complete binary tree of bounding balls in heap order, built
// bottom-up (each parent encloses its two children). A query first scans the
// leaf of its hint (the same face's answer an iteration ago, usually still
// the answer) or else the leaf reached by descending to the nearer child
// centre, then walks up to the
// root and searches each sibling subtree whose ball may hold a nearer point:
// every other leaf lies in exactly one of them, so the answer is exact, and a
// good first guess costs one ball test per level.

namespace {

struct Arc {
  Eigen::Vector3d a, m;    // start (unit), unit normal of the arc's plane (0 for a point)
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
  // Per node: a lower bound on the distance from its ball's centre to any arc
  // outside its subtree (see nearest_rows).
  std::vector<double> clearance;
  int leaves = 1;  // a power of two; leaf l holds arcs kLeafArcs * l ..
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

// Depth of a heap-order node (the root is 1, at depth 0).
int depth_of(int node) { return 31 - __builtin_clz(static_cast<unsigned>(node)); }

// Lower bound on the distance from the centre c of node's ball to the arcs
// outside node's subtree, by a search of the rest of the tree that starts
// from the arcs just before and after the subtree's (usually the nearest
// outside ones: the curve continues there). The nearest point of an arc to c
// (|c| <= 1) is its nearest point to c / |c|, at distance^2 = |c|^2 + 1 -
// 2 |c| cos(angle).
double clearance_of(const ArcTree& tree, int node) {
  const Eigen::Vector3d& c = tree.balls[static_cast<size_t>(node)].center;
  const double length = c.norm();
  const Eigen::Vector3d direction = length > 0.0 ? Eigen::Vector3d(c / length) : Eigen::Vector3d::UnitZ();
  auto distance2 = [&](int arc) {
    const double near = nearness(tree.arcs[static_cast<size_t>(arc)], direction);
    const double cosine = std::copysign(std::sqrt(std::abs(near)), near);
    return std::max(0.0, length * length + 1.0 - 2.0 * length * cosine);
  };
  const int node_depth = depth_of(node);
  const int shift = depth_of(tree.leaves) - node_depth;  // node's leaves: node << shift ..
  const int arc_count = static_cast<int>(tree.arcs.size());
  const int first_arc = ((node << shift) - tree.leaves) * kLeafArcs;
  const int end_arc = std::min(arc_count, (((node + 1) << shift) - tree.leaves) * kLeafArcs);
  double best2 = INFINITY;
  if (first_arc > 0) best2 = std::min(best2, distance2(first_arc - 1));
  if (end_arc < arc_count) best2 = std::min(best2, distance2(end_arc));
  int stack[64];
  int top = 0;
  stack[top++] = 1;
  while (top > 0) {
    const int w = stack[--top];
    const Ball& ball = tree.balls[static_cast<size_t>(w)];
    if (ball.radius < 0.0) continue;
    const int below = depth_of(w) - node_depth;
    if (below >= 0 && (w >> below) == node) continue;  // inside node's subtree
    const double gap = (c - ball.center).norm() - ball.radius;
    if (gap > 0.0 && gap * gap >= best2) continue;
    if (w < tree.leaves) {
      // Nearer child on top of the stack.
      const bool left_nearer = (c - tree.balls[2 * static_cast<size_t>(w)].center).squaredNorm() <=
                               (c - tree.balls[2 * static_cast<size_t>(w) + 1].center).squaredNorm();
      stack[top++] = left_nearer ? 2 * w + 1 : 2 * w;
      stack[top++] = left_nearer ? 2 * w : 2 * w + 1;
      continue;
    }
    const int begin = (w - tree.leaves) * kLeafArcs;
    const int end = std::min(arc_count, begin + kLeafArcs);
    for (int s = begin; s < end; ++s) best2 = std::min(best2, distance2(s));
  }
  // Less a margin for the rounding of the distances compared against it.
  return std::isfinite(best2) ? std::sqrt(best2) - 1e-9 : INFINITY;
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
      ball.radius =
          std::max({ball.radius, (tree.arcs[s].a - ball.center).norm(), (tree.arcs[s].b - ball.center).norm()});
    }
    ball.radius += bulge + 1e-12;
  }
  for (int i = tree.leaves - 1; i >= 1; --i)
    tree.balls[static_cast<size_t>(i)] =
        enclose(tree.balls[2 * static_cast<size_t>(i)], tree.balls[2 * static_cast<size_t>(i) + 1]);
  tree.clearance.assign(tree.balls.size(), 0.0);
  for (int i = 1; i < 2 * tree.leaves; ++i)
    if (tree.balls[static_cast<size_t>(i)].radius >= 0.0)
      tree.clearance[static_cast<size_t>(i)] = clearance_of(tree, i);
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
// hints: null, or one arc per row where the search starts, replaced by the
// row's answer.
void nearest_rows(const Normals& normals, const ArcTree& tree, Eigen::Index begin, Eigen::Index end, Normals& targets,
                  int* hints) {
  for (Eigen::Index i = begin; i < end; ++i) {
    const Eigen::Vector3d n = normals.row(i).transpose();
    const double len = n.norm();
    if (!(len > 0.0)) {
      targets.row(i) = tree.arcs.front().a.transpose();
      continue;
    }
    const Eigen::Vector3d q = n / len;
    // First guess: the hinted arc's leaf, else down from the root to the
    // nearer child centre.
    const int arc_count = static_cast<int>(tree.arcs.size());
    int node = 1;
    if (hints != nullptr && hints[i] >= 0 && hints[i] < arc_count) node = tree.leaves + hints[i] / kLeafArcs;
    while (node < tree.leaves) {
      const Ball& left = tree.balls[2 * static_cast<size_t>(node)];
      const Ball& right = tree.balls[2 * static_cast<size_t>(node) + 1];
      node = right.radius >= 0.0 &&
                     (left.radius < 0.0 || (q - right.center).squaredNorm() < (q - left.center).squaredNorm())
                 ? 2 * node + 1
                 : 2 * node;
    }
    Best best;
    scan_leaf(tree, node - tree.leaves, q, best);
    for (; node > 1; node /= 2) {
      // Every arc of node's subtree has been considered. No arc outside it
      // is nearer than the best when the ball of radius best.chord about q
      // lies within node's clearance: the search is over.
      const double room = tree.clearance[static_cast<size_t>(node)] - best.chord;
      if (room > 0.0 && (q - tree.balls[static_cast<size_t>(node)].center).squaredNorm() < room * room) break;
      search_subtree(tree, node ^ 1, q, best);
    }
    targets.row(i) = closest_point(tree.arcs[static_cast<size_t>(best.arc)], q).transpose();
    if (hints != nullptr) hints[i] = best.arc;
  }
}

// Targets of all rows, over a few threads for large inputs.
Normals nearest_on_curves(const Normals& normals, const ArcTree& tree, std::vector<int>* hints, int threads) {
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    if (!normals.row(i).allFinite()) {
      throw EngineError(Status::invalid_argument, "nearest on curves: normal " + std::to_string(i) + " is not finite");
    }
  }
  Normals targets(normals.rows(), 3);
  if (hints != nullptr && static_cast<Eigen::Index>(hints->size()) != normals.rows())
    hints->assign(static_cast<size_t>(normals.rows()), -1);
  int* const hint = hints != nullptr ? hints->data() : nullptr;
  parallel_for(normals.rows(), 8192, threads,
               [&](Eigen::Index begin, Eigen::Index end) { nearest_rows(normals, tree, begin, end, targets, hint); });
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

Normals CurveSearch::nearest(const Normals& normals, std::vector<int>* hints, int threads) const {
  if (!tree_) throw EngineError(Status::invalid_argument, "nearest on curves: no curve");
  return nearest_on_curves(normals, tree_->tree, hints, threads);
}

}  // namespace developable

#include "segmentation/crease_pieces.h"

#include "core/cone_fit.h"
#include "core/measures.h"
#include "core/union_find.h"
#include "segmentation/crease_lines.h"
#include "segmentation/crease_strength.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace developable {
namespace {

// Pieces under this share of the faces join a neighbour too.
constexpr double kMinPieceShare = 0.005;
// A border face moves to a neighbouring piece whose cone is nearer its normal
// than this share of its angle to its own piece's cone.
constexpr double kBetterCone = 0.5;
constexpr int kBorderRounds = 5;

// Renumbers labels 0 .. count-1 in the order of each label's first face;
// returns count.
int renumber(std::vector<int>& ids) {
  std::map<int, int> order;
  for (int& id : ids) id = order.emplace(id, static_cast<int>(order.size())).first->second;
  return static_cast<int>(order.size());
}

// The faces joined across the interior edges where `joined` holds.
template <typename Joined>
std::vector<int> components(Eigen::Index faces, const std::vector<MeshEdge>& edges, Joined joined) {
  UnionFind pieces(static_cast<size_t>(faces));
  for (size_t e = 0; e < edges.size(); ++e)
    if (edges[e].g >= 0 && joined(e)) pieces.unite(edges[e].f, edges[e].g);
  std::vector<int> ids(static_cast<size_t>(faces));
  for (size_t f = 0; f < ids.size(); ++f) ids[f] = pieces.find(static_cast<int>(f));
  renumber(ids);
  return ids;
}

// Per pair of neighbouring pieces (lower id first), how many edges they share.
std::map<std::pair<int, int>, int> borders(const std::vector<int>& ids, const std::vector<MeshEdge>& edges) {
  std::map<std::pair<int, int>, int> shared;
  for (const MeshEdge& e : edges) {
    if (e.g < 0) continue;
    const int p = ids[static_cast<size_t>(e.f)], q = ids[static_cast<size_t>(e.g)];
    if (p != q) ++shared[{std::min(p, q), std::max(p, q)}];
  }
  return shared;
}

// Step 1: the smallest piece under `min_faces` joins the neighbour it shares
// most edges with (the lower id on a tie), until none is left that has a
// neighbour.
int merge_small(std::vector<int>& ids, const std::vector<MeshEdge>& edges, int min_faces) {
  int count = renumber(ids);
  while (true) {
    std::vector<int> size(static_cast<size_t>(count), 0);
    for (int id : ids) ++size[static_cast<size_t>(id)];
    const auto shared = borders(ids, edges);
    int smallest = -1, host = -1;
    for (int p = 0; p < count; ++p) {
      if (size[static_cast<size_t>(p)] >= min_faces) continue;
      if (smallest >= 0 && size[static_cast<size_t>(p)] >= size[static_cast<size_t>(smallest)]) continue;
      int best = -1, most = 0;
      for (const auto& [pair, n] : shared) {
        const int other = pair.first == p ? pair.second : pair.second == p ? pair.first : -1;
        if (other >= 0 && (n > most || (n == most && other < best))) {
          best = other;
          most = n;
        }
      }
      if (best >= 0) {
        smallest = p;
        host = best;
      }
    }
    if (smallest < 0) return count;
    for (int& id : ids)
      if (id == smallest) id = host;
    count = renumber(ids);
  }
}

// The area-weighted cone of each piece's normals.
std::vector<Cone> piece_cones(const std::vector<int>& ids, int count, const Normals& normals,
                              const Eigen::VectorXd& areas) {
  std::vector<NormalMoments> moments(static_cast<size_t>(count));
  for (size_t f = 0; f < ids.size(); ++f)
    moments[static_cast<size_t>(ids[f])].add(normals.row(static_cast<Eigen::Index>(f)).transpose(),
                                             areas[static_cast<Eigen::Index>(f)]);
  std::vector<Cone> cones;
  for (const NormalMoments& m : moments) cones.push_back(fit_cone(m).cone);
  return cones;
}

// Steps 2 and 4: faces on a border moved to the neighbouring piece whose cone
// fits them much better, all at once, for at most kBorderRounds rounds.
void settle_borders(std::vector<int>& ids, int count, const Normals& normals, const Eigen::VectorXd& areas,
                    const std::vector<MeshEdge>& edges) {
  for (int round = 0; round < kBorderRounds; ++round) {
    const std::vector<Cone> cones = piece_cones(ids, count, normals, areas);
    const auto angle = [&](int f, int piece) {
      return angle_to_cone(cones[static_cast<size_t>(piece)], normals.row(f).transpose());
    };
    std::map<int, std::pair<int, double>> moves;  // face -> (piece, its angle to that piece's cone)
    for (const MeshEdge& e : edges) {
      if (e.g < 0 || ids[static_cast<size_t>(e.f)] == ids[static_cast<size_t>(e.g)]) continue;
      for (const auto& [face, across] : {std::make_pair(e.f, e.g), std::make_pair(e.g, e.f)}) {
        const int there = ids[static_cast<size_t>(across)];
        const double own = angle(face, ids[static_cast<size_t>(face)]), other = angle(face, there);
        if (!(other < kBetterCone * own)) continue;
        auto [it, fresh] = moves.emplace(face, std::make_pair(there, other));
        if (!fresh && other < it->second.second) it->second = {there, other};
      }
    }
    if (moves.empty()) return;
    for (const auto& [face, move] : moves) ids[static_cast<size_t>(face)] = move.first;
  }
}

// How well a set of faces fits one cone: the RMS angle (rad) of their normals
// to it, and that over the RMS the noise would give (fit, crease_pieces.h).
struct ConeMisfit {
  double rms = 0.0, fit = 0.0;
  double squares = 0.0,
         expected = 0.0;  // area-weighted sums of the squared angles and of their variances per unit noise
};

class Misfits {
 public:
  Misfits(const Positions& positions, const Triangles& triangles, const Normals& normals, const Eigen::VectorXd& areas,
          double noise)
      : normals_(normals), areas_(areas), noise_(noise), gradients_(static_cast<size_t>(triangles.rows())) {
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
      gradients_[static_cast<size_t>(f)] = barycentric_gradients(positions, triangles, f);
  }

  ConeMisfit of(const std::vector<int>& faces) const {
    NormalMoments moments;
    for (int f : faces) moments.add(normals_.row(f).transpose(), areas_[f]);
    const Cone cone = fit_cone(moments).cone;
    double squares = 0.0, expected = 0.0, area = 0.0;
    for (int f : faces) {
      const double a = areas_[f];
      if (!(a > 0.0)) continue;
      const Eigen::Vector3d n = normals_.row(f).transpose();
      const double angle = angle_to_cone(cone, n);
      // The direction in which the normal leaves the cone's circle.
      const Eigen::Vector3d off = n.cross(cone.axis.cross(n));
      const Eigen::Matrix3d& g = gradients_[static_cast<size_t>(f)];
      const double variance = off.norm() > 1e-12 ? (g.transpose() * off.normalized()).squaredNorm()
                                                 : g.squaredNorm() / 2.0;  // a plane: any direction
      squares += a * angle * angle;
      expected += a * variance;
      area += a;
    }
    ConeMisfit m;
    m.squares = squares;
    m.expected = expected;
    if (!(area > 0.0)) return m;
    m.rms = std::sqrt(squares / area);
    m.fit = expected > 0.0 ? std::sqrt(squares / (noise_ * noise_ * expected)) : 0.0;
    return m;
  }

 private:
  const Normals& normals_;
  const Eigen::VectorXd& areas_;
  double noise_;
  std::vector<Eigen::Matrix3d> gradients_;
};

std::vector<std::vector<int>> faces_by_piece(const std::vector<int>& ids, int count) {
  std::vector<std::vector<int>> faces(static_cast<size_t>(count));
  for (size_t f = 0; f < ids.size(); ++f) faces[static_cast<size_t>(ids[f])].push_back(static_cast<int>(f));
  return faces;
}

// Step 3: of the neighbouring pairs whose union fits one cone (kSameCone,
// kCreasePieceFit), the one whose union grows its RMS least is merged, until
// none is left.
int merge_same_cones(std::vector<int>& ids, int count, const std::vector<MeshEdge>& edges, const Eigen::VectorXd& areas,
                     const Misfits& misfits) {
  while (count > 1) {
    const std::vector<std::vector<int>> faces = faces_by_piece(ids, count);
    std::vector<double> rms, area;
    for (const auto& members : faces) {
      rms.push_back(misfits.of(members).rms);
      double sum = 0.0;
      for (int f : members) sum += areas[f];
      area.push_back(sum);
    }
    double best = kSameCone;
    std::pair<int, int> chosen{-1, -1};
    for (const auto& entry : borders(ids, edges)) {
      const auto [p, q] = entry.first;
      std::vector<int> both = faces[static_cast<size_t>(p)];
      both.insert(both.end(), faces[static_cast<size_t>(q)].begin(), faces[static_cast<size_t>(q)].end());
      const ConeMisfit united = misfits.of(both);
      const double pooled =
          std::sqrt((area[static_cast<size_t>(p)] * rms[static_cast<size_t>(p)] * rms[static_cast<size_t>(p)] +
                     area[static_cast<size_t>(q)] * rms[static_cast<size_t>(q)] * rms[static_cast<size_t>(q)]) /
                    (area[static_cast<size_t>(p)] + area[static_cast<size_t>(q)]));
      const double growth = united.rms / std::max(pooled, 1e-12);
      if (growth <= best && united.fit <= kCreasePieceFit) {
        best = growth;
        chosen = {p, q};
      }
    }
    if (chosen.first < 0) return count;
    for (int& id : ids)
      if (id == chosen.second) id = chosen.first;
    count = renumber(ids);
  }
  return count;
}

// plane_parting's search: directions of the planes over a hemisphere, and
// offsets along each.
constexpr int kPartingDirections = 128;
constexpr int kPartingOffsets = 64;

// Unit directions spread evenly over a hemisphere (a Fibonacci lattice): a
// plane and its opposite are one.
std::vector<Eigen::Vector3d> hemisphere_directions(int count) {
  std::vector<Eigen::Vector3d> directions;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - (k + 0.5) / count;  // (0, 1)
    const double r = std::sqrt(1.0 - z * z);
    directions.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  return directions;
}

// The fine search about the best lattice direction: directions within half
// the lattice's spacing on a grid of (2 kFineSteps + 1)^2, each at
// kFineOffsets offsets.
constexpr int kFineSteps = 4;
constexpr int kFineOffsets = 256;

// A plane across a piece: the faces whose centroids fall in `slab` or a
// later one of `slabs` even slabs of [lo, hi] along `direction` lie beyond
// it; `residual` is the summed fit_cone residual of the two sides.
struct Cut {
  double residual = std::numeric_limits<double>::infinity();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double lo = 0.0, hi = 0.0;
  int slabs = 1, slab = 0;

  int slab_of(const Eigen::Vector3d& centroid) const {
    return std::min(slabs - 1, static_cast<int>((direction.dot(centroid) - lo) / (hi - lo) * slabs));
  }
  bool side(const Eigen::Vector3d& centroid) const { return slab_of(centroid) >= slab; }
};

// The lower residual; the first on a tie (deterministic).
Cut better(const Cut& a, const Cut& b) { return b.residual < a.residual ? b : a; }

// The best of the `slabs` - 1 planes across the faces along `direction`
// leaving both sides min_faces faces (residual infinite when none does).
Cut best_cut_along(const Eigen::Vector3d& direction, int slabs, const std::vector<Eigen::Vector3d>& centroids,
                   const std::vector<int>& faces, const Normals& normals, const Eigen::VectorXd& areas, int min_faces) {
  Cut cut;
  cut.direction = direction;
  cut.slabs = slabs;
  cut.lo = std::numeric_limits<double>::infinity();
  cut.hi = -cut.lo;
  for (const Eigen::Vector3d& c : centroids) {
    const double height = direction.dot(c);
    cut.lo = std::min(cut.lo, height);
    cut.hi = std::max(cut.hi, height);
  }
  if (!(cut.hi > cut.lo)) return cut;
  // The faces' moments per slab, then summed from either end.
  const size_t count = static_cast<size_t>(slabs);
  std::vector<NormalMoments> slab(count), below(count + 1), above(count + 1);
  std::vector<int> in_slab(count, 0), count_below(count + 1, 0);
  for (size_t k = 0; k < centroids.size(); ++k) {
    const size_t s = static_cast<size_t>(cut.slab_of(centroids[k]));
    slab[s].add(normals.row(faces[k]).transpose(), areas[faces[k]]);
    ++in_slab[s];
  }
  for (size_t s = 0; s < count; ++s) {
    below[s + 1] = below[s];
    below[s + 1] += slab[s];
    count_below[s + 1] = count_below[s] + in_slab[s];
  }
  for (size_t s = count; s-- > 0;) {
    above[s] = above[s + 1];
    above[s] += slab[s];
  }
  const int n = static_cast<int>(centroids.size());
  for (size_t s = 1; s < count; ++s) {
    if (count_below[s] < min_faces || n - count_below[s] < min_faces) continue;
    const double residual = fit_cone(below[s]).residual + fit_cone(above[s]).residual;
    if (residual < cut.residual) {
      cut.residual = residual;
      cut.slab = static_cast<int>(s);
    }
  }
  return cut;
}

// Step 5: the worst-fitting piece above kCreasePieceFit is parted
// (plane_parting) when both parts fit their cones better than it fits its
// own, until every piece fits, no parting helps or kMostPartings were made.
// Returns the count of pieces.
int part_misfits(std::vector<int>& ids, int count, const Positions& positions, const Triangles& triangles,
                 const Normals& normals, const Eigen::VectorXd& areas, const Misfits& misfits, int min_faces) {
  // Each piece's faces (ascending, as faces_by_piece lists them) and fit,
  // kept up to date across partings rather than recomputed for every piece.
  std::vector<std::vector<int>> faces = faces_by_piece(ids, count);
  std::vector<double> fit;
  for (const auto& members : faces) fit.push_back(misfits.of(members).fit);
  std::vector<bool> tried(static_cast<size_t>(count), false);
  for (int partings = 0; partings < kMostPartings;) {
    int worst = -1;
    for (size_t p = 0; p < faces.size(); ++p)
      if (!tried[p] && fit[p] > (worst < 0 ? kCreasePieceFit : fit[static_cast<size_t>(worst)]))
        worst = static_cast<int>(p);
    if (worst < 0) break;
    const size_t w = static_cast<size_t>(worst);
    tried[w] = true;
    const std::vector<bool> beyond = plane_parting(faces[w], positions, triangles, normals, areas, min_faces);
    if (beyond.empty()) continue;
    std::vector<int> near, far;
    for (size_t k = 0; k < faces[w].size(); ++k) (beyond[k] ? far : near).push_back(faces[w][k]);
    const double near_fit = misfits.of(near).fit, far_fit = misfits.of(far).fit;
    if (!(near_fit < fit[w] && far_fit < fit[w])) continue;
    for (int f : far) ids[static_cast<size_t>(f)] = count;
    ++count;
    faces[w] = std::move(near);
    fit[w] = near_fit;
    tried[w] = false;  // each part may be parted again
    faces.push_back(std::move(far));
    fit.push_back(far_fit);
    tried.push_back(false);
    ++partings;
  }
  return count;
}

}  // namespace

std::vector<bool> plane_parting(const std::vector<int>& faces, const Positions& positions, const Triangles& triangles,
                                const Normals& normals, const Eigen::VectorXd& areas, int min_faces) {
  const size_t n = faces.size();
  std::vector<Eigen::Vector3d> centroids(n);
  for (size_t k = 0; k < n; ++k) centroids[k] = face_centroid(positions, triangles, faces[k]);
  Cut best;
  for (const Eigen::Vector3d& d : hemisphere_directions(kPartingDirections))
    best = better(best, best_cut_along(d, kPartingOffsets, centroids, faces, normals, areas, min_faces));
  if (!std::isfinite(best.residual)) return {};
  // Then finer, about the best direction: the lattice's directions are
  // about `spacing` apart (its cells' area, 2 pi / count, square-rooted), and
  // at that a plane is a face off on a mitre's sides.
  const double spacing = std::sqrt(2.0 * M_PI / kPartingDirections);
  const Eigen::Vector3d coarse = best.direction;
  const Eigen::Vector3d u = coarse.unitOrthogonal(), v = coarse.cross(u);
  for (int i = -kFineSteps; i <= kFineSteps; ++i)
    for (int j = -kFineSteps; j <= kFineSteps; ++j) {
      const double step = spacing / (2 * kFineSteps);
      const Eigen::Vector3d d = (coarse + i * step * u + j * step * v).normalized();
      best = better(best, best_cut_along(d, kFineOffsets, centroids, faces, normals, areas, min_faces));
    }
  std::vector<bool> beyond(n);
  for (size_t k = 0; k < n; ++k) beyond[k] = best.side(centroids[k]);
  return beyond;
}

CreasePieces crease_pieces(const Positions& positions, const Triangles& triangles, const Normals& normals,
                           const Eigen::VectorXd& areas, const VertexFaces& connectivity, int threads) {
  CreasePieces out;
  const Eigen::Index faces = triangles.rows();
  if (faces == 0) return out;
  const std::vector<MeshEdge> edges = mesh_edges(triangles, connectivity);
  const CreaseStrengths strengths = crease_strengths(positions, triangles, normals, connectivity, edges, threads);
  out.noise = strengths.noise;
  out.cut = crease_lines(positions, triangles, normals, connectivity, edges, strengths);
  const int min_faces = std::max(kMinPieceFaces, static_cast<int>(kMinPieceShare * static_cast<double>(faces)));
  out.ids = components(faces, edges, [&](size_t e) { return !out.cut[e]; });
  int count = merge_small(out.ids, edges, min_faces);
  const Misfits misfits(positions, triangles, normals, areas, strengths.noise);
  settle_borders(out.ids, count, normals, areas, edges);
  count = merge_same_cones(out.ids, renumber(out.ids), edges, areas, misfits);
  settle_borders(out.ids, count, normals, areas, edges);
  if (count >= 2) {
    count = part_misfits(out.ids, count, positions, triangles, normals, areas, misfits, min_faces);
    settle_borders(out.ids, count, normals, areas, edges);
  }
  // Moved faces may have left a piece in parts: each part its own, small
  // ones joined to a neighbour.
  const std::vector<int> settled = out.ids;
  out.ids = components(faces, edges, [&](size_t e) {
    return settled[static_cast<size_t>(edges[e].f)] == settled[static_cast<size_t>(edges[e].g)];
  });
  out.count = merge_small(out.ids, edges, min_faces);
  double squares = 0.0, expected = 0.0;
  for (const auto& members : faces_by_piece(out.ids, out.count)) {
    const ConeMisfit m = misfits.of(members);
    out.fit.push_back(m.fit);
    squares += m.squares;
    expected += m.expected;
  }
  out.cone_noise = expected > 0.0 ? std::sqrt(squares / expected) : 0.0;
  return out;
}

}  // namespace developable

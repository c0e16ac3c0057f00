#include "segmentation/crease_pieces.h"

#include "core/cone_fit.h"
#include "core/union_find.h"
#include "segmentation/crease_lines.h"
#include "segmentation/crease_strength.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
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

}  // namespace

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

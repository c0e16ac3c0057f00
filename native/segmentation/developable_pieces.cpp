#include "segmentation/developable_pieces.h"

#include "core/union_find.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace developable {

namespace {

// Whether an interior vertex that is flat lies on a cut all the same: where
// a mitre's two cylinders are tangent, the ring vertex between its curved
// neighbours has no defect. Such a gap is a flat interior vertex whose
// curved neighbours fall into two or more runs around it (not joined by an
// edge of its faces); the flat vertices beside a cut see one run.
bool flat_gap(Eigen::Index v, const Triangles& triangles, const VertexFaces& connectivity,
              const std::vector<bool>& curved) {
  std::vector<int> neighbours;
  for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f)
    for (int c = 0; c < 3; ++c)
      if (triangles(*f, c) != v && curved[static_cast<size_t>(triangles(*f, c))])
        neighbours.push_back(triangles(*f, c));
  std::sort(neighbours.begin(), neighbours.end());
  neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  if (neighbours.size() < 2) return false;
  const auto index = [&](int w) {
    return static_cast<int>(std::lower_bound(neighbours.begin(), neighbours.end(), w) - neighbours.begin());
  };
  UnionFind runs(neighbours.size());
  size_t count = neighbours.size();
  for (const int* f = connectivity.begin(v); f != connectivity.end(v); ++f) {
    int others[2], k = 0;
    for (int c = 0; c < 3; ++c)
      if (triangles(*f, c) != v) others[k++] = triangles(*f, c);
    if (curved[static_cast<size_t>(others[0])] && curved[static_cast<size_t>(others[1])] &&
        runs.unite(index(others[0]), index(others[1])))
      --count;
  }
  return count >= 2;
}

// The faces of a mesh joined into pieces across every edge that is not cut.
class PieceCutter {
 public:
  PieceCutter(const Triangles& triangles, const VertexFaces& connectivity, const std::vector<bool>& interior,
              std::vector<bool> curved)
      : triangles_(triangles),
        connectivity_(connectivity),
        interior_(interior),
        curved_(std::move(curved)),
        on_cut_(curved_),
        pieces_(static_cast<size_t>(triangles.rows())) {
    for (Eigen::Index v = 0; v < connectivity.vertex_count(); ++v)
      if (interior_[static_cast<size_t>(v)] && !curved_[static_cast<size_t>(v)])
        on_cut_[static_cast<size_t>(v)] = flat_gap(v, triangles, connectivity, curved_);
    join_uncut_edges();
  }

  // Not every flat vertex between two runs of curved ones is on a cut: the
  // neighbours of a true gap see its two runs too, and so do the flat middle
  // vertices of a strip one row wide between two cuts. The faces of pieces
  // with nothing strictly inside rejoin across the gaps' edges: first with
  // each other (the strip becomes one piece, the faces around a gap one),
  // then each such piece with the first piece across its gaps' edges that
  // has something inside, unless that would leave a curved vertex with all
  // its faces in the two (the strip beside a gap, which must stay apart).
  void rejoin_gaps() {
    std::vector<bool> inside = pieces_with_inside(true);
    for (const auto& [f, g] : gap_edges_) {
      const int pf = pieces_.find(f), pg = pieces_.find(g);
      if (!inside[static_cast<size_t>(pf)] && !inside[static_cast<size_t>(pg)]) pieces_.unite(pf, pg);
    }
    inside = pieces_with_inside(true);
    std::map<int, std::vector<int>> hosts;  // per root without inside: pieces with one, in edge order
    for (const auto& [f, g] : gap_edges_) {
      const int pf = pieces_.find(f), pg = pieces_.find(g);
      if (!inside[static_cast<size_t>(pf)] && inside[static_cast<size_t>(pg)]) hosts[pf].push_back(pg);
      if (!inside[static_cast<size_t>(pg)] && inside[static_cast<size_t>(pf)]) hosts[pg].push_back(pf);
    }
    std::map<int, std::vector<int>> curved_of;                         // the curved vertices of each of those roots
    std::vector<int> root_of(static_cast<size_t>(triangles_.rows()));  // the roots before any joining below
    for (Eigen::Index f = 0; f < triangles_.rows(); ++f) {
      const int root = root_of[static_cast<size_t>(f)] = pieces_.find(static_cast<int>(f));
      if (hosts.count(root) == 0) continue;
      for (int c = 0; c < 3; ++c)
        if (curved_[static_cast<size_t>(triangles_(f, c))]) curved_of[root].push_back(triangles_(f, c));
    }
    for (const auto& [piece, candidates] : hosts) {
      for (int host : candidates) {
        bool keeps_cuts = true;
        for (int v : curved_of[piece]) {
          bool within = true;
          for (const int* f = connectivity_.begin(v); f != connectivity_.end(v) && within; ++f)
            within = root_of[static_cast<size_t>(*f)] == piece || root_of[static_cast<size_t>(*f)] == host;
          keeps_cuts = keeps_cuts && !within;
        }
        if (keeps_cuts) {
          pieces_.unite(piece, host);
          break;
        }
      }
    }
  }

  // A piece id per face, numbered in face order, when every piece has an
  // inside vertex and no curved vertex is inside a piece; else none.
  std::optional<std::vector<int>> labels() {
    const std::vector<bool> inside = pieces_with_inside(false);
    const Eigen::Index faces = triangles_.rows();
    for (Eigen::Index f = 0; f < faces; ++f)
      if (pieces_.find(static_cast<int>(f)) == f && !inside[static_cast<size_t>(f)]) return std::nullopt;
    for (Eigen::Index v = 0; v < connectivity_.vertex_count(); ++v)
      if (curved_[static_cast<size_t>(v)] && piece_around(v) >= 0) return std::nullopt;  // curvature inside a piece
    // Roots are each piece's smallest face: numbered in face order.
    std::vector<int> ids(static_cast<size_t>(faces), -1);
    int count = 0;
    for (Eigen::Index f = 0; f < faces; ++f) {
      const int root = pieces_.find(static_cast<int>(f));
      if (root == f) ids[static_cast<size_t>(f)] = count++;
      ids[static_cast<size_t>(f)] = ids[static_cast<size_t>(root)];
    }
    return ids;
  }

 private:
  // A cut ends on the boundary only from a curved vertex: a gap's line may
  // not run on to it.
  bool cut(int a, int b) const {
    const bool oa = on_cut_[static_cast<size_t>(a)], ob = on_cut_[static_cast<size_t>(b)];
    const bool ca = curved_[static_cast<size_t>(a)], cb = curved_[static_cast<size_t>(b)];
    const bool ba = !interior_[static_cast<size_t>(a)], bb = !interior_[static_cast<size_t>(b)];
    return (oa && ob) || (ca && bb) || (ba && cb);
  }

  // The faces joined across every edge that is not cut; the edges cut for a
  // gap vertex kept aside.
  void join_uncut_edges() {
    for (Eigen::Index f = 0; f < triangles_.rows(); ++f) {
      for (int c = 0; c < 3; ++c) {
        const int a = triangles_(f, c), b = triangles_(f, (c + 1) % 3);
        const int g = face_across(connectivity_, triangles_, static_cast<int>(f), a, b);
        if (g <= f) continue;
        if (!cut(a, b))
          pieces_.unite(static_cast<int>(f), g);
        else if (!curved_[static_cast<size_t>(a)] || !curved_[static_cast<size_t>(b)])
          gap_edges_.emplace_back(static_cast<int>(f), g);
      }
    }
  }

  // The piece (root face) holding all of an interior vertex's faces, or -1.
  int piece_around(Eigen::Index v) {
    const int piece = pieces_.find(*connectivity_.begin(v));
    for (const int* f = connectivity_.begin(v); f != connectivity_.end(v); ++f)
      if (pieces_.find(*f) != piece) return -1;
    return piece;
  }

  // Whether the piece of each root face has an inside vertex: interior,
  // flat, with all its faces in that piece; `strict`: not on a cut either.
  std::vector<bool> pieces_with_inside(bool strict) {
    std::vector<bool> inside(static_cast<size_t>(triangles_.rows()), false);
    for (Eigen::Index v = 0; v < connectivity_.vertex_count(); ++v) {
      if (!interior_[static_cast<size_t>(v)] || (strict ? on_cut_ : curved_)[static_cast<size_t>(v)]) continue;
      const int piece = piece_around(v);
      if (piece >= 0) inside[static_cast<size_t>(piece)] = true;
    }
    return inside;
  }

  const Triangles& triangles_;
  const VertexFaces& connectivity_;
  const std::vector<bool>& interior_;
  std::vector<bool> curved_;
  std::vector<bool> on_cut_;
  UnionFind pieces_;
  std::vector<std::pair<int, int>> gap_edges_;  // the two faces of each edge cut for a gap vertex
};

}  // namespace

std::optional<std::vector<int>> developable_pieces(const Triangles& triangles, const VertexFaces& connectivity,
                                                   const std::vector<bool>& interior, const Eigen::VectorXd& defects,
                                                   double flat_defect) {
  const Eigen::Index n = connectivity.vertex_count();
  std::vector<bool> curved(static_cast<size_t>(n), false);
  bool any_curved = false;
  for (Eigen::Index v = 0; v < n; ++v) {
    curved[static_cast<size_t>(v)] = interior[static_cast<size_t>(v)] && !(std::abs(defects[v]) < flat_defect);
    any_curved = any_curved || curved[static_cast<size_t>(v)];
  }
  if (!any_curved) return std::nullopt;
  PieceCutter cutter(triangles, connectivity, interior, std::move(curved));
  cutter.rejoin_gaps();
  return cutter.labels();
}

}  // namespace developable

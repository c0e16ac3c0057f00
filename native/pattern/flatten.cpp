#include "pattern/flatten.h"

#include "core/measures.h"
#include "pattern/plane_geometry.h"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

namespace developable::unfolding {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

constexpr double kTwoPi = 2.0 * M_PI;
// A breadth-first map this close to isometric replaces the conformal start
// (whose 2n x 2n factorisation is the unfolding's largest cost); this close,
// the refinement is skipped too: it cannot do better than rounding.
constexpr double kGreedyStart = 1e-3;
constexpr double kAlreadyIsometric = 1e-9;
// Faces between two progress reports in the linear passes.
constexpr size_t kReportEvery = 1 << 17;

// Each triangle in its own plane: corner 0 at the origin, corner 1 on the
// first axis.
struct Frames {
  std::vector<std::array<Vec2, 3>> local;
  std::vector<double> area;
  double total_area = 0.0;
  double edge(size_t f, int k) const { return (local[f][(k + 1) % 3] - local[f][k]).norm(); }
};

Frames frames_of(const Positions& positions, const LocalPiece& piece) {
  Frames fr;
  const size_t nf = piece.tris.size();
  fr.local.resize(nf);
  fr.area.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Vec3 p0 = positions.row(piece.tris[f][0]).transpose();
    const Vec3 e1 = positions.row(piece.tris[f][1]).transpose() - p0;
    const Vec3 e2 = positions.row(piece.tris[f][2]).transpose() - p0;
    const double l1 = e1.norm();
    const double x2 = e2.dot(e1) / l1;
    const double y2 = e1.cross(e2).norm() / l1;
    fr.local[f] = {Vec2(0, 0), Vec2(l1, 0), Vec2(x2, y2)};
    fr.area[f] = 0.5 * l1 * y2;
    fr.total_area += fr.area[f];
  }
  return fr;
}

// The face across face-edge fe over an uncut interior edge, or -1.
int face_across(const EdgeTable& edges, const std::vector<char>& is_cut, int fe) {
  const int e = edges.of_face_edge[fe];
  if (edges.uses[e][1] < 0 || is_cut[e]) return -1;
  return (edges.uses[e][0] == fe ? edges.uses[e][1] : edges.uses[e][0]) / 3;
}

// Breadth-first order of the faces over uncut edges from `root`, with the
// face each was reached from.
std::vector<int> breadth_first(const EdgeTable& edges, const std::vector<char>& is_cut, size_t nf, int root,
                               std::vector<int>* parent) {
  parent->assign(nf, -2);
  std::vector<int> queue{root};
  (*parent)[root] = -1;
  for (size_t head = 0; head < queue.size(); ++head)
    for (int k = 0; k < 3; ++k) {
      const int g = face_across(edges, is_cut, 3 * queue[head] + k);
      if (g >= 0 && (*parent)[g] == -2) (*parent)[g] = queue[head], queue.push_back(g);
    }
  return queue;
}

// The face halfway along a longest breadth-first path (two sweeps): the
// breadth-first map's errors grow with the distance from its root.
int central_face(const EdgeTable& edges, const std::vector<char>& is_cut, size_t nf) {
  std::vector<int> parent;
  const int far = breadth_first(edges, is_cut, nf, 0, &parent).back();
  const int other = breadth_first(edges, is_cut, nf, far, &parent).back();
  std::vector<int> path;
  for (int f = other; f >= 0; f = parent[f]) path.push_back(f);
  return path[path.size() / 2];
}

// Breadth-first map: each triangle laid down beside the one it is reached
// from, by its edge lengths. Exact on a developable disc, O(#faces); where
// the piece is not developable the vertices reached twice disagree.
std::vector<Vec2> greedy_layout(const LocalPiece& piece, const CornerVertices& verts, const EdgeTable& edges,
                                const std::vector<char>& is_cut, const Frames& fr, const Progress& progress) {
  const size_t nf = piece.tris.size();
  const int root = central_face(edges, is_cut, nf);
  std::vector<Vec2> uv(verts.count, Vec2::Zero());
  std::vector<char> placed(verts.count, 0), visited(nf, 0);
  for (int k = 0; k < 3; ++k)
    uv[verts.of_corner[3 * root + k]] = fr.local[root][k], placed[verts.of_corner[3 * root + k]] = 1;
  std::vector<int> queue{root};
  visited[root] = 1;
  for (size_t head = 0; head < queue.size(); ++head) {
    if (head % kReportEvery == kReportEvery - 1) progress.report(0.04 + 0.05 * head / nf, "unfolding: laying out");
    const int f = queue[head];
    for (int k = 0; k < 3; ++k) {
      const int e = edges.of_face_edge[3 * f + k];
      if (edges.uses[e][1] < 0 || is_cut[e]) continue;
      const int twin = edges.uses[e][0] == 3 * f + k ? edges.uses[e][1] : edges.uses[e][0];
      const int g = twin / 3, kg = twin % 3;  // in g the edge runs b -> a
      if (visited[g]) continue;
      visited[g] = 1;
      queue.push_back(g);
      const int c = verts.of_corner[3 * g + (kg + 2) % 3];
      if (placed[c]) continue;
      const Vec2 b = uv[verts.of_corner[3 * g + kg]], a = uv[verts.of_corner[3 * g + (kg + 1) % 3]];
      const double d = (a - b).norm();
      const double lbc = (fr.local[g][(kg + 2) % 3] - fr.local[g][kg]).norm();
      const double lac = (fr.local[g][(kg + 2) % 3] - fr.local[g][(kg + 1) % 3]).norm();
      const Vec2 along = d > 0 ? Vec2((a - b) / d) : Vec2(1, 0);
      const double x = d > 0 ? (lbc * lbc - lac * lac + d * d) / (2 * d) : 0.0;
      const double h = std::sqrt(std::max(0.0, lbc * lbc - x * x));
      uv[c] = b + x * along + h * Vec2(-along.y(), along.x());  // b, a, c counter-clockwise
      placed[c] = 1;
    }
  }
  return uv;
}

double largest_strain(const std::vector<Vec2>& uv, const CornerVertices& verts, const Frames& fr) {
  double worst = 0.0;
  for (size_t f = 0; f < fr.local.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const double l2 = (uv[verts.of_corner[3 * f + (k + 1) % 3]] - uv[verts.of_corner[3 * f + k]]).norm();
      worst = std::max(worst, std::abs(l2 / fr.edge(f, k) - 1.0));
    }
  return worst;
}

double flat_area(const std::vector<Vec2>& p, const CornerVertices& verts, size_t nf) {
  double sum = 0.0;
  for (size_t f = 0; f < nf; ++f) {
    const Vec2& q0 = p[verts.of_corner[3 * f]];
    sum += 0.5 * cross2(p[verts.of_corner[3 * f + 1]] - q0, p[verts.of_corner[3 * f + 2]] - q0);
  }
  return sum;
}

// Two outline vertices far apart (two sweeps over the longest loop).
std::array<int, 2> far_pair(const Positions& positions, const LocalPiece& piece, const std::vector<int>& loop) {
  const auto point_of = [&](int fe) { return positions.row(piece.tris[fe / 3][fe % 3]); };
  int pa = loop[0], pb = loop[0];
  for (int pass = 0; pass < 2; ++pass) {
    double best = -1.0;
    const int from = pass == 0 ? loop[0] : pa;
    for (int fe : loop) {
      const double d = (point_of(fe) - point_of(from)).norm();
      if (d > best) best = d, (pass == 0 ? pa : pb) = fe;
    }
  }
  return {pa, pb};
}

// Least-squares conformal map (Levy et al. 2002) with two far-apart outline
// vertices pinned, scaled to the 3D area; nothing when it fails.
std::optional<std::vector<Vec2>> conformal_start(const Positions& positions, const LocalPiece& piece,
                                                 const PieceTopology& t, const Frames& fr) {
  const size_t nf = piece.tris.size();
  const int nv = t.verts.count;
  const auto longest = std::max_element(t.loops.begin(), t.loops.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  const auto [pa, pb] = far_pair(positions, piece, *longest);
  const int va = t.verts.of_corner[pa], vb = t.verts.of_corner[pb];
  if (va == vb) return std::nullopt;
  std::vector<int> column(nv, -1);
  int free_count = 0;
  for (int v = 0; v < nv; ++v)
    if (v != va && v != vb) column[v] = free_count++;
  std::vector<Vec2> uv(nv, Vec2::Zero());
  uv[vb] = Vec2((positions.row(piece.tris[pa / 3][pa % 3]) - positions.row(piece.tris[pb / 3][pb % 3])).norm(), 0);
  if (free_count > 0) {
    std::vector<Triplet> rows;
    rows.reserve(nf * 12);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nf);
    for (size_t f = 0; f < nf; ++f) {
      const double scale = 1.0 / std::sqrt(fr.area[f]);
      for (int k = 0; k < 3; ++k) {
        // W_k = z_{k+2} - z_{k+1} (complex), row: sum_k W_k U_k = 0.
        const Vec2 w = (fr.local[f][(k + 2) % 3] - fr.local[f][(k + 1) % 3]) * scale;
        const int v = t.verts.of_corner[3 * f + k];
        const int c = column[v];
        if (c >= 0) {
          rows.emplace_back(2 * f, 2 * c, w.x());
          rows.emplace_back(2 * f, 2 * c + 1, -w.y());
          rows.emplace_back(2 * f + 1, 2 * c, w.y());
          rows.emplace_back(2 * f + 1, 2 * c + 1, w.x());
        } else {
          rhs[2 * f] -= w.x() * uv[v].x() - w.y() * uv[v].y();
          rhs[2 * f + 1] -= w.y() * uv[v].x() + w.x() * uv[v].y();
        }
      }
    }
    SparseMatrix a(2 * nf, 2 * free_count);
    a.setFromTriplets(rows.begin(), rows.end());
    const SparseMatrix at = a.transpose();
    const SparseMatrix normal = at * a;
    Eigen::SimplicialLDLT<SparseMatrix> solver(normal);
    if (solver.info() != Eigen::Success) return std::nullopt;
    const Eigen::VectorXd x = solver.solve(at * rhs);
    if (solver.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
    for (int v = 0; v < nv; ++v)
      if (column[v] >= 0) uv[v] = Vec2(x[2 * column[v]], x[2 * column[v] + 1]);
  }
  const double area = flat_area(uv, t.verts, nf);
  if (!(area > 0.0)) return std::nullopt;
  const double to_scale = std::sqrt(fr.total_area / area);
  for (auto& p : uv) p *= to_scale;
  return uv;
}

// x = A^-1 b for the two columns of b at once with the factors of an LDLT
// (one sweep of L for both: half the memory traffic of two solves).
Eigen::MatrixX2d solve_two_columns(const Eigen::SimplicialLDLT<SparseMatrix>& solver, const Eigen::MatrixX2d& b) {
  const SparseMatrix& lower = solver.matrixL().nestedExpression();  // unit diagonal implied
  const Eigen::VectorXd& diagonal = solver.vectorD();
  const int* permutation = solver.permutationP().indices().data();
  const Eigen::Index n = b.rows();
  std::vector<double> y(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) y[2 * permutation[i]] = b(i, 0), y[2 * permutation[i] + 1] = b(i, 1);
  const int* start = lower.outerIndexPtr();
  const int* count = lower.innerNonZeroPtr();  // null when compressed
  const auto end = [&](Eigen::Index j) { return count ? start[j] + count[j] : start[j + 1]; };
  const int* row = lower.innerIndexPtr();
  const double* value = lower.valuePtr();
  for (Eigen::Index j = 0; j < n; ++j) {  // L y = P b
    const double y0 = y[2 * j], y1 = y[2 * j + 1];
    for (int k = start[j]; k < end(j); ++k) y[2 * row[k]] -= value[k] * y0, y[2 * row[k] + 1] -= value[k] * y1;
  }
  for (Eigen::Index j = 0; j < n; ++j) y[2 * j] *= 1.0 / diagonal[j], y[2 * j + 1] *= 1.0 / diagonal[j];
  for (Eigen::Index j = n - 1; j >= 0; --j) {  // L^T z = D^-1 y
    double z0 = y[2 * j], z1 = y[2 * j + 1];
    for (int k = start[j]; k < end(j); ++k) z0 -= value[k] * y[2 * row[k]], z1 -= value[k] * y[2 * row[k] + 1];
    y[2 * j] = z0, y[2 * j + 1] = z1;
  }
  Eigen::MatrixX2d x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) x(i, 0) = y[2 * permutation[i]], x(i, 1) = y[2 * permutation[i] + 1];
  return x;
}

// As-rigid-as-possible refinement (Liu et al. 2008): local step = the closest
// rotation per triangle (closed form in 2D, never a reflection), global step
// = the cotangent Laplacian (vertex 0 fixed) factored once, back-substituted
// for x and y together.
class Arap {
 public:
  Arap(const Frames& fr, const CornerVertices& verts) : fr_(fr), verts_(verts), cot_(fr.local.size()) {
    for (size_t f = 0; f < fr.local.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Vec2 e1 = fr.local[f][(k + 1) % 3] - fr.local[f][k];
        const Vec2 e2 = fr.local[f][(k + 2) % 3] - fr.local[f][k];
        cot_[f][k] = e1.dot(e2) / (2.0 * fr.area[f]);
      }
  }

  // Factors the Laplacian once; false when that fails.
  bool factor() {
    if (factored_) return ok_;
    factored_ = true;
    const int unknowns = verts_.count - 1;
    std::vector<Triplet> entries;
    entries.reserve(fr_.local.size() * 12);
    for (size_t f = 0; f < fr_.local.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int i = verts_.of_corner[3 * f + (k + 1) % 3] - 1, j = verts_.of_corner[3 * f + (k + 2) % 3] - 1;
        const double w = cot_[f][k];
        if (i >= 0) entries.emplace_back(i, i, w);
        if (j >= 0) entries.emplace_back(j, j, w);
        if (i >= 0 && j >= 0) entries.emplace_back(i, j, -w), entries.emplace_back(j, i, -w);
      }
    SparseMatrix laplacian(unknowns, unknowns);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    solver_.compute(laplacian);
    ok_ = solver_.info() == Eigen::Success;
    return ok_;
  }

  // Up to `rounds` rounds from uv (changed in place); stops when the energy
  // changes by less than `tolerance` (relative) or is below 1e-18 of the area
  // (about the mean squared edge strain). Returns the rounds run, -1 when a
  // solve fails.
  int refine(std::vector<Vec2>& uv, int rounds, double tolerance, const Progress& progress) {
    if (verts_.count < 2 || rounds == 0) return 0;
    progress.report(0.1, "unfolding: factoring");
    if (!factor()) return -1;
    std::vector<Eigen::Matrix2d> rotation(fr_.local.size());
    double previous = std::numeric_limits<double>::infinity();
    for (int round = 0; round < rounds; ++round) {
      progress.report(0.2 + 0.8 * round / rounds, "unfolding: refining");
      local_step(uv, rotation);
      if (!global_step(uv, rotation)) return -1;
      const double e = energy(uv, rotation);
      if (e <= 1e-18 * fr_.total_area || (std::isfinite(previous) && std::abs(previous - e) <= tolerance * previous))
        return round + 1;
      previous = e;
    }
    return rounds;
  }

 private:
  Vec2 edge_3d(size_t f, int a, int b) const { return fr_.local[f][a] - fr_.local[f][b]; }
  const Vec2& at(const std::vector<Vec2>& uv, size_t f, int k) const { return uv[verts_.of_corner[3 * f + k]]; }

  void local_step(const std::vector<Vec2>& uv, std::vector<Eigen::Matrix2d>& rotation) const {
    for (size_t f = 0; f < fr_.local.size(); ++f) {
      Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        s += cot_[f][k] * (at(uv, f, a) - at(uv, f, b)) * edge_3d(f, a, b).transpose();
      }
      const double angle = std::atan2(s(1, 0) - s(0, 1), s(0, 0) + s(1, 1));
      const double c = std::cos(angle), sn = std::sin(angle);
      rotation[f] << c, -sn, sn, c;
    }
  }

  bool global_step(std::vector<Vec2>& uv, const std::vector<Eigen::Matrix2d>& rotation) const {
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(verts_.count - 1, 2);
    for (size_t f = 0; f < fr_.local.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const int va = verts_.of_corner[3 * f + a], vb = verts_.of_corner[3 * f + b];
        const Vec2 target = cot_[f][k] * (rotation[f] * edge_3d(f, a, b));
        const int i = va - 1, j = vb - 1;
        if (i >= 0) rhs.row(i) += target.transpose();
        if (j >= 0) rhs.row(j) -= target.transpose();
        // The fixed vertex's known position moves to the right-hand side.
        if (i >= 0 && j < 0) rhs.row(i) += cot_[f][k] * uv[vb].transpose();
        if (j >= 0 && i < 0) rhs.row(j) += cot_[f][k] * uv[va].transpose();
      }
    const Eigen::MatrixX2d x = solve_two_columns(solver_, rhs);
    if (!x.allFinite()) return false;
    for (int v = 1; v < verts_.count; ++v) uv[v] = x.row(v - 1).transpose();
    return true;
  }

  double energy(const std::vector<Vec2>& uv, const std::vector<Eigen::Matrix2d>& rotation) const {
    double sum = 0.0;
    for (size_t f = 0; f < fr_.local.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        sum += cot_[f][k] * ((at(uv, f, a) - at(uv, f, b)) - rotation[f] * edge_3d(f, a, b)).squaredNorm();
      }
    return sum;
  }

  const Frames& fr_;
  const CornerVertices& verts_;
  std::vector<std::array<double, 3>> cot_;
  Eigen::SimplicialLDLT<SparseMatrix> solver_;
  bool factored_ = false, ok_ = false;
};

// The outline loops' segments as vertex pairs.
std::vector<std::array<int, 2>> outline_segments(const PieceTopology& t) {
  std::vector<std::array<int, 2>> segments;
  for (const auto& loop : t.loops)
    for (int fe : loop) segments.push_back({t.verts.of_corner[fe], t.verts.of_corner[next_in_face(fe)]});
  return segments;
}

// Every flat triangle positive, a flat angle sum of 2 pi around inner
// vertices (a fan winding twice has positive triangles too), at most 2 pi on
// the outline, and no two outline edges crossing.
bool map_is_valid(const std::vector<Vec2>& p, const PieceTopology& t, const Frames& fr) {
  const CornerVertices& verts = t.verts;
  std::vector<double> angle_sum(verts.count, 0.0);
  for (size_t f = 0; f < fr.local.size(); ++f) {
    const Vec2& q0 = p[verts.of_corner[3 * f]];
    const Vec2& q1 = p[verts.of_corner[3 * f + 1]];
    const Vec2& q2 = p[verts.of_corner[3 * f + 2]];
    if (!q0.allFinite() || !q1.allFinite() || !q2.allFinite()) return false;
    if (!(0.5 * cross2(q1 - q0, q2 - q0) > 1e-12 * fr.area[f])) return false;
    for (int k = 0; k < 3; ++k) {
      const Vec2& c = p[verts.of_corner[3 * f + k]];
      const Vec2 e1 = p[verts.of_corner[3 * f + (k + 1) % 3]] - c;
      const Vec2 e2 = p[verts.of_corner[3 * f + (k + 2) % 3]] - c;
      angle_sum[verts.of_corner[3 * f + k]] += std::atan2(cross2(e1, e2), e1.dot(e2));
    }
  }
  const auto segments = outline_segments(t);
  std::vector<char> on_outline(verts.count, 0);
  for (const auto& s : segments) on_outline[s[0]] = 1;
  for (int v = 0; v < verts.count; ++v)
    if (on_outline[v] ? angle_sum[v] > kTwoPi + 1e-9 : std::abs(angle_sum[v] - kTwoPi) > 1e-6) return false;
  return outline_is_simple(p, segments);
}

// A flat map of the piece cut by is_cut (topology t) within `limit`, or
// nothing. Candidates in order: the breadth-first map when isometric to
// rounding; its refinement (when near-isometric or the piece is flat; if
// that is valid it decides); the refined conformal map; the conformal map;
// the breadth-first map itself.
std::optional<std::vector<Vec2>> flat_map(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges,
                                          const std::vector<char>& is_cut, const PieceTopology& t,
                                          const UnfoldOptions& options, bool flat, double limit,
                                          const Progress& progress, int* iterations) {
  const Frames fr = frames_of(positions, piece);
  if (!(fr.total_area > 0.0)) return std::nullopt;
  progress.report(0.04, "unfolding: laying out");
  const auto keeps = [&](const std::vector<Vec2>& uv) {
    return map_is_valid(uv, t, fr) && largest_strain(uv, t.verts, fr) <= limit;
  };
  *iterations = 0;
  const std::vector<Vec2> greedy = greedy_layout(piece, t.verts, edges, is_cut, fr, progress);
  const double greedy_strain = largest_strain(greedy, t.verts, fr);
  progress.report(0.09, "unfolding: checking");
  if (greedy_strain <= kAlreadyIsometric && keeps(greedy)) return greedy;
  Arap arap(fr, t.verts);
  const auto refined = [&](std::vector<Vec2> uv) -> std::optional<std::vector<Vec2>> {
    const int rounds = arap.refine(uv, options.arap_iterations, options.arap_tolerance, progress);
    if (rounds < 0) return std::nullopt;
    *iterations = rounds;
    return uv;
  };
  if (greedy_strain <= kGreedyStart || flat) {
    const auto uv = refined(greedy);
    if (uv && map_is_valid(*uv, t, fr)) {
      // A valid refinement beyond the rule: the conformal start would end
      // at the same minimum, the piece must be split.
      if (largest_strain(*uv, t.verts, fr) <= limit) return uv;
      return std::nullopt;
    }
  }
  const auto conformal = conformal_start(positions, piece, t, fr);
  if (conformal) {
    const auto uv = refined(*conformal);
    if (uv && keeps(*uv)) return uv;
    if (keeps(*conformal)) return conformal;
  }
  if (keeps(greedy)) return greedy;
  return std::nullopt;
}

// The loops in the order of their flat signed area, largest (the outer
// one, counter-clockwise) first.
void outer_loop_first(std::vector<std::vector<int>>& loops, const std::vector<Vec2>& corner_uv) {
  std::vector<std::pair<double, size_t>> order;
  for (size_t l = 0; l < loops.size(); ++l) {
    std::vector<Vec2> polygon;
    for (int fe : loops[l]) polygon.push_back(corner_uv[fe]);
    order.emplace_back(-signed_area(polygon), l);
  }
  std::sort(order.begin(), order.end());
  std::vector<std::vector<int>> sorted;
  for (const auto& [area, l] : order) sorted.push_back(std::move(loops[l]));
  loops = std::move(sorted);
}

// Darts: a slit along the shortest interior edge path from each cone vertex
// that is not flat (its angles sum under 2 pi - kFlatDefect) to the border,
// so that it opens there; at most kMaxDarts of them, the largest defect
// first. False (is_cut then undefined) when a vertex that is not flat is a
// saddle (a slit ending there would overlap itself), or there are too many.
constexpr int kMaxDarts = 8;

bool cut_darts(const Positions& positions, const LocalPiece& piece, const EdgeTable& edges, const PieceTopology& uncut,
               const PieceDefects& defects, std::vector<char>& is_cut) {
  std::vector<int> corner_of(uncut.verts.count, -1);
  for (size_t c = 0; c < uncut.verts.of_corner.size(); ++c)
    if (corner_of[uncut.verts.of_corner[c]] < 0) corner_of[uncut.verts.of_corner[c]] = static_cast<int>(c);
  std::vector<int> tips;
  for (int v = 0; v < uncut.verts.count; ++v) {
    if (std::abs(defects.of_vertex[v]) < kFlatDefect) continue;
    if (defects.of_vertex[v] < 0.0) return false;
    tips.push_back(v);
  }
  if (tips.empty() || tips.size() > static_cast<size_t>(kMaxDarts)) return false;
  std::sort(tips.begin(), tips.end(), [&](int a, int b) { return defects.of_vertex[a] > defects.of_vertex[b]; });
  for (int tip : tips) {
    const PieceTopology t = piece_topology(piece, edges, is_cut);
    std::vector<char> border(t.verts.count, 0);
    for (const auto& loop : t.loops)
      for (int fe : loop) border[t.verts.of_corner[fe]] = 1;
    const int v = t.verts.of_corner[corner_of[tip]];
    if (border[v]) continue;  // on a cut already
    const ShortestPaths sp = dijkstra(vertex_graph(positions, piece, edges, t.verts, is_cut), {v}, border);
    if (sp.reached < 0) return false;
    for (int w = sp.reached; sp.prev_edge[w] >= 0; w = sp.prev_vertex[w]) is_cut[sp.prev_edge[w]] = 1;
  }
  return true;
}

}  // namespace

bool PieceDefects::flat() const { return largest < kFlatDefect; }

PieceDefects piece_defects(const Positions& positions, const LocalPiece& piece, const PieceTopology& uncut) {
  PieceDefects d;
  const CornerVertices& verts = uncut.verts;
  std::vector<double> angle(verts.count, 0.0);
  for (size_t f = 0; f < piece.tris.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3 c = positions.row(piece.tris[f][k]).transpose();
      const Vec3 u = positions.row(piece.tris[f][(k + 1) % 3]).transpose() - c;
      const Vec3 w = positions.row(piece.tris[f][(k + 2) % 3]).transpose() - c;
      angle[verts.of_corner[3 * f + k]] += std::atan2(u.cross(w).norm(), u.dot(w));
    }
  std::vector<char> border(verts.count, 0);
  for (const auto& loop : uncut.loops)
    for (int fe : loop) border[verts.of_corner[fe]] = 1;
  d.of_vertex.assign(verts.count, 0.0);
  for (int v = 0; v < verts.count; ++v) {
    if (border[v]) continue;
    d.of_vertex[v] = kTwoPi - angle[v];
    d.sum += std::abs(d.of_vertex[v]);
    if (std::abs(d.of_vertex[v]) >= kFlatDefect) d.curved_sum += std::abs(d.of_vertex[v]);
    if (std::abs(d.of_vertex[v]) > d.largest || d.largest_vertex < 0)
      d.largest = std::abs(d.of_vertex[v]), d.largest_vertex = v;
  }
  return d;
}

double strain_limit(double seam_tolerance, const PieceDefects& defects) {
  if (!(seam_tolerance > 0.0)) return std::numeric_limits<double>::infinity();
  if (defects.curved_sum / kTwoPi > seam_tolerance) return seam_tolerance;
  return std::max(seam_tolerance, defects.sum / kTwoPi);
}

bool flatten_piece(const Positions& positions, const LocalPiece& piece, const UnfoldOptions& options,
                   const Progress& progress, FlatPiece* out) {
  const bool large = piece.tris.size() >= kReportEvery;
  const auto step = [&](double at) {
    if (large) progress.report(at, "unfolding: cutting");
  };
  const EdgeTable edges = edge_table(piece.tris);
  step(0.01);
  const std::vector<char> no_cuts(edges.keys.size(), 0);
  const PieceTopology uncut = piece_topology(piece, edges, no_cuts);
  const PieceDefects defects = piece_defects(positions, piece, uncut);
  step(0.02);
  // A flat map of the piece cut by is_cut within the limit of `d` into *out.
  const auto attempt = [&](const std::vector<char>& is_cut, const PieceDefects& d) {
    PieceTopology t = piece_topology(piece, edges, is_cut);
    if (!t.flattenable()) return false;
    step(0.03);
    int iterations = 0;
    const double limit = strain_limit(options.seam_tolerance, d);
    const auto uv = flat_map(positions, piece, edges, is_cut, t, options, limit > options.seam_tolerance || d.flat(),
                             limit, progress, &iterations);
    if (!uv) return false;
    out->corner_uv.resize(piece.tris.size() * 3);
    for (size_t c = 0; c < out->corner_uv.size(); ++c) out->corner_uv[c] = (*uv)[t.verts.of_corner[c]];
    out->outline = std::move(t.loops);
    outer_loop_first(out->outline, out->corner_uv);
    out->cut_keys.clear();
    for (size_t e = 0; e < edges.keys.size(); ++e)
      if (is_cut[e]) out->cut_keys.push_back(edges.keys[e]);
    out->arap_iterations = iterations;
    return true;
  };
  std::vector<char> is_cut = no_cuts;
  if (uncut.loops.size() >= 2) {  // holes kept first
    if (!choose_cuts(positions, piece, edges, Holes::keep, is_cut)) return false;
    if (attempt(is_cut, defects)) return true;
    is_cut = no_cuts;
  }
  if (!choose_cuts(positions, piece, edges, Holes::join, is_cut)) return false;
  if (attempt(is_cut, defects)) return true;
  if (strain_limit(options.seam_tolerance, defects) > options.seam_tolerance || defects.flat() ||
      !cut_darts(positions, piece, edges, uncut, defects, is_cut))
    return false;
  return attempt(is_cut, piece_defects(positions, piece, piece_topology(piece, edges, is_cut)));
}

bool outline_is_simple(const std::vector<Vec2>& uv, const std::vector<std::array<int, 2>>& segments) {
  if (segments.size() < 4) return true;
  Eigen::AlignedBox2d box;
  double total = 0.0;
  for (const auto& s : segments) {
    box.extend(uv[s[0]]);
    box.extend(uv[s[1]]);
    total += (uv[s[1]] - uv[s[0]]).norm();
  }
  const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
  const double cell = std::max(2.0 * total / segments.size(), extent / 4096.0);
  const auto index = [&](double x, double lo) { return static_cast<int64_t>(std::floor((x - lo) / cell)); };
  std::unordered_map<int64_t, std::vector<int>> grid;
  const int64_t stride = index(box.max().y(), box.min().y()) + 2;
  for (size_t i = 0; i < segments.size(); ++i) {
    const Vec2& a = uv[segments[i][0]];
    const Vec2& b = uv[segments[i][1]];
    for (int64_t x = index(std::min(a.x(), b.x()), box.min().x()); x <= index(std::max(a.x(), b.x()), box.min().x());
         ++x)
      for (int64_t y = index(std::min(a.y(), b.y()), box.min().y()); y <= index(std::max(a.y(), b.y()), box.min().y());
           ++y)
        grid[x * stride + y].push_back(static_cast<int>(i));
  }
  const double eps = 1e-12 * extent * extent;
  for (const auto& [cell_id, list] : grid)
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        const auto& s = segments[list[i]];
        const auto& u = segments[list[j]];
        if (s[0] == u[0] || s[0] == u[1] || s[1] == u[0] || s[1] == u[1]) continue;
        const Vec2 &a = uv[s[0]], &b = uv[s[1]], &c = uv[u[0]], &d = uv[u[1]];
        const double o1 = cross2(b - a, c - a), o2 = cross2(b - a, d - a);
        const double o3 = cross2(d - c, a - c), o4 = cross2(d - c, b - c);
        if (((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps)) &&
            ((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps)))
          return false;
      }
  return true;
}

}  // namespace developable::unfolding

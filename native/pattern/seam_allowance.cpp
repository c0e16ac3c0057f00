#include "pattern/seam_allowance.h"

#include "core/types.h"
#include "pattern/plane_geometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;

// The outward normal of the counter-clockwise edge direction u, and its angle.
Vec2 outward(const Vec2& u) { return Vec2(u.y(), -u.x()); }
double angle_of(const Vec2& v) { return std::atan2(v.y(), v.x()); }

// A straight piece of the offset's boundary.
struct Piece {
  Vec2 from, to;
};

// The parameters t in [lo, hi] of the line a + t v inside the open disc of
// radius r about c; false when none.
bool line_in_disc(const Vec2& a, const Vec2& v, const Vec2& c, double r, double& lo, double& hi) {
  const double alpha = v.squaredNorm();
  const double beta = v.dot(a - c);
  const double gamma = (a - c).squaredNorm() - r * r;
  if (alpha <= 0.0) {
    if (gamma >= 0.0) return false;
    lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    return true;
  }
  const double discriminant = beta * beta - alpha * gamma;
  if (discriminant <= 0.0) return false;
  const double root = std::sqrt(discriminant);
  lo = (-beta - root) / alpha, hi = (-beta + root) / alpha;
  return true;
}

// Narrows [lo, hi] to the t where s0 + t s1 lies in (low, high); false when empty.
bool clip_slab(double s0, double s1, double low, double high, double& lo, double& hi) {
  if (s1 == 0.0) return s0 > low && s0 < high;
  double t0 = (low - s0) / s1, t1 = (high - s0) / s1;
  if (t0 > t1) std::swap(t0, t1);
  lo = std::max(lo, t0), hi = std::min(hi, t1);
  return lo < hi;
}

// The parameters of the line a + t v nearer than r to the segment [p, q]
// (a capsule, convex, so one interval); false when none.
bool line_in_capsule(const Vec2& a, const Vec2& v, const Vec2& p, const Vec2& q, double r, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  double l, h;
  if (line_in_disc(a, v, p, r, l, h)) lo = std::min(lo, l), hi = std::max(hi, h);
  if (line_in_disc(a, v, q, r, l, h)) lo = std::min(lo, l), hi = std::max(hi, h);
  const Vec2 e = q - p;
  const double length = e.norm();
  if (length > 0.0) {
    const Vec2 u = e / length, w(-u.y(), u.x());
    l = -std::numeric_limits<double>::infinity(), h = std::numeric_limits<double>::infinity();
    if (clip_slab(u.dot(a - p), u.dot(v), 0.0, length, l, h) && clip_slab(w.dot(a - p), w.dot(v), -r, r, l, h))
      lo = std::min(lo, l), hi = std::max(hi, h);
  }
  return lo < hi;
}

// The angles (in [0, turn]) of the arc about `centre` of `radius`, from
// angle `start` counter-clockwise by `turn`, that lie nearer than r to the
// segment [p, q]: every crossing of the circle with the capsule's boundary
// (its two sides' lines and end circles, extended: extra cuts are harmless)
// splits the arc, and each part is in or out as its middle is.
void arc_in_capsule(const Vec2& centre, double radius, double start, double turn, const Vec2& p, const Vec2& q,
                    double r, std::vector<std::pair<double, double>>& out) {
  std::vector<double> cuts{0.0, turn};
  const auto add = [&](double angle) {
    double delta = std::fmod(angle - start, 2.0 * M_PI);
    if (delta < 0.0) delta += 2.0 * M_PI;
    if (delta > 0.0 && delta < turn) cuts.push_back(delta);
  };
  for (const Vec2& c : {p, q}) {  // the end circles
    const Vec2 to = c - centre;
    const double gap = to.norm();
    if (gap == 0.0 || gap > radius + r || gap < std::abs(radius - r)) continue;
    const double half = std::acos(std::clamp((radius * radius + gap * gap - r * r) / (2.0 * radius * gap), -1.0, 1.0));
    add(angle_of(to) - half), add(angle_of(to) + half);
  }
  const Vec2 e = q - p;
  if (e.norm() > 0.0) {  // the side lines: points p + side w + s u
    const Vec2 u = e.normalized(), w(-u.y(), u.x());
    for (double side : {-r, r}) {
      const double offset = w.dot(p - centre) + side;  // the line's signed distance from the centre along w
      if (std::abs(offset) > radius) continue;
      const double along = std::sqrt(radius * radius - offset * offset);
      const Vec2 foot = centre + offset * w;
      add(angle_of(foot + along * u - centre)), add(angle_of(foot - along * u - centre));
    }
  }
  std::sort(cuts.begin(), cuts.end());
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double middle = start + 0.5 * (cuts[k] + cuts[k + 1]);
    const Vec2 x = centre + radius * Vec2(std::cos(middle), std::sin(middle));
    const double t = e.squaredNorm() > 0.0 ? std::clamp(e.dot(x - p) / e.squaredNorm(), 0.0, 1.0) : 0.0;
    if ((p + t * e - x).norm() < r) out.emplace_back(cuts[k], cuts[k + 1]);
  }
}

// The round corner about `centre` of `radius` from `from` (at direction
// angle `start`) turning counter-clockwise by `turn` to `to`, as chords whose
// sag is at most `sag`; its ends are `from` and `to` exactly, so that it
// meets the shifted edges beside it without a gap.
void add_arc(std::vector<Piece>& pieces, const Vec2& centre, double radius, const Vec2& from, const Vec2& to,
             double start, double turn, double sag) {
  const double step = 2.0 * std::acos(std::max(-1.0, 1.0 - sag / radius));
  const int count = std::max(1, static_cast<int>(std::ceil(turn / std::max(step, 1e-3))));
  Vec2 previous = from;
  for (int k = 1; k <= count; ++k) {
    const double angle = start + turn * k / count;
    const Vec2 next = k == count ? to : Vec2(centre + radius * Vec2(std::cos(angle), std::sin(angle)));
    pieces.push_back({previous, next});
    previous = next;
  }
}

// The offset of a convex counter-clockwise polygon: shifted edges and round
// corners, nothing to trim.
std::vector<Vec2> offset_convex(const std::vector<Vec2>& hull, double distance, double sag) {
  std::vector<Piece> pieces;
  const size_t n = hull.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 before = (hull[i] - hull[(i + n - 1) % n]).normalized();
    const Vec2 after = (hull[(i + 1) % n] - hull[i]).normalized();
    add_arc(pieces, hull[i], distance, hull[i] + distance * outward(before), hull[i] + distance * outward(after),
            angle_of(outward(before)), std::atan2(cross2(before, after), before.dot(after)), sag);
    pieces.push_back({hull[i] + distance * outward(after), hull[(i + 1) % n] + distance * outward(after)});
  }
  std::vector<Vec2> out;
  for (const Piece& piece : pieces) out.push_back(piece.from);
  return out;
}

// The pieces chained into loops: each piece is followed by the unused piece
// that starts nearest to its end (the next one in order, or the one across a
// gap the trimming closed). Returns the loop of largest area (the outer
// one), its area, and whether every chain closed.
std::vector<Vec2> outer_loop(const std::vector<Piece>& kept, double join, double* best_area, bool* closed_all) {
  std::vector<char> used(kept.size(), 0);
  std::vector<Vec2> best;
  for (size_t first = 0; first < kept.size(); ++first) {
    if (used[first]) continue;
    std::vector<Vec2> chain;
    size_t at = first;
    used[at] = 1;
    bool closed = false;
    for (;;) {
      chain.push_back(kept[at].from);
      const Vec2& end = kept[at].to;
      size_t next = kept.size();
      double nearest = join;
      for (size_t m = 1; m < kept.size(); ++m) {
        const size_t k = (at + m) % kept.size();
        if (used[k]) continue;
        const double gap = (kept[k].from - end).norm();
        if (gap <= nearest) next = k, nearest = gap;
        if (gap == 0.0) break;  // the next piece untrimmed: nothing is nearer
      }
      const double home = (kept[first].from - end).norm();
      if (home <= join && (next == kept.size() || home <= nearest)) {
        closed = true;
        break;
      }
      if (next == kept.size()) break;
      used[next] = 1;
      at = next;
    }
    if (!closed) {
      *closed_all = false;
      continue;
    }
    const double chain_area = signed_area(chain);
    if (chain_area > *best_area) *best_area = chain_area, best = std::move(chain);
  }
  return best;
}

}  // namespace

OffsetOutline offset_outline(const std::vector<Vec2>& outline, double distance, double tolerance) {
  if (!std::isfinite(distance) || !(distance > 0.0) || !std::isfinite(tolerance) || !(tolerance > 0.0))
    throw EngineError(Status::invalid_argument, "offset_outline: the distance and the tolerance must be positive");
  std::vector<Vec2> loop;
  for (const Vec2& p : outline) {
    if (!p.allFinite()) throw EngineError(Status::invalid_argument, "offset_outline: a corner is not finite");
    if (loop.empty() || p != loop.back()) loop.push_back(p);
  }
  while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
  const double area = loop.size() >= 3 ? signed_area(loop) : 0.0;
  if (!(std::abs(area) > 0.0))
    throw EngineError(Status::invalid_argument, "offset_outline: the outline needs 3 corners and an area");
  const bool clockwise = area < 0.0;
  if (clockwise) std::reverse(loop.begin(), loop.end());
  const size_t n = loop.size();
  // A candidate point is cut away where it is nearer than `distance` to
  // some edge (less a rounding margin, so that a shifted edge keeps its own
  // edge's and its corners' distance); a round corner is not cut by its
  // corner's two edges, whose nearest point to it is the corner itself. The
  // chords that draw a round corner sag by at most half the tolerance; they
  // are cut where the exact arc is, so that the ends of two trimmed pieces
  // agree to rounding.
  const double sag = 0.5 * tolerance;
  const double reach = distance * (1.0 - 1e-12);
  std::vector<Eigen::AlignedBox2d> edge_box(n);
  for (size_t j = 0; j < n; ++j) {
    edge_box[j].extend(loop[j]);
    edge_box[j].extend(loop[(j + 1) % n]);
    edge_box[j].min().array() -= reach;
    edge_box[j].max().array() += reach;
  }
  Eigen::AlignedBox2d extent;
  for (const Vec2& p : loop) extent.extend(p);
  const double join = 1e-9 * (extent.sizes().norm() + distance) + 0.1 * tolerance;
  // Pieces shorter than `join` are left out: their neighbours meet across them.
  std::vector<Piece> kept;
  const auto keep = [&](const Vec2& from, const Vec2& to) {
    if ((to - from).norm() > join) kept.push_back({from, to});
  };
  // The parts of [0, length] left after the (sorted) cut intervals.
  std::vector<std::pair<double, double>> cut;
  const auto left_over = [&](double length) {
    std::sort(cut.begin(), cut.end());
    std::vector<std::pair<double, double>> parts;
    double t = 0.0;
    for (const auto& [lo, hi] : cut) {
      if (lo > t) parts.emplace_back(t, lo);
      t = std::max(t, hi);
    }
    if (t < length) parts.emplace_back(t, length);
    return parts;
  };

  // The candidate boundary, in outline order: a round corner at each convex
  // corner and each edge shifted outward (a reflex corner's two shifted
  // edges cross each other and are cut there), each trimmed.
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = loop[i];
    const Vec2& b = loop[(i + 1) % n];
    const Vec2 before = (a - loop[(i + n - 1) % n]).normalized();
    const Vec2 u = (b - a).normalized();
    const double turn = std::atan2(cross2(before, u), before.dot(u));
    const Vec2 normal = outward(u);
    if (turn > 0.0) {
      const double start = angle_of(outward(before));
      Eigen::AlignedBox2d box(a);
      box.min().array() -= distance;
      box.max().array() += distance;
      cut.clear();
      for (size_t j = 0; j < n; ++j)
        if (j != i && (j + 1) % n != i && box.intersects(edge_box[j]))
          arc_in_capsule(a, distance, start, turn, loop[j], loop[(j + 1) % n], reach, cut);
      for (const auto& [lo, hi] : left_over(turn)) {
        const auto at = [&](double angle) -> Vec2 {
          if (angle == 0.0) return a + distance * outward(before);
          if (angle == turn) return a + distance * normal;
          return a + distance * Vec2(std::cos(start + angle), std::sin(start + angle));
        };
        std::vector<Piece> chords;
        add_arc(chords, a, distance, at(lo), at(hi), start + lo, hi - lo, sag);
        for (const Piece& chord : chords) keep(chord.from, chord.to);
      }
    }
    const Vec2 from = a + distance * normal, to = b + distance * normal, v = to - from;
    Eigen::AlignedBox2d box(from);
    box.extend(to);
    cut.clear();
    for (size_t j = 0; j < n; ++j) {
      double lo, hi;
      if (box.intersects(edge_box[j]) && line_in_capsule(from, v, loop[j], loop[(j + 1) % n], reach, lo, hi) &&
          hi > 0.0 && lo < 1.0)
        cut.emplace_back(std::max(lo, 0.0), std::min(hi, 1.0));
    }
    for (const auto& [lo, hi] : left_over(1.0))
      keep(lo == 0.0 ? from : Vec2(from + lo * v), hi == 1.0 ? to : Vec2(from + hi * v));
  }

  double best_area = 0.0;
  bool closed_all = true;
  std::vector<Vec2> best = outer_loop(kept, join, &best_area, &closed_all);
  OffsetOutline result;
  result.from_hull = best.empty() || !closed_all || best_area < std::abs(area);
  result.points = result.from_hull ? offset_convex(convex_hull(loop), distance, sag) : std::move(best);
  if (clockwise) std::reverse(result.points.begin(), result.points.end());
  return result;
}

}  // namespace developable

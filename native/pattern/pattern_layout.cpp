#include "pattern/pattern_layout.h"

#include "pattern/glue_tabs.h"
#include "pattern/pattern_labels.h"
#include "pattern/plane_geometry.h"
#include "pattern/seam_allowance.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;

// mm: how far the chords that draw a cut line's round corners may stray from
// the circle, a cutting plotter's step.
constexpr double kCutLineTolerance = 0.01;

// The turn (radians) that brings the hull's smallest-area bounding rectangle
// upright, tried along every hull edge (at most 720 of them).
double upright_angle(const std::vector<Vec2>& hull) {
  if (hull.size() < 3) return 0.0;
  const size_t step = std::max<size_t>(1, hull.size() / 720);
  double best_area = std::numeric_limits<double>::infinity(), best = 0.0;
  for (size_t i = 0; i < hull.size(); i += step) {
    const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
    if (e.norm() == 0.0) continue;
    const double angle = -std::atan2(e.y(), e.x());
    const Eigen::Rotation2Dd turn(angle);
    Eigen::AlignedBox2d box;
    for (const Vec2& p : hull) box.extend(turn * p);
    const double area = box.volume();
    if (area < best_area) best_area = area, best = angle;
  }
  return best;
}

std::string format_scale(double scale) {
  std::ostringstream out;
  if (scale >= 1.0)
    out << scale << ":1";
  else
    out << "1:" << 1.0 / scale;
  return out.str();
}

// The runs of one side of a seam on its piece's outline, in the outline's
// order (side a is left of the directed edges, as the piece is of its
// outline, so its edges run the outline's way; side b's run it backwards).
// `position`: outline edge (3 f + k: corner k of face f to the next) -> its
// index on its piece's loop. `lost`: an edge not on the outline as expected.
struct SideRuns {
  std::vector<TabRun> runs;
  bool lost = false;
};

SideRuns side_runs(const UnfoldResult& unfolded, const Triangles& triangles, const std::vector<int>& position,
                   const UnfoldSeam& seam, int side) {
  const int piece = side == 0 ? seam.piece_a : seam.piece_b;
  const int n = static_cast<int>(unfolded.pieces[static_cast<size_t>(piece)].outline.front().size());
  SideRuns result;
  int previous = -2;
  const size_t m = seam.edges.size();
  for (size_t j = 0; j < m; ++j) {
    const size_t i = side == 0 ? j : m - 1 - j;
    const int f = seam.faces[i][static_cast<size_t>(side)];
    const int from = seam.edges[i][static_cast<size_t>(side)];  // side b's edges go the other way
    int edge = -1;
    for (int k = 0; k < 3; ++k)
      if (triangles(f, k) == from) edge = position[static_cast<size_t>(3 * f + k)];
    if (edge < 0) {
      previous = -2;
      result.lost = true;
      continue;
    }
    if (previous >= 0 && edge == (previous + 1) % n)
      ++result.runs.back().count;  // the run goes on
    else
      result.runs.push_back({edge, 1});
    previous = edge;
  }
  // A seam around a closed ring starts anywhere on it: its last run may end
  // where its first begins on the flat outline, one run there.
  auto& runs = result.runs;
  if (runs.size() > 1 && (runs.back().first + runs.back().count) % n == runs.front().first) {
    runs.back().count += runs.front().count;
    runs.erase(runs.begin());
  }
  return result;
}

// Glue tabs on one side of every seam: side a's runs first (add_glue_tabs);
// a seam none of whose side-a runs got a tab then tries side b, on pieces
// that keep the tabs they have and fit the new ones around them. The cut
// lines and fold lines go into `layout`; dropped counts, per seam, the runs
// of the side it ended on that got no tab (and that side once if an edge of
// it was not on its outline).
void add_tabs(const UnfoldResult& unfolded, const Triangles& triangles, double height, Layout& layout) {
  std::vector<int> position(static_cast<size_t>(unfolded.corners.rows()), -1);
  for (const UnfoldPiece& piece : unfolded.pieces)
    for (size_t j = 0; j < piece.outline.front().size(); ++j)
      position[static_cast<size_t>(piece.outline.front()[j])] = static_cast<int>(j);
  const size_t piece_count = unfolded.pieces.size(), seam_count = unfolded.seams.size();
  // Per piece: its runs, the seam of each and what add_glue_tabs made of them.
  std::vector<std::vector<TabRun>> runs(piece_count);
  std::vector<std::vector<size_t>> seam_of(piece_count);
  std::vector<TabbedOutline> tabbed(piece_count);
  const auto place = [&](size_t p) { tabbed[p] = add_glue_tabs(outline_on_sheet(layout, p), runs[p], height); };
  // Per seam: the runs without a tab of the side it ended on, plus one if
  // that side lost an edge.
  std::vector<int> dropped(seam_count, 0);
  for (size_t s = 0; s < seam_count; ++s) {
    const SideRuns a = side_runs(unfolded, triangles, position, unfolded.seams[s], 0);
    const auto p = static_cast<size_t>(unfolded.seams[s].piece_a);
    runs[p].insert(runs[p].end(), a.runs.begin(), a.runs.end());
    seam_of[p].insert(seam_of[p].end(), a.runs.size(), s);
    dropped[s] = a.lost ? 1 : 0;
  }
  for (size_t p = 0; p < piece_count; ++p)
    if (!runs[p].empty()) place(p);
  std::vector<bool> has_tab(seam_count, false);
  for (size_t p = 0; p < piece_count; ++p)
    for (size_t r = 0; r < runs[p].size(); ++r) {
      if (tabbed[p].tabbed[r])
        has_tab[seam_of[p][r]] = true;
      else
        ++dropped[seam_of[p][r]];
    }

  // Seams with no tab on side a try side b.
  std::vector<bool> retried(piece_count, false), on_b(seam_count, false);
  for (size_t s = 0; s < seam_count; ++s) {
    if (has_tab[s]) continue;
    const SideRuns b = side_runs(unfolded, triangles, position, unfolded.seams[s], 1);
    if (b.runs.empty()) continue;  // nothing to try: side a's count stands
    const auto p = static_cast<size_t>(unfolded.seams[s].piece_b);
    if (!retried[p]) {
      // The piece keeps the tabs it has (tried first, they fit as before).
      std::vector<TabRun> kept;
      std::vector<size_t> kept_seams;
      for (size_t r = 0; r < runs[p].size(); ++r)
        if (tabbed[p].tabbed[r]) kept.push_back(runs[p][r]), kept_seams.push_back(seam_of[p][r]);
      runs[p] = std::move(kept);
      seam_of[p] = std::move(kept_seams);
      retried[p] = true;
    }
    runs[p].insert(runs[p].end(), b.runs.begin(), b.runs.end());
    seam_of[p].insert(seam_of[p].end(), b.runs.size(), s);
    on_b[s] = true;
    dropped[s] = b.lost ? 1 : 0;
  }
  for (size_t p = 0; p < piece_count; ++p) {
    if (!retried[p]) continue;
    place(p);
    for (size_t r = 0; r < runs[p].size(); ++r)
      if (on_b[seam_of[p][r]] && !tabbed[p].tabbed[r]) ++dropped[seam_of[p][r]];
  }

  for (size_t p = 0; p < piece_count; ++p) {
    if (runs[p].empty()) continue;
    layout.pieces[p].cut_line = std::move(tabbed[p].cut_line);
    for (auto& fold : tabbed[p].folds) layout.fold_lines.push_back({layout.pieces[p].sheet, std::move(fold)});
    layout.glue_tabs += tabbed[p].tabs;
  }
  for (int d : dropped) layout.glue_tabs_dropped += d;
}

void check_options(const LayoutOptions& options) {
  const auto finite_positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!finite_positive(options.sheet_width) || !finite_positive(options.sheet_height))
    throw EngineError(Status::invalid_argument, "the sheet width and height must be positive (mm)");
  if (!finite_positive(options.unit_mm))
    throw EngineError(Status::invalid_argument, "the model unit's length in mm must be positive");
  if (!std::isfinite(options.scale) || options.scale < 0.0)
    throw EngineError(Status::invalid_argument, "the scale must be positive, or 0 for automatic");
  if (!std::isfinite(options.margin) || options.margin < 0.0 || !std::isfinite(options.spacing) ||
      options.spacing < 0.0 || !std::isfinite(options.footer) || options.footer < 0.0)
    throw EngineError(Status::invalid_argument, "margin, spacing and footer must not be negative");
  if (!std::isfinite(options.seam_allowance) || options.seam_allowance < 0.0)
    throw EngineError(Status::invalid_argument, "the seam allowance must not be negative (mm)");
  if (!std::isfinite(options.glue_tabs) || options.glue_tabs < 0.0)
    throw EngineError(Status::invalid_argument, "the glue tabs' height must not be negative (mm)");
  if (options.seam_allowance > 0.0 && options.glue_tabs > 0.0)
    throw EngineError(Status::invalid_argument, "a seam allowance or glue tabs, not both");
}

// The printable room (mm) and what is kept around every piece.
struct Room {
  double width = 0.0, height = 0.0, reserve = 0.0;
};

Room printable_room(const LayoutOptions& options) {
  Room room;
  room.reserve = options.seam_allowance + options.glue_tabs;
  room.width = options.sheet_width - 2.0 * options.margin;
  room.height = options.sheet_height - 2.0 * options.margin - options.footer;
  if (room.width <= 0.0 || room.height <= 0.0)
    throw EngineError(Status::invalid_argument, "the margins leave no room on the sheet");
  if (2.0 * room.reserve >= std::min(room.width, room.height)) {
    std::ostringstream message;
    message.precision(4);
    message << (options.seam_allowance > 0.0 ? "a seam allowance of " : "glue tabs of ") << room.reserve
            << " mm leave no room for a piece on the printable " << room.width << " x " << room.height
            << " mm of the sheet";
    throw EngineError(Status::invalid_argument, message.str());
  }
  return room;
}

// Each piece upright in model units: its turn and its bounding box, lying.
struct Upright {
  std::vector<double> turn;
  std::vector<Eigen::AlignedBox2d> box;
};

Upright upright_pieces(const UnfoldResult& unfolded, const Progress& progress) {
  const size_t n = unfolded.pieces.size();
  Upright u{std::vector<double>(n), std::vector<Eigen::AlignedBox2d>(n)};
  for (size_t p = 0; p < n; ++p) {
    if (p % 64 == 0) progress.report(0.5 * p / n, "laying out");
    std::vector<Vec2> points;
    for (const auto& loop : unfolded.pieces[p].outline)
      for (Eigen::Index row : loop) points.push_back(unfolded.corners.row(row).transpose());
    u.turn[p] = upright_angle(convex_hull(points));
    for (int pass = 0; pass < 2; ++pass) {
      const Eigen::Rotation2Dd r(u.turn[p]);
      u.box[p].setEmpty();
      for (const Vec2& q : points) u.box[p].extend(r * q);
      if (u.box[p].sizes().x() >= u.box[p].sizes().y()) break;
      u.turn[p] += M_PI / 2;  // lying: shelves fill better
    }
  }
  return u;
}

// The first piece that fits neither lying nor standing at `mm_per_unit`, or
// -1; `stand` (if given) says which pieces only fit standing.
int first_misfit(const Upright& u, const Room& room, double mm_per_unit, std::vector<char>* stand) {
  for (size_t p = 0; p < u.box.size(); ++p) {
    const double w = u.box[p].sizes().x() * mm_per_unit + 2.0 * room.reserve;
    const double h = u.box[p].sizes().y() * mm_per_unit + 2.0 * room.reserve;
    const bool lying = w <= room.width && h <= room.height;
    const bool standing = h <= room.width && w <= room.height;
    if (!lying && !standing) return static_cast<int>(p);
    if (stand) (*stand)[p] = !lying;
  }
  return -1;
}

// The largest 1-2-5 scale at which every piece fits (throws if none does).
double automatic_scale(const Upright& u, const Room& room, double unit_mm) {
  for (double decade = 1.0; decade < 1e10; decade *= 10.0)
    for (double step : {1.0, 2.0, 5.0})
      if (first_misfit(u, room, unit_mm / (decade * step), nullptr) < 0) return 1.0 / (decade * step);
  throw EngineError(Status::invalid_argument, "no scale down to 1:10^9 fits the pieces on the sheet");
}

[[noreturn]] void piece_does_not_fit(const Upright& u, const Room& room, const LayoutOptions& options, double scale,
                                     int too_big) {
  const double mm_per_unit = scale * options.unit_mm;
  const Eigen::Vector2d size = u.box[too_big].sizes() * mm_per_unit + Vec2::Constant(2.0 * room.reserve);
  double fitting = 0.0;  // the largest 1-2-5 scale that would fit this piece
  // (the reserve keeps its mm at any scale)
  const double ratio =
      std::min((std::max(room.width, room.height) - 2.0 * room.reserve) / (size.x() - 2.0 * room.reserve),
               (std::min(room.width, room.height) - 2.0 * room.reserve) / (size.y() - 2.0 * room.reserve));
  for (double decade = 1.0; decade < 1e10 && fitting == 0.0; decade *= 10.0)
    for (double step : {1.0, 2.0, 5.0})
      if (1.0 / (decade * step) <= ratio) {
        fitting = scale / (decade * step);
        break;
      }
  std::ostringstream message;
  message.precision(4);
  message << "piece " << piece_label(too_big) << " is " << size.x() << " x " << size.y() << " mm at "
          << format_scale(scale) << " and does not fit the printable " << room.width << " x " << room.height
          << " mm of the " << options.sheet_width << " x " << options.sheet_height
          << " mm sheet: use a larger sheet or a scale of " << format_scale(fitting) << " (" << fitting
          << ") or smaller";
  throw EngineError(Status::invalid_argument, message.str());
}

// First-fit decreasing height on shelves across sheets: each piece's sheet
// and size in `layout`, the top left corner of its box in `origin`.
std::vector<Vec2> shelve(const std::vector<Vec2>& sizes, const Room& room, const LayoutOptions& options,
                         Layout& layout) {
  struct Shelf {
    int sheet;
    double top, height, used;
  };
  std::vector<Shelf> shelves;
  std::vector<double> sheet_filled;  // height used on each sheet
  std::vector<size_t> order(sizes.size());
  for (size_t p = 0; p < sizes.size(); ++p) order[p] = p;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return sizes[a].y() > sizes[b].y(); });
  std::vector<Vec2> origin(sizes.size());
  for (size_t p : order) {
    const Vec2& size = sizes[p];
    Shelf* target = nullptr;
    for (Shelf& shelf : shelves)
      if (size.y() <= shelf.height + 1e-9 && shelf.used + size.x() <= room.width + 1e-9) {
        target = &shelf;
        break;
      }
    if (target == nullptr) {
      int sheet = -1;
      for (size_t s = 0; s < sheet_filled.size() && sheet < 0; ++s)
        if (sheet_filled[s] + size.y() <= room.height + 1e-9) sheet = static_cast<int>(s);
      if (sheet < 0) {
        sheet = static_cast<int>(sheet_filled.size());
        sheet_filled.push_back(0.0);
      }
      shelves.push_back({sheet, sheet_filled[sheet], size.y(), 0.0});
      sheet_filled[sheet] += size.y() + options.spacing;
      target = &shelves.back();
    }
    origin[p] = Vec2(options.margin + target->used, options.margin + target->top);
    target->used += size.x() + options.spacing;
    layout.pieces[p].sheet = target->sheet;
    layout.pieces[p].size = size;
  }
  layout.sheets = static_cast<int>(sheet_filled.size());
  return origin;
}

// Piece p's corners and outline curves on its sheet: turned, scaled, y
// flipped so that the sheet shows the side the normals point to (no
// mirror), moved into its box.
void place_piece(const UnfoldResult& unfolded, const std::vector<int>& faces, size_t p, double angle,
                 const Vec2& corner, double mm_per_unit, Layout& layout) {
  const Eigen::Rotation2Dd r(angle);
  Eigen::AlignedBox2d turned;
  for (int f : faces)
    for (int k = 0; k < 3; ++k) turned.extend(r * unfolded.corners.row(3 * f + k).transpose());
  const auto to_sheet = [&](const Vec2& x) {
    const Vec2 q = r * x;
    return Vec2(corner.x() + (q.x() - turned.min().x()) * mm_per_unit,
                corner.y() + (turned.max().y() - q.y()) * mm_per_unit);
  };
  for (int f : faces)
    for (int k = 0; k < 3; ++k)
      layout.corners.row(3 * f + k) = to_sheet(unfolded.corners.row(3 * f + k).transpose()).transpose();
  const UnfoldPiece& piece = unfolded.pieces[p];
  auto& loops = layout.outlines[p];
  loops.assign(piece.outline.size(), {});
  for (size_t l = 0; l < piece.outline.size(); ++l) {
    const bool curve = l < piece.outline_curve.size() && piece.outline_curve[l].size() == piece.outline[l].size();
    for (size_t j = 0; j < piece.outline[l].size(); ++j)
      loops[l].push_back(curve ? to_sheet(piece.outline_curve[l][j])
                               : Vec2(layout.corners.row(piece.outline[l][j]).transpose()));
  }
}

// The piece's label, inside it: at the face centre farthest from its outline
// (sampled: at most 400 faces and 400 outline points per loop), so that it
// sits well inside even a ring or a C-shaped piece, scaled so that its box
// stays within that distance (and at most 10 mm, or 0.12 x the square root
// of the piece's area).
SheetLabel piece_label_inside(const Layout& layout, const std::vector<int>& faces, size_t p) {
  const auto corner = [&](int f, int k) -> Vec2 { return layout.corners.row(3 * f + k).transpose(); };
  double area_sum = 0.0;
  for (int f : faces) area_sum += std::abs(cross2(corner(f, 1) - corner(f, 0), corner(f, 2) - corner(f, 0))) / 2;
  std::vector<Vec2> rim;
  for (const auto& loop : layout.outlines[p]) {
    const size_t step = std::max<size_t>(1, loop.size() / 400);
    for (size_t i = 0; i < loop.size(); i += step) rim.push_back(loop[i]);
  }
  const size_t face_step = std::max<size_t>(1, faces.size() / 400);
  Vec2 best_at = Vec2::Zero();
  double room = -1.0;
  for (size_t i = 0; i < faces.size(); i += face_step) {
    const Vec2 c = (corner(faces[i], 0) + corner(faces[i], 1) + corner(faces[i], 2)) / 3.0;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec2& q : rim) nearest = std::min(nearest, (q - c).norm());
    if (nearest > room) room = nearest, best_at = c;
  }
  SheetLabel label;
  label.text = piece_label(static_cast<int>(p));
  label.sheet = layout.pieces[p].sheet;
  label.at = best_at;
  const Eigen::AlignedBox2d unit = label_box(label.text, Vec2::Zero(), 1.0, 0.0);
  const double fit = room / (0.5 * unit.sizes().norm());
  label.size = std::min({0.12 * std::sqrt(area_sum), fit, 10.0});
  return label;
}

// The match marks of seam s on both sides: a notch at the seam's middle and
// the seam's label beside it, inside the piece, where its box is free in
// `space` (along the seam near its middle, shrunk to half size at most;
// else the label is left out, text empty).
void seam_marks(const UnfoldResult& unfolded, const Triangles& triangles, size_t s, std::vector<LabelSpace>& space,
                Layout& layout) {
  const UnfoldSeam& seam = unfolded.seams[s];
  const double allowance = layout.options.seam_allowance;
  for (int side = 0; side < 2; ++side) {
    const auto corner_at = [&](int f, int v) -> Vec2 {
      for (int k = 0; k < 3; ++k)
        if (triangles(f, k) == v) return layout.corners.row(3 * f + k).transpose();
      return Vec2::Zero();
    };
    // The seam on this side: its points and their arc lengths.
    std::vector<Vec2> points{corner_at(seam.faces[0][side], seam.edges[0][0])};
    std::vector<double> arc{0.0};
    std::vector<int> face_of;
    for (size_t i = 0; i < seam.edges.size(); ++i) {
      const int f = seam.faces[i][side];
      points.push_back(corner_at(f, seam.edges[i][1]));
      arc.push_back(arc.back() + (points.back() - points[points.size() - 2]).norm());
      face_of.push_back(f);
    }
    const double length = arc.back();
    const auto at_arc = [&](double t, Vec2* tangent, Vec2* inward) {
      size_t i = 0;
      while (i + 2 < points.size() && arc[i + 1] < t) ++i;
      const double l = arc[i + 1] - arc[i];
      const Vec2 a = points[i], b = points[i + 1];
      *tangent = l > 0 ? Vec2((b - a) / l) : Vec2(1, 0);
      *inward = Vec2(-tangent->y(), tangent->x());
      const int f = face_of[i];
      const Vec2 centre =
          (corner_at(f, triangles(f, 0)) + corner_at(f, triangles(f, 1)) + corner_at(f, triangles(f, 2))) / 3.0;
      const Vec2 x = a + (b - a) * std::clamp(l > 0 ? (t - arc[i]) / l : 0.5, 0.0, 1.0);
      if (inward->dot(centre - x) < 0) *inward = -*inward;
      return x;
    };
    MatchMark mark;
    mark.seam = static_cast<int>(s);
    mark.side = side;
    Vec2 tangent, inward;
    const Vec2 middle = at_arc(0.5 * length, &tangent, &inward);
    const double size = std::clamp(0.4 * length, 1.2, 3.0);
    mark.notch_from = middle - inward * allowance;  // across the allowance to the cut line
    mark.notch_to = middle + inward * 0.6 * size;
    mark.label.sheet = layout.pieces[side == 0 ? seam.piece_a : seam.piece_b].sheet;
    for (double shrink : {1.0, 0.7, 0.5, 0.35, 0.25}) {
      for (double side_of_seam : {1.3, -1.3}) {  // inside the piece, else outside it
        for (double t : {0.5, 0.35, 0.65, 0.2, 0.8}) {
          const Vec2 x = at_arc(t * length, &tangent, &inward);
          double degrees = std::atan2(tangent.y(), tangent.x()) * 180.0 / M_PI;
          if (degrees > 90.0) degrees -= 180.0;
          if (degrees < -90.0) degrees += 180.0;
          const Vec2 at = x + inward * side_of_seam * size * shrink;
          const Eigen::AlignedBox2d box = label_box(layout.seam_labels[s], at, size * shrink, degrees);
          if (!space[mark.label.sheet].free(box)) continue;
          space[mark.label.sheet].add(box);
          mark.label = {layout.seam_labels[s], mark.label.sheet, at, size * shrink, degrees};
          break;
        }
        if (!mark.label.text.empty()) break;
      }
      if (!mark.label.text.empty()) break;
    }
    if (mark.label.text.empty()) ++layout.labels_left_out;
    layout.marks.push_back(mark);
  }
}

}  // namespace

std::vector<Vec2> outline_on_sheet(const Layout& layout, size_t p, size_t loop) { return layout.outlines[p][loop]; }

std::string piece_label(int index) {
  std::string text;
  for (int i = index + 1; i > 0; i = (i - 1) / 26) text.insert(text.begin(), static_cast<char>('A' + (i - 1) % 26));
  return text;
}

Layout layout_pattern(const UnfoldResult& unfolded, const Triangles& triangles, const LayoutOptions& options,
                      const Progress& progress) {
  check_options(options);
  const Room room = printable_room(options);
  const size_t n_pieces = unfolded.pieces.size();
  const Upright upright = upright_pieces(unfolded, progress);
  Layout layout;
  layout.options = options;
  const double scale = options.scale == 0.0 ? automatic_scale(upright, room, options.unit_mm) : options.scale;
  layout.options.scale = scale;
  const double mm_per_unit = scale * options.unit_mm;
  std::vector<char> stand(n_pieces, 0);
  const int too_big = first_misfit(upright, room, mm_per_unit, &stand);
  if (too_big >= 0) piece_does_not_fit(upright, room, options, scale, too_big);
  std::vector<Vec2> sizes(n_pieces);
  for (size_t p = 0; p < n_pieces; ++p) {
    const Vec2 s = upright.box[p].sizes() * mm_per_unit + Vec2::Constant(2.0 * room.reserve);
    sizes[p] = stand[p] ? Vec2(s.y(), s.x()) : s;
  }
  layout.pieces.resize(n_pieces);
  const std::vector<Vec2> origin = shelve(sizes, room, options, layout);

  layout.corners.setZero(unfolded.corners.rows(), 2);
  layout.outlines.resize(n_pieces);
  std::vector<std::vector<int>> faces_of(n_pieces);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    faces_of[unfolded.piece_of_face[f]].push_back(static_cast<int>(f));
  std::vector<LabelSpace> space(static_cast<size_t>(layout.sheets));
  for (size_t p = 0; p < n_pieces; ++p) {
    if (p % 64 == 0) progress.report(0.5 + 0.4 * p / n_pieces, "laying out");
    place_piece(unfolded, faces_of[p], p, upright.turn[p] + (stand[p] ? M_PI / 2 : 0.0),
                origin[p] + Vec2::Constant(room.reserve), mm_per_unit, layout);
    // The cut line: the outline offset by the allowance, drawn to within
    // kCutLineTolerance.
    if (options.seam_allowance > 0.0) {
      OffsetOutline cut = offset_outline(outline_on_sheet(layout, p), options.seam_allowance, kCutLineTolerance);
      layout.pieces[p].cut_line = std::move(cut.points);
      layout.pieces[p].cut_line_from_hull = cut.from_hull;
    }
    layout.pieces[p].label = piece_label_inside(layout, faces_of[p], p);
    const SheetLabel& label = layout.pieces[p].label;
    space[label.sheet].add(label_box(label.text, label.at, label.size, label.angle));
  }
  // Match marks: the same label on both sides of every seam.
  for (size_t s = 0; s < unfolded.seams.size(); ++s) layout.seam_labels.push_back(std::to_string(s + 1));
  for (size_t s = 0; s < unfolded.seams.size(); ++s) seam_marks(unfolded, triangles, s, space, layout);
  if (options.glue_tabs > 0.0) add_tabs(unfolded, triangles, options.glue_tabs, layout);
  return layout;
}

}  // namespace developable

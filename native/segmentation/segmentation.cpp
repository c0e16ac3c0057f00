#include "segmentation/segmentation.h"

#include "core/cone_fit.h"
#include "core/measures.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <queue>
#include <tuple>
#include <vector>

namespace developable {

namespace {

// Defaults and weights; docs/segmentation.md tells how they were measured.
constexpr double kDefaultMaxFitError = 0.1;  // rad, area-weighted RMS
// An edge whose face normals differ by more than this is a crease: a chart
// holding one is split there. Above 22.5 deg so that a 16-sided cylinder is
// not a fold of 16 planes; below 30 deg so that a sheet folded to 150 deg is.
constexpr double kCreaseAngle = 0.4363323129985824;  // 25 deg
// Scale of the normal jump in the growth and merge costs: smaller than
// kCreaseAngle so that boundaries also follow the softer folds of a
// piecewise developable model.
constexpr double kFoldAngle = 0.2617993877991494;  // 15 deg
constexpr double kCompactnessWeight = 0.5;
constexpr double kBoundaryWeight = 1.0;
constexpr double kFoldWeight = 10.0;
constexpr int kMinPatchFaces = 20;
constexpr double kMinPatchAreaFraction = 0.01;
constexpr int kSplitRounds = 2;   // Lloyd rounds after each batch of new seeds
constexpr int kSettleRounds = 4;  // Lloyd rounds once the count is fixed
constexpr int kMaxSplitIterations = 8;
constexpr int kMaxSeedsPerSplit = 4;
constexpr double kSettledFraction = 1e-3;

constexpr const char* kStage = "segmentation";

// Fewest faces of a patch: kMinPatchFaces, scaled down on coarse meshes (a
// 40-face cube keeps its 8-face sides).
int min_patch_faces(int face_count) { return std::min(kMinPatchFaces, face_count / 50); }

// Per-face geometry, computed once.
struct FaceGeometry {
  std::vector<Eigen::Vector3d> normal;  // unit
  std::vector<double> area;
  std::vector<Eigen::Vector3d> centroid;
  double total_area = 0.0;
};

// Edge i of face f joins its corners i and (i + 1) % 3.
struct FaceAdjacency {
  std::vector<std::array<int, 3>> neighbour;  // -1 on a boundary edge
  std::vector<std::array<double, 3>> length;  // edge length
  std::vector<std::array<double, 3>> jump;    // angle between the two face normals, rad
  std::vector<double> perimeter;
};

// A chart while growing: its seed face, its cone, and its area in the last
// labelling (the scale of the compactness term).
struct Chart {
  int seed = 0;
  Cone cone;
  double area = 0.0;
};

// What the cost terms are measured against.
struct GrowthScale {
  double max_fit_error = kDefaultMaxFitError;
};

FaceGeometry face_geometry(const Positions& positions, const Triangles& triangles, const Normals& normals,
                           const Eigen::VectorXd& areas) {
  const Eigen::Index face_count = triangles.rows();
  FaceGeometry geometry;
  geometry.normal.resize(face_count);
  geometry.area.resize(face_count);
  geometry.centroid.resize(face_count);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    geometry.normal[f] = normals.row(f).transpose();
    geometry.area[f] = areas[f];
    geometry.centroid[f] = face_centroid(positions, triangles, f);
    geometry.total_area += geometry.area[f];
  }
  return geometry;
}

// Face adjacency through the vertex -> faces table (face_across).
FaceAdjacency face_adjacency(const Positions& positions, const Triangles& triangles, const VertexFaces& table,
                             const FaceGeometry& geometry) {
  const int face_count = static_cast<int>(triangles.rows());
  FaceAdjacency adjacency;
  adjacency.neighbour.resize(face_count);
  adjacency.length.resize(face_count);
  adjacency.jump.resize(face_count);
  adjacency.perimeter.assign(face_count, 0.0);
  for (int f = 0; f < face_count; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = triangles(f, i);
      const int b = triangles(f, (i + 1) % 3);
      const int across = face_across(table, triangles, f, a, b);
      adjacency.neighbour[f][i] = across;
      adjacency.length[f][i] = (positions.row(a) - positions.row(b)).norm();
      adjacency.perimeter[f] += adjacency.length[f][i];
      adjacency.jump[f][i] =
          across < 0 ? 0.0 : std::acos(std::clamp(geometry.normal[f].dot(geometry.normal[across]), -1.0, 1.0));
    }
  }
  return adjacency;
}

// Edge-connected components; returns the component of each face and the count.
std::pair<std::vector<int>, int> face_components(const FaceAdjacency& adjacency) {
  const int face_count = static_cast<int>(adjacency.neighbour.size());
  std::vector<int> component(face_count, -1);
  std::vector<int> stack;
  int count = 0;
  for (int start = 0; start < face_count; ++start) {
    if (component[start] >= 0) continue;
    component[start] = count;
    stack.push_back(start);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (const int g : adjacency.neighbour[f]) {
        if (g >= 0 && component[g] < 0) {
          component[g] = count;
          stack.push_back(g);
        }
      }
    }
    ++count;
  }
  return {component, count};
}

// A new chart's cone before it has faces to fit: the plane of its seed.
Chart chart_at(const FaceGeometry& geometry, int seed, double area) {
  Chart chart;
  chart.seed = seed;
  chart.cone.axis = geometry.normal[seed];
  chart.cone.angle = 0.0;
  chart.area = area;
  return chart;
}

// Grows every chart from its seed at once, a face at a time, always taking the
// cheapest (chart, face) pair on the front. Cost of face f for chart c:
//   (angle of n_f to c's cone / max_fit_error)^2           fitting
// + kCompactnessWeight * pi |x_f - x_seed|^2 / area(c)     compactness
// + kBoundaryWeight * (f's perimeter not on c) / perimeter  boundary straightness
// + kFoldWeight * (normal jump over the entry edge / kFoldAngle)^2
// A face only joins through an edge with the chart, so every chart stays
// edge-connected; every face is reached when each component holds a seed.
std::vector<int> grow_charts(const FaceGeometry& geometry, const FaceAdjacency& adjacency,
                             const std::vector<Chart>& charts, const GrowthScale& scale) {
  const int face_count = static_cast<int>(adjacency.neighbour.size());
  std::vector<int> label(face_count, -1);
  // Only the cheapest entry queued for a face can win it, so each face keeps
  // one live entry: its cost and chart here, the key (cost bits, face) in the
  // queue. Non-negative floats order like their bit patterns; equal costs
  // fall back to the face id, which keeps the growth deterministic.
  std::vector<float> queued_cost(face_count, HUGE_VALF);
  std::vector<int> queued_chart(face_count, -1);
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<std::uint64_t>> front;
  const auto key = [](float cost, int face) {
    std::uint32_t bits;
    std::memcpy(&bits, &cost, sizeof bits);
    return (static_cast<std::uint64_t>(bits) << 32) | static_cast<std::uint32_t>(face);
  };
  const double inverse_tolerance = 1.0 / scale.max_fit_error;

  const auto push_neighbours = [&](int f, int c) {
    const Chart& chart = charts[c];
    for (int i = 0; i < 3; ++i) {
      const int g = adjacency.neighbour[f][i];
      if (g < 0 || label[g] >= 0) continue;
      double inner = 0.0;
      for (int k = 0; k < 3; ++k) {
        const int h = adjacency.neighbour[g][k];
        if (h >= 0 && label[h] == c) inner += adjacency.length[g][k];
      }
      const double fit = angle_to_cone(chart.cone, geometry.normal[g]) * inverse_tolerance;
      const double distance2 = (geometry.centroid[g] - geometry.centroid[chart.seed]).squaredNorm();
      const double fold = adjacency.jump[f][i] / kFoldAngle;
      const float cost =
          static_cast<float>(fit * fit + kCompactnessWeight * M_PI * distance2 / chart.area +
                             kBoundaryWeight * (1.0 - inner / adjacency.perimeter[g]) + kFoldWeight * fold * fold);
      if (cost < queued_cost[g]) {
        queued_cost[g] = cost;
        queued_chart[g] = c;
        front.push(key(cost, g));
      }
    }
  };

  for (int c = 0; c < static_cast<int>(charts.size()); ++c) label[charts[c].seed] = c;
  for (int c = 0; c < static_cast<int>(charts.size()); ++c) push_neighbours(charts[c].seed, c);
  while (!front.empty()) {
    const std::uint64_t top = front.top();
    front.pop();
    const int f = static_cast<int>(top & 0xffffffffu);
    if (label[f] >= 0 || top != key(queued_cost[f], f)) continue;  // taken, or outbid
    label[f] = queued_chart[f];
    push_neighbours(f, label[f]);
  }
  return label;
}

// Per-chart fit of a labelling.
struct ChartFit {
  NormalMoments moments;
  Cone cone;
  double area = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // area-weighted face centroid
  int face_count = 0;
};

std::vector<ChartFit> fit_charts(const FaceGeometry& geometry, const std::vector<int>& label, int chart_count) {
  std::vector<ChartFit> fits(chart_count);
  for (int f = 0; f < static_cast<int>(label.size()); ++f) {
    ChartFit& fit = fits[label[f]];
    const double area = geometry.area[f];
    fit.moments.add(geometry.normal[f], area);
    fit.area += area;
    fit.centroid += area * geometry.centroid[f];
    ++fit.face_count;
  }
  for (ChartFit& fit : fits) {
    fit.cone = fit_cone(fit.moments).cone;
    fit.centroid /= fit.area;
  }
  return fits;
}

// Angle of every face's normal to its chart's cone.
std::vector<double> face_fit_errors(const FaceGeometry& geometry, const std::vector<int>& label,
                                    const std::vector<ChartFit>& fits) {
  std::vector<double> error(label.size());
  for (int f = 0; f < static_cast<int>(label.size()); ++f)
    error[f] = angle_to_cone(fits[label[f]].cone, geometry.normal[f]);
  return error;
}

// Area-weighted RMS of the face errors, per chart.
std::vector<double> chart_rms_errors(const FaceGeometry& geometry, const std::vector<int>& label,
                                     const std::vector<double>& error, const std::vector<ChartFit>& fits) {
  std::vector<double> rms(fits.size(), 0.0);
  for (int f = 0; f < static_cast<int>(label.size()); ++f) rms[label[f]] += geometry.area[f] * error[f] * error[f];
  for (size_t c = 0; c < fits.size(); ++c) rms[c] = std::sqrt(rms[c] / fits[c].area);
  return rms;
}

// Charts (seed, cone, area) of a labelling with ids 0 .. chart_count-1, each
// seeded at the face that best fits its cone near the chart's centroid.
std::vector<Chart> charts_of(const FaceGeometry& geometry, const GrowthScale& scale, const std::vector<int>& label,
                             int chart_count) {
  const std::vector<ChartFit> fits = fit_charts(geometry, label, chart_count);
  std::vector<Chart> charts(chart_count);
  std::vector<double> best_score(chart_count, HUGE_VAL);
  const double inverse_tolerance = 1.0 / scale.max_fit_error;
  for (int f = 0; f < static_cast<int>(label.size()); ++f) {
    const ChartFit& fit = fits[label[f]];
    const double error = angle_to_cone(fit.cone, geometry.normal[f]) * inverse_tolerance;
    const double distance2 = (geometry.centroid[f] - fit.centroid).squaredNorm();
    const double score = error * error + kCompactnessWeight * M_PI * distance2 / fit.area;
    if (score < best_score[label[f]]) {
      best_score[label[f]] = score;
      charts[label[f]].seed = f;
    }
  }
  for (int c = 0; c < chart_count; ++c) {
    charts[c].cone = fits[c].cone;
    charts[c].area = fits[c].area;
  }
  return charts;
}

// Lloyd rounds: grow, refit each chart's cone, move each seed to the face that
// best fits its cone near the chart's centroid; stop when the labels repeat
// (up to kSettledFraction of the faces: boundaries can flicker by a face).
// `label` holds the previous labelling (or is empty) and is updated in place.
// Reports `fraction` after each round (a round of a million faces takes ~0.3 s).
void lloyd(const FaceGeometry& geometry, const FaceAdjacency& adjacency, const GrowthScale& scale, int max_rounds,
           const Progress& progress, double fraction, std::vector<Chart>& charts, std::vector<int>& label) {
  const int chart_count = static_cast<int>(charts.size());
  for (int round = 0; round < max_rounds; ++round) {
    std::vector<int> grown = grow_charts(geometry, adjacency, charts, scale);
    charts = charts_of(geometry, scale, grown, chart_count);
    size_t changed = grown.size();
    if (label.size() == grown.size()) {
      changed = 0;
      for (size_t f = 0; f < grown.size(); ++f) changed += grown[f] != label[f];
    }
    const bool settled = changed <= kSettledFraction * static_cast<double>(grown.size());
    label = std::move(grown);
    progress.report(fraction, kStage);
    if (settled) break;
  }
}

// The face beside the chart's sharpest interior crease edge, on the side away
// from the seed, or -1 when the chart holds no edge sharper than kCreaseAngle.
std::vector<int> crease_faces(const FaceGeometry& geometry, const FaceAdjacency& adjacency,
                              const std::vector<int>& label, const std::vector<Chart>& charts) {
  std::vector<int> face(charts.size(), -1);
  std::vector<double> sharpest(charts.size(), kCreaseAngle);
  for (int f = 0; f < static_cast<int>(label.size()); ++f) {
    for (int i = 0; i < 3; ++i) {
      const int g = adjacency.neighbour[f][i];
      if (g < f || label[g] != label[f] || adjacency.jump[f][i] <= sharpest[label[f]]) continue;
      const int c = label[f];
      sharpest[c] = adjacency.jump[f][i];
      const Eigen::Vector3d seed = geometry.centroid[charts[c].seed];
      face[c] = (geometry.centroid[f] - seed).squaredNorm() >= (geometry.centroid[g] - seed).squaredNorm() ? f : g;
    }
  }
  return face;
}

// Adds seeds to every chart that fits worse than max_fit_error or folds over a
// crease, unless the chart is too small to split. A badly fitting chart gets
// about (rms / max_fit_error)^2 - 1 seeds (up to kMaxSeedsPerSplit; the error
// of a curved chart grows with its diameter), at its worst faces, spaced by
// the radius of the pieces it should split into; a creased chart gets one,
// beside the crease. With `forced` > 0, instead adds one seed to each of that
// many worst charts, whatever their error. Returns the number added.
int add_split_seeds(const FaceGeometry& geometry, const FaceAdjacency& adjacency, const GrowthScale& scale,
                    int max_charts, int forced, std::vector<Chart>& charts, const std::vector<int>& label) {
  const int chart_count = static_cast<int>(charts.size());
  const int face_count = static_cast<int>(label.size());
  const std::vector<ChartFit> fits = fit_charts(geometry, label, chart_count);
  const std::vector<double> error = face_fit_errors(geometry, label, fits);
  const std::vector<double> rms = chart_rms_errors(geometry, label, error, fits);
  std::vector<int> worst(chart_count, -1);
  for (int f = 0; f < face_count; ++f) {
    const int c = label[f];
    if (f != charts[c].seed && (worst[c] < 0 || error[f] > error[worst[c]])) worst[c] = f;
  }

  std::vector<std::pair<int, int>> new_seeds;  // chart split, seed face
  std::vector<int> wanted(chart_count, 0);
  std::vector<double> spacing2(chart_count, 0.0);
  if (forced > 0) {
    // The charts with the largest fitting energy (area * rms^2): large and
    // badly fitting charts before tiny noisy ones.
    std::vector<int> order;
    for (int c = 0; c < chart_count; ++c)
      if (worst[c] >= 0) order.push_back(c);
    const auto energy = [&](int c) { return fits[c].area * rms[c] * rms[c]; };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return energy(a) > energy(b); });
    for (int i = 0; i < std::min(forced, static_cast<int>(order.size())); ++i) {
      wanted[order[i]] = 1;
      spacing2[order[i]] = fits[order[i]].area / (2.0 * M_PI);
    }
  } else {
    const std::vector<int> crease = crease_faces(geometry, adjacency, label, charts);
    const double min_area = kMinPatchAreaFraction * geometry.total_area;
    const int min_faces = min_patch_faces(face_count);
    for (int c = 0; c < chart_count; ++c) {
      if (fits[c].face_count < 2 * min_faces || fits[c].area < 2.0 * min_area) continue;
      if (rms[c] > scale.max_fit_error && worst[c] >= 0) {
        const double ratio = rms[c] / scale.max_fit_error;
        const int by_size =
            std::min(fits[c].face_count / std::max(min_faces, 1), static_cast<int>(fits[c].area / min_area)) - 1;
        // ratio^2 is capped before the cast: a tiny max_fit_error makes it
        // overflow an int, and every count past kMaxSeedsPerSplit is cut anyway.
        const int by_error = static_cast<int>(std::ceil(std::min(ratio * ratio, double(kMaxSeedsPerSplit) + 1.0))) - 1;
        wanted[c] = std::clamp(by_error, 1, std::max(1, std::min(kMaxSeedsPerSplit, by_size)));
        spacing2[c] = fits[c].area / (M_PI * (wanted[c] + 1));
      } else if (crease[c] >= 0 && crease[c] != charts[c].seed) {
        new_seeds.emplace_back(c, crease[c]);
      }
    }
  }
  // Worst faces first; ties by face id.
  std::vector<int> order;
  for (int f = 0; f < face_count; ++f)
    if (wanted[label[f]] > 0 && (forced > 0 || error[f] > scale.max_fit_error)) order.push_back(f);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return error[a] > error[b]; });
  std::vector<std::vector<int>> chosen(chart_count);
  for (const int f : order) {
    const int c = label[f];
    if (static_cast<int>(chosen[c].size()) >= wanted[c] || f == charts[c].seed) continue;
    bool spaced = (geometry.centroid[f] - geometry.centroid[charts[c].seed]).squaredNorm() >= spacing2[c];
    for (const int g : chosen[c])
      spaced = spaced && (geometry.centroid[f] - geometry.centroid[g]).squaredNorm() >= spacing2[c];
    if (spaced) chosen[c].push_back(f);
  }
  for (int c = 0; c < chart_count; ++c) {
    if (wanted[c] > 0 && chosen[c].empty()) chosen[c].push_back(worst[c]);
    for (const int f : chosen[c]) new_seeds.emplace_back(c, f);
  }
  if (chart_count + static_cast<int>(new_seeds.size()) > max_charts)
    new_seeds.resize(std::max(0, max_charts - chart_count));
  std::vector<int> pieces(chart_count, 1);
  for (const auto& [c, seed] : new_seeds) ++pieces[c];
  for (const auto& [c, seed] : new_seeds) charts.push_back(chart_at(geometry, seed, fits[c].area / pieces[c]));
  for (int c = 0; c < chart_count; ++c) charts[c].area = fits[c].area / pieces[c];
  return static_cast<int>(new_seeds.size());
}

// Greedy merging of adjacent charts. Merge cost of charts a and b, unitless:
//   (increase of the cone-fit residual) / ((area(a) + area(b)) max_fit_error^2)
// + (mean normal jump along their shared border / kFoldAngle)^2
// so that charts whose union still fits one cone and that meet smoothly go
// first. Chart ids stay those of the input labelling; labels() renumbers.
class ChartMerger {
 public:
  ChartMerger(const FaceGeometry& geometry, const FaceAdjacency& adjacency, const std::vector<int>& label,
              int chart_count, const GrowthScale& scale)
      : geometry_(geometry),
        label_(label),
        scale_(scale),
        parent_(chart_count),
        alive_(chart_count, true),
        moments_(chart_count),
        faces_(chart_count),
        borders_(chart_count),
        count_(chart_count) {
    for (int c = 0; c < chart_count; ++c) parent_[c] = c;
    for (int f = 0; f < static_cast<int>(label.size()); ++f) {
      moments_[label[f]].add(geometry.normal[f], geometry.area[f]);
      faces_[label[f]].push_back(f);
      for (int i = 0; i < 3; ++i) {
        const int g = adjacency.neighbour[f][i];
        if (g < 0 || label[g] == label[f]) continue;
        Border& border = borders_[label[f]][label[g]];
        border.length += adjacency.length[f][i];
        border.jump_length += adjacency.length[f][i] * adjacency.jump[f][i];
      }
    }
    residual_.resize(chart_count);
    for (int c = 0; c < chart_count; ++c) residual_[c] = fit_cone(moments_[c]).residual;
  }

  int count() const { return count_; }
  bool alive(int c) const { return alive_[c]; }
  double area(int c) const { return moments_[c].weight; }
  int face_count(int c) const { return static_cast<int>(faces_[c].size()); }
  bool has_neighbour(int c) const { return !borders_[c].empty(); }

  // Mean normal jump (rad) over the border of two adjacent charts.
  double border_jump(int a, int b) const {
    const Border& border = borders_[a].at(b);
    return border.jump_length / border.length;
  }

  double merge_cost(int a, int b) const {
    NormalMoments merged = moments_[a];
    merged += moments_[b];
    const double increase = fit_cone(merged).residual - residual_[a] - residual_[b];
    const double jump = border_jump(a, b) / kFoldAngle;
    return std::max(increase, 0.0) / (merged.weight * scale_.max_fit_error * scale_.max_fit_error) + jump * jump;
  }

  // Whether the union of two adjacent charts still fits one cone within
  // max_fit_error (area-weighted RMS angle) and they do not meet at a crease.
  bool union_fits(int a, int b) const {
    if (border_jump(a, b) >= kCreaseAngle) return false;
    NormalMoments merged = moments_[a];
    merged += moments_[b];
    const ConeFit fit = fit_cone(merged);
    // |cos x - cos y| <= |x - y|: the algebraic RMS bounds the angular one from
    // below and rejects most pairs without a pass over their faces.
    const double bound2 = scale_.max_fit_error * scale_.max_fit_error * merged.weight;
    if (fit.residual > bound2) return false;
    double sum = 0.0;
    for (const int c : {a, b})
      for (const int f : faces_[c]) {
        const double error = angle_to_cone(fit.cone, geometry_.normal[f]);
        sum += geometry_.area[f] * error * error;
      }
    return sum <= bound2;
  }

  // The neighbour of c that is cheapest to merge with (ties: lowest id).
  int cheapest_neighbour(int c) const {
    int best = -1;
    double best_cost = HUGE_VAL;
    for (const auto& [d, border] : borders_[c]) {
      const double cost = merge_cost(c, d);
      if (best < 0 || cost < best_cost) {
        best_cost = cost;
        best = d;
      }
    }
    return best;
  }

  std::vector<int> neighbours(int c) const {
    std::vector<int> ids;
    for (const auto& [d, border] : borders_[c]) ids.push_back(d);
    return ids;
  }

  // Absorbs chart b into chart a.
  void merge(int a, int b) {
    moments_[a] += moments_[b];
    residual_[a] = fit_cone(moments_[a]).residual;
    faces_[a].insert(faces_[a].end(), faces_[b].begin(), faces_[b].end());
    faces_[b].clear();
    faces_[b].shrink_to_fit();
    for (const auto& [d, border] : borders_[b]) {
      if (d == a) continue;
      Border& into = borders_[a][d];
      into.length += border.length;
      into.jump_length += border.jump_length;
      Border& back = borders_[d][a];
      back.length += border.length;
      back.jump_length += border.jump_length;
      borders_[d].erase(b);
    }
    borders_[a].erase(b);
    borders_[b].clear();
    alive_[b] = false;
    parent_[b] = a;
    --count_;
  }

  // The labels after the merges, renumbered 0 .. k-1 in order of first face.
  std::vector<int> labels() const {
    std::vector<int> id(parent_.size(), -1);
    std::vector<int> out(label_.size());
    int next = 0;
    for (size_t f = 0; f < label_.size(); ++f) {
      int c = label_[f];
      while (parent_[c] != c) c = parent_[c];
      if (id[c] < 0) id[c] = next++;
      out[f] = id[c];
    }
    return out;
  }

 private:
  struct Border {
    double length = 0.0;
    double jump_length = 0.0;  // sum of length * normal jump over the border edges
  };

  const FaceGeometry& geometry_;
  std::vector<int> label_;
  GrowthScale scale_;
  std::vector<int> parent_;
  std::vector<bool> alive_;
  std::vector<NormalMoments> moments_;
  std::vector<double> residual_;
  std::vector<std::vector<int>> faces_;
  std::vector<std::map<int, Border>> borders_;  // ordered: deterministic iteration
  int count_;
};

// Merges adjacent charts whose union still fits (ChartMerger::union_fits),
// cheapest first: undoes splits that Lloyd rounds made unnecessary and seeds
// that landed on a piece another chart already fits.
std::vector<int> merge_fitting_charts(const FaceGeometry& geometry, const FaceAdjacency& adjacency,
                                      const std::vector<int>& label, int chart_count, const GrowthScale& scale) {
  ChartMerger merger(geometry, adjacency, label, chart_count, scale);
  // Candidate pairs by cost; a pair is stale once either chart has changed.
  using Candidate = std::tuple<double, int, int, int, int>;  // cost, a, b, versions
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> candidates;
  std::vector<int> version(chart_count, 0);
  const auto push_pairs = [&](int a) {
    for (const int b : merger.neighbours(a))
      candidates.emplace(merger.merge_cost(a, b), std::min(a, b), std::max(a, b), version[std::min(a, b)],
                         version[std::max(a, b)]);
  };
  for (int a = 0; a < chart_count; ++a) push_pairs(a);
  while (!candidates.empty()) {
    const auto [cost, a, b, version_a, version_b] = candidates.top();
    candidates.pop();
    if (!merger.alive(a) || !merger.alive(b) || version[a] != version_a || version[b] != version_b ||
        !merger.union_fits(a, b))
      continue;
    const int kept = merger.area(a) >= merger.area(b) ? a : b;
    merger.merge(kept, kept == a ? b : a);
    ++version[kept];
    push_pairs(kept);
  }
  return merger.labels();
}

// Merges every chart smaller than min_patch_faces() faces or
// kMinPatchAreaFraction of the area into its cheapest neighbour, smallest
// first, while more than `fewest_charts` remain.
std::vector<int> merge_small_charts(const FaceGeometry& geometry, const FaceAdjacency& adjacency,
                                    const std::vector<int>& label, int chart_count, int fewest_charts,
                                    const GrowthScale& scale) {
  ChartMerger merger(geometry, adjacency, label, chart_count, scale);
  const int min_faces = min_patch_faces(static_cast<int>(label.size()));
  const double min_area = kMinPatchAreaFraction * geometry.total_area;
  while (merger.count() > fewest_charts) {
    int smallest = -1;
    for (int c = 0; c < chart_count; ++c) {
      if (!merger.alive(c) || !merger.has_neighbour(c)) continue;
      if (merger.face_count(c) >= min_faces && merger.area(c) >= min_area) continue;
      if (smallest < 0 || merger.area(c) < merger.area(smallest)) smallest = c;
    }
    if (smallest < 0) break;
    merger.merge(merger.cheapest_neighbour(smallest), smallest);
  }
  return merger.labels();
}

// Merges the cheapest adjacent pairs until `target` charts remain (or no two
// charts touch: separate components never merge).
std::vector<int> merge_to_count(const FaceGeometry& geometry, const FaceAdjacency& adjacency,
                                const std::vector<int>& label, int chart_count, int target, const GrowthScale& scale) {
  ChartMerger merger(geometry, adjacency, label, chart_count, scale);
  while (merger.count() > target) {
    int best_a = -1;
    int best_b = -1;
    double best_cost = HUGE_VAL;
    for (int a = 0; a < chart_count; ++a) {
      if (!merger.alive(a)) continue;
      const int b = merger.cheapest_neighbour(a);
      if (b < 0) continue;
      const double cost = merger.merge_cost(a, b);
      if (best_a < 0 || cost < best_cost) {
        best_cost = cost;
        best_a = a;
        best_b = b;
      }
    }
    if (best_a < 0) break;
    // Keep the larger chart's id so that its seed and cone stay meaningful.
    if (merger.area(best_b) > merger.area(best_a)) std::swap(best_a, best_b);
    merger.merge(best_a, best_b);
  }
  return merger.labels();
}

}  // namespace

std::vector<int> segment_mesh(const Positions& positions, const Triangles& triangles,
                              const SegmentationOptions& options, const Progress& progress) {
  return segment_mesh(positions, triangles, face_normals(positions, triangles), face_areas(positions, triangles),
                      vertex_faces(triangles, positions.rows()), options, progress);
}

std::vector<int> segment_mesh(const Positions& positions, const Triangles& triangles, const Normals& normals,
                              const Eigen::VectorXd& areas, const VertexFaces& table,
                              const SegmentationOptions& options, const Progress& progress) {
  if (triangles.rows() == 0 || positions.rows() == 0)
    throw EngineError(Status::empty_input, "segmentation: the mesh has no triangles");
  if (options.max_fit_error < 0.0 || !std::isfinite(options.max_fit_error))
    throw EngineError(Status::invalid_argument, "segmentation: max_fit_error must be finite and >= 0");
  if (options.target_patches < 0)
    throw EngineError(Status::invalid_argument, "segmentation: target_patches must be >= 0");

  progress.report(0.0, kStage);
  GrowthScale scale;
  if (options.max_fit_error > 0.0) scale.max_fit_error = options.max_fit_error;
  const FaceGeometry geometry = face_geometry(positions, triangles, normals, areas);
  const FaceAdjacency adjacency = face_adjacency(positions, triangles, table, geometry);
  const auto [component, component_count] = face_components(adjacency);
  const int face_count = static_cast<int>(triangles.rows());

  // One seed per component, at its first face.
  std::vector<Chart> charts;
  for (int f = 0, next = 0; f < face_count && next < component_count; ++f) {
    if (component[f] == next) {
      charts.push_back(chart_at(geometry, f, geometry.total_area / component_count));
      ++next;
    }
  }
  std::vector<int> label;
  lloyd(geometry, adjacency, scale, kSplitRounds, progress, 0.05, charts, label);

  // Split until every chart fits (or is too small to split).
  const int max_charts = std::max(component_count, static_cast<int>(2.0 / kMinPatchAreaFraction));
  for (int iteration = 0; iteration < kMaxSplitIterations; ++iteration) {
    if (add_split_seeds(geometry, adjacency, scale, max_charts, 0, charts, label) == 0) break;
    lloyd(geometry, adjacency, scale, kSplitRounds, progress, 0.05 + 0.6 * (iteration + 1) / kMaxSplitIterations,
          charts, label);
  }
  const auto count_of = [](const std::vector<int>& labels) {
    return *std::max_element(labels.begin(), labels.end()) + 1;
  };

  if (options.target_patches > 0) {
    const int target = std::min(options.target_patches, face_count);
    while (static_cast<int>(charts.size()) < target) {
      const int missing = target - static_cast<int>(charts.size());
      if (add_split_seeds(geometry, adjacency, scale, face_count, missing, charts, label) == 0) break;
      lloyd(geometry, adjacency, scale, kSplitRounds, progress, 0.7, charts, label);
    }
    // Small charts go first (never below the target), then the cheapest pairs;
    // no Lloyd round after the last merge, since it could starve a chart.
    label = merge_small_charts(geometry, adjacency, label, count_of(label), target, scale);
    charts = charts_of(geometry, scale, label, count_of(label));
    lloyd(geometry, adjacency, scale, kSettleRounds, progress, 0.9, charts, label);
    label = merge_small_charts(geometry, adjacency, label, count_of(label), target, scale);
    label = merge_to_count(geometry, adjacency, label, count_of(label), target, scale);
    progress.report(1.0, kStage);
    return label;
  }

  label = merge_fitting_charts(geometry, adjacency, label, count_of(label), scale);
  label = merge_small_charts(geometry, adjacency, label, count_of(label), 1, scale);
  charts = charts_of(geometry, scale, label, count_of(label));
  lloyd(geometry, adjacency, scale, kSettleRounds, progress, 0.9, charts, label);
  label = merge_small_charts(geometry, adjacency, label, count_of(label), 1, scale);
  progress.report(1.0, kStage);
  return label;
}

}  // namespace developable

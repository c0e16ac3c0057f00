#include "pipeline/thinned_pieces.h"

#include "core/measures.h"
#include "deformation/deformation.h"
#include "deformation/move_limit.h"
#include "deformation/ruled_polish.h"
#include "ideal_curve/gauss_thinning.h"
#include "pipeline/patches.h"
#include "segmentation/curved_pieces.h"
#include "segmentation/normal_jump_pieces.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

// A face collapses when its area falls under this share of the input's, or
// its smallest angle under kCollapsedAngleShare of the input's: its normal is
// then noise.
constexpr double kCollapsedAreaShare = 0.1;
constexpr double kCollapsedAngleShare = 0.25;
// Rounds of putting corners back before a step is dropped.
constexpr int kPutBackRounds = 20;
// Small pieces: fewer faces than this, or than faces / kSmallPieceShare.
constexpr int kSmallPieceFaces = 20;
constexpr Eigen::Index kSmallPieceShare = 500;

double smallest_angle(const Positions& p, const Triangles& t, Eigen::Index f) {
  double smallest = M_PI;
  for (int c = 0; c < 3; ++c) {
    const Eigen::RowVector3d u = p.row(t(f, (c + 1) % 3)) - p.row(t(f, c));
    const Eigen::RowVector3d w = p.row(t(f, (c + 2) % 3)) - p.row(t(f, c));
    smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)));
  }
  return smallest;
}

// What a thinning step may not do: turn a face over against the input,
// collapse it, or crease an edge inside a piece (guard).
class StepGuard {
 public:
  StepGuard(const MeasuredInput& input, CreaseGuard crease) : input_(input), crease_(std::move(crease)) {
    const Eigen::Index m = input.triangles.rows();
    smallest_.resize(m);
    for (Eigen::Index f = 0; f < m; ++f) smallest_[f] = smallest_angle(input.positions, input.triangles, f);
  }

  std::vector<Eigen::Index> bad_faces(const Positions& p, const Normals& normals) const {
    std::vector<Eigen::Index> bad = folded_faces(normals, input_.normals, crease_);
    const Eigen::VectorXd areas = face_areas(p, input_.triangles);
    for (Eigen::Index f = 0; f < p.rows() && f < input_.triangles.rows(); ++f)
      if (areas[f] < kCollapsedAreaShare * input_.areas[f] ||
          smallest_angle(p, input_.triangles, f) < kCollapsedAngleShare * smallest_[f])
        bad.push_back(f);
    std::sort(bad.begin(), bad.end());
    bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
    return bad;
  }

  // `next` with the corners of its bad faces put back where `previous` has
  // them, ring by ring; `previous` itself when that does not clear them.
  void put_back(Positions& next, const Positions& previous) const {
    for (int round = 0; round < kPutBackRounds; ++round) {
      const std::vector<Eigen::Index> bad = bad_faces(next, face_normals(next, input_.triangles));
      if (bad.empty()) return;
      for (Eigen::Index f : bad)
        for (int c = 0; c < 3; ++c) next.row(input_.triangles(f, c)) = previous.row(input_.triangles(f, c));
    }
    if (!bad_faces(next, face_normals(next, input_.triangles)).empty()) next = previous;
  }

  // The corners of the bad faces of `p` put back where the input has them,
  // ring by ring, until none is bad (the input has none); returns the count
  // of vertices put back.
  Eigen::Index heal(Positions& p) const {
    std::vector<bool> healed(static_cast<size_t>(p.rows()), false);
    for (;;) {
      const std::vector<Eigen::Index> bad = bad_faces(p, face_normals(p, input_.triangles));
      if (bad.empty()) break;
      for (Eigen::Index f : bad)
        for (int c = 0; c < 3; ++c) {
          const int v = input_.triangles(f, c);
          p.row(v) = input_.positions.row(v);
          healed[static_cast<size_t>(v)] = true;
        }
    }
    return std::count(healed.begin(), healed.end(), true);
  }

 private:
  const MeasuredInput& input_;
  CreaseGuard crease_;
  Eigen::VectorXd smallest_;
};

// `iterations` thinning steps from `current` (pieces: empty or per face).
void thin(const MeasuredInput& input, NormalGuidedDeformation& deformation, const StepGuard& guard,
          const std::vector<int>& pieces, int iterations, Positions& current, const Progress& progress) {
  const double radius = kThinningRadius * input.measured.stats.average_edge_length;
  const GaussThinning thinning(current, input.triangles, radius, pieces);
  double cone = kThinningConeStart;
  Normals normals = face_normals(current, input.triangles);
  for (int it = 0; it < iterations; ++it) {
    progress.report(static_cast<double>(it) / iterations, "thinning");
    deformation.set_targets(thinning.targets(normals, cone, input.options.threads, input.spare_cores));
    cone = std::max(cone * kThinningConeShrink, kThinningConeEnd);
    Positions next = deformation.step(current, normals);
    clamp_moves(next, input.positions, kThinningLimitShare * input.limit);
    guard.put_back(next, current);
    current = std::move(next);
    normals = face_normals(current, input.triangles);
  }
}

// The interior vertices off every seam of `pieces`, not pinned: the ones the
// ruled polish makes flat and ruled.
std::vector<bool> inside_vertices(const MeasuredInput& input, const std::vector<int>& pieces) {
  return inside_patches(input.measured.interior, patch_border_vertices(input.triangles, pieces, input.positions.rows()),
                        input.pinned);
}

// Stages 3 and 4 on `pieces` from `positions`: corners of faces creased inside
// a piece put back, thinning inside the pieces with `deformation`, then the
// ruled polish of `inside` (inside_vertices of `pieces`). Returns the
// polish's steps kept.
int settle_pieces(const MeasuredInput& input, NormalGuidedDeformation& deformation, const std::vector<int>& pieces,
                  const std::vector<bool>& inside, Positions& positions, const Progress& progress) {
  const CreaseGuard crease(input.triangles, input.normals, pieces, kSegmentedCreaseGrowth);
  const StepGuard guard(input, crease);
  guard.heal(positions);
  thin(input, deformation, guard, pieces, kPieceThinningIterations, positions, progress.sub(0.0, 0.45));
  deformation.release();  // its share of the factor is of no use to the ruled polish, which needs the memory

  RuledPolishOptions ruled;
  ruled.max_iterations = kThinnedPolishIterations;
  ruled.robust = kThinnedPolishRobust;
  ruled.limit = input.limit;
  ruled.spare_cores = input.spare_cores;
  ruled.crease_guard = crease;
  const RuledPolishResult polished = polish_ruled(positions, input.positions, input.normals, input.triangles, inside,
                                                  input.pinned, ruled, progress.sub(0.45, 1.0));
  positions = polished.positions;
  return polished.iterations;
}

// Per vertex: inside a piece, flat and ruled at `positions`.
std::vector<bool> developable_inside(const MeasuredInput& input, const Positions& positions,
                                     const std::vector<bool>& inside) {
  const Normals normals = face_normals(positions, input.triangles);
  const Eigen::VectorXd defects = angle_defects(positions, input.triangles, inside);
  const Eigen::VectorXd spreads = ruling_spreads(positions, input.triangles, normals, input.connectivity, inside);
  std::vector<bool> developable(inside.size(), false);
  for (size_t v = 0; v < inside.size(); ++v)
    developable[v] =
        inside[v] && flat_and_ruled(defects[static_cast<Eigen::Index>(v)], spreads[static_cast<Eigen::Index>(v)]);
  return developable;
}

}  // namespace

NormalGuidedDeformation thinning_deformation(const MeasuredInput& input) {
  return NormalGuidedDeformation(input.triangles, input.pinned, Eigen::VectorXd::Ones(input.triangles.rows()),
                                 input.options.omega, kRefitCentroidWeight, Formulation::decoupled, input.normals,
                                 input.options.threads);
}

Positions thin_whole(const MeasuredInput& input, NormalGuidedDeformation& deformation, const Progress& progress) {
  Positions thinned = input.positions;
  if (!(input.limit > 0.0)) return thinned;
  const StepGuard free_guard(input, CreaseGuard(input.triangles, input.normals, {}, 0.0));
  thin(input, deformation, free_guard, {}, kThinningIterations, thinned, progress);
  return thinned;
}

ThinnedPieces thinned_pieces(const MeasuredInput& input, const Positions& thinned, PieceSource source,
                             NormalGuidedDeformation deformation, const Progress& progress) {
  ThinnedPieces out;
  const Eigen::Index m = input.triangles.rows();
  out.positions = thinned;
  out.pieces.assign(static_cast<size_t>(m), 0);
  out.count = 1;
  if (!(input.limit > 0.0)) return out;
  const Normals thinned_normals = face_normals(thinned, input.triangles);
  if (source == PieceSource::creases) {
    const int min_faces = static_cast<int>(std::max<Eigen::Index>(kSmallPieceFaces, m / kSmallPieceShare));
    out.pieces = normal_jump_pieces(input.triangles, input.connectivity, thinned_normals, kPieceCrease, min_faces,
                                    input.normals, kSegmentedCreaseGrowth);
  } else {
    out.pieces = segmented_patches(thinned, input.triangles, thinned_normals, face_areas(thinned, input.triangles),
                                   input.connectivity, input.options, progress.sub(0.0, 0.05))
                     .ids;
  }
  out.count = 1 + *std::max_element(out.pieces.begin(), out.pieces.end());

  const std::vector<bool> inside = inside_vertices(input, out.pieces);
  out.polish_iterations = settle_pieces(input, deformation, out.pieces, inside, out.positions, progress.sub(0.05, 0.6));

  // Stage 5: the pieces still curved inside, split in two and settled again
  // from where the polish left them, with a thinning factored anew.
  const std::vector<bool> curved =
      curved_pieces(out.pieces, out.count, input.connectivity, inside, developable_inside(input, out.positions, inside),
                    kCurvedPieceShare, kCurvedPieceInside);
  if (std::find(curved.begin(), curved.end(), true) == curved.end()) return out;
  out.pieces = split_in_two(out.positions, input.triangles, out.pieces, out.count, curved, progress.sub(0.6, 0.62));
  out.count = 1 + *std::max_element(out.pieces.begin(), out.pieces.end());
  NormalGuidedDeformation again = thinning_deformation(input);
  out.polish_iterations += settle_pieces(input, again, out.pieces, inside_vertices(input, out.pieces), out.positions,
                                         progress.sub(0.62, 1.0));
  return out;
}

}  // namespace developable

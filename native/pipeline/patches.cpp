#include "pipeline/patches.h"

#include "core/cone_fit.h"
#include "core/measures.h"
#include "segmentation/segmentation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace developable {

PatchFaces faces_of_patches(const std::vector<int>& patch_ids, int patch_count) {
  PatchFaces faces(static_cast<size_t>(patch_count));
  for (size_t f = 0; f < patch_ids.size(); ++f)
    faces[static_cast<size_t>(patch_ids[f])].push_back(static_cast<Eigen::Index>(f));
  return faces;
}

namespace {

// A patch's faces are 0 .. n-1 when it has all n of them: its rows need no gathering.
bool whole_mesh(const std::vector<Eigen::Index>& members, Eigen::Index faces) {
  return static_cast<Eigen::Index>(members.size()) == faces;
}

Normals gather_rows(const Normals& rows, const std::vector<Eigen::Index>& members) {
  Normals out(static_cast<Eigen::Index>(members.size()), 3);
  for (size_t i = 0; i < members.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows.row(members[i]);
  return out;
}

}  // namespace

std::vector<PatchCurve> fit_patch_curves(const Normals& normals, const Eigen::VectorXd& areas,
                                         const PatchFaces& patches, const IdealCurveOptions& options) {
  std::vector<PatchCurve> curves;
  for (size_t patch = 0; patch < patches.size(); ++patch) {
    const auto& members = patches[patch];
    if (members.empty()) continue;
    std::vector<SphereCurve> fitted;
    if (whole_mesh(members, normals.rows())) {
      fitted = fit_ideal_curves(normals, areas, options);
    } else {
      Eigen::VectorXd patch_areas(static_cast<Eigen::Index>(members.size()));
      for (size_t i = 0; i < members.size(); ++i) patch_areas[static_cast<Eigen::Index>(i)] = areas[members[i]];
      fitted = fit_ideal_curves(gather_rows(normals, members), patch_areas, options);
    }
    for (auto& curve : fitted) curves.push_back({static_cast<int>(patch), std::move(curve)});
  }
  return curves;
}

std::vector<CurveSearch> patch_curve_searches(const std::vector<PatchCurve>& curves, int patch_count) {
  std::vector<std::vector<SphereCurve>> by_patch(static_cast<size_t>(patch_count));
  for (const auto& c : curves) by_patch[static_cast<size_t>(c.patch)].push_back(c.curve);
  std::vector<CurveSearch> searches(static_cast<size_t>(patch_count));
  for (size_t patch = 0; patch < by_patch.size(); ++patch)
    if (!by_patch[patch].empty()) searches[patch] = CurveSearch(by_patch[patch]);
  return searches;
}

Normals patch_target_normals(const Normals& normals, const PatchFaces& patches,
                             const std::vector<CurveSearch>& searches, std::vector<std::vector<int>>* hints,
                             int threads) {
  if (hints != nullptr) hints->resize(patches.size());
  Normals targets(normals.rows(), 3);
  for (size_t patch = 0; patch < patches.size(); ++patch) {
    const auto& members = patches[patch];
    if (members.empty()) continue;
    std::vector<int>* const patch_hints = hints != nullptr ? &(*hints)[patch] : nullptr;
    if (whole_mesh(members, normals.rows())) return searches[patch].nearest(normals, patch_hints, threads);
    const Normals patch_targets = searches[patch].nearest(gather_rows(normals, members), patch_hints, threads);
    for (size_t i = 0; i < members.size(); ++i)
      targets.row(members[i]) = patch_targets.row(static_cast<Eigen::Index>(i));
  }
  return targets;
}

Patches fitted_patches(std::vector<int> ids, int count, const Normals& normals, const Eigen::VectorXd& areas,
                       const PipelineOptions& options) {
  Patches patches;
  patches.ids = std::move(ids);
  patches.count = count;
  patches.faces = faces_of_patches(patches.ids, count);
  patches.curves = fit_patch_curves(normals, areas, patches.faces, options.curve_options);
  patches.targets = patch_target_normals(normals, patches.faces, patch_curve_searches(patches.curves, count), nullptr,
                                         options.threads);
  return patches;
}

Patches one_patch(const Normals& normals, const Eigen::VectorXd& areas, const PipelineOptions& options) {
  return fitted_patches(std::vector<int>(static_cast<size_t>(normals.rows()), 0), 1, normals, areas, options);
}

Patches segmented_patches(const Positions& positions, const Triangles& triangles, const Normals& normals,
                          const Eigen::VectorXd& areas, const VertexFaces& connectivity, const PipelineOptions& options,
                          const Progress& progress) {
  std::vector<int> ids = segment_mesh(positions, triangles, normals, areas, connectivity, options.segmentation_options,
                                      progress.sub(0.02, 0.05));
  int count = 1;
  for (int label : ids) count = std::max(count, label + 1);
  progress.report(0.05, "ideal curve");
  return fitted_patches(std::move(ids), count, normals, areas, options);
}

double curve_fit_error(const Normals& normals, const Normals& targets, const Eigen::VectorXd& areas) {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < normals.rows(); ++f) {
    const double angle = std::atan2(normals.row(f).cross(targets.row(f)).norm(), normals.row(f).dot(targets.row(f)));
    sum += areas[f] * angle * angle;
  }
  return std::sqrt(sum / std::max(areas.sum(), 1e-300));
}

std::vector<bool> patch_border_vertices(const Triangles& triangles, const std::vector<int>& patch_ids,
                                        Eigen::Index vertex_count) {
  std::vector<int> first_patch(static_cast<size_t>(vertex_count), -1);
  std::vector<bool> border(static_cast<size_t>(vertex_count), false);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<size_t>(triangles(f, c));
      const int patch = patch_ids[static_cast<size_t>(f)];
      if (first_patch[v] < 0)
        first_patch[v] = patch;
      else if (first_patch[v] != patch)
        border[v] = true;
    }
  }
  return border;
}

std::vector<bool> inside_patches(const std::vector<bool>& interior, const std::vector<bool>& border,
                                 const std::vector<bool>& pinned) {
  if (border.size() != interior.size() || (!pinned.empty() && pinned.size() != interior.size()))
    throw EngineError(Status::internal_error, "inside_patches: sizes disagree");
  std::vector<bool> inside(interior.size());
  for (size_t v = 0; v < inside.size(); ++v) inside[v] = interior[v] && !border[v] && (pinned.empty() || !pinned[v]);
  return inside;
}

bool patches_fit_cones(const std::vector<int>& patch_ids, int patch_count, const Normals& normals,
                       const Eigen::VectorXd& areas) {
  std::vector<NormalMoments> moments(static_cast<size_t>(patch_count));
  for (Eigen::Index f = 0; f < normals.rows(); ++f)
    moments[static_cast<size_t>(patch_ids[static_cast<size_t>(f)])].add(normals.row(f).transpose(), areas[f]);
  std::vector<Cone> cones;
  for (const NormalMoments& m : moments) cones.push_back(fit_cone(m).cone);
  for (Eigen::Index f = 0; f < normals.rows(); ++f)
    if (angle_to_cone(cones[static_cast<size_t>(patch_ids[static_cast<size_t>(f)])], normals.row(f).transpose()) >=
        kFlatDefect)
      return false;
  return true;
}

}  // namespace developable

#include "pattern/unfold.h"

#include "core/union_find.h"
#include "pattern/flatten.h"
#include "pattern/piece_split.h"
#include "pattern/plane_geometry.h"
#include "pattern/seam_curves.h"
#include "pattern/unfold_mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>

namespace developable {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using namespace unfolding;

void check_arguments(Eigen::Index nf, const std::vector<int>& patch_ids, const UnfoldOptions& options,
                     const std::vector<int>& face_groups) {
  if (!patch_ids.empty() && static_cast<Eigen::Index>(patch_ids.size()) != nf)
    throw EngineError(Status::invalid_argument, "patch_ids has " + std::to_string(patch_ids.size()) + " entries for " +
                                                    std::to_string(nf) + " triangles");
  if (!face_groups.empty() && static_cast<Eigen::Index>(face_groups.size()) != nf)
    throw EngineError(Status::invalid_argument, "face_groups has " + std::to_string(face_groups.size()) +
                                                    " entries for " + std::to_string(nf) + " triangles");
  for (size_t f = 0; f < patch_ids.size(); ++f)
    if (patch_ids[f] < 0)
      throw EngineError(Status::invalid_argument, "patch id of triangle " + std::to_string(f) + " is negative");
  if (!(options.seam_tolerance >= 0.0))
    throw EngineError(Status::invalid_argument, "seam_tolerance must not be negative");
  if (options.arap_iterations < 0) throw EngineError(Status::invalid_argument, "arap_iterations must not be negative");
}

// The faces of one patch joined by edges, largest first (piece numbers
// follow size); a piece still to be laid flat, with the splits that made it.
struct Job {
  std::vector<int> faces;
  int splits = 0;
};

std::vector<Job> first_jobs(const EdgeTable& mesh_edges, Eigen::Index nf, const std::vector<int>& patch_ids) {
  const auto patch_of = [&](int f) { return patch_ids.empty() ? 0 : patch_ids[f]; };
  UnionFind same_patch(nf);
  for (const auto& uses : mesh_edges.uses)
    if (uses[1] >= 0 && patch_of(uses[0] / 3) == patch_of(uses[1] / 3)) same_patch.unite(uses[0] / 3, uses[1] / 3);
  std::vector<Job> jobs;
  std::unordered_map<int, int> job_of_root;
  for (Eigen::Index f = 0; f < nf; ++f) {
    auto [it, inserted] = job_of_root.emplace(same_patch.find(static_cast<int>(f)), static_cast<int>(jobs.size()));
    if (inserted) jobs.emplace_back();
    jobs[it->second].faces.push_back(static_cast<int>(f));
  }
  // A stack: the largest is taken first.
  std::sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) {
    return a.faces.size() != b.faces.size() ? a.faces.size() < b.faces.size() : a.faces[0] > b.faces[0];
  });
  return jobs;
}

// Connected parts (across shared edges) of a set of faces.
std::vector<std::vector<int>> connected_parts(const Triangles& triangles, const std::vector<int>& faces) {
  const LocalPiece piece = local_piece(triangles, faces, {});
  const EdgeTable edges = edge_table(piece.tris);
  UnionFind uf(faces.size());
  for (const auto& uses : edges.uses)
    if (uses[1] >= 0) uf.unite(uses[0] / 3, uses[1] / 3);
  std::unordered_map<int, int> part_of_root;
  std::vector<std::vector<int>> parts;
  for (size_t i = 0; i < faces.size(); ++i) {
    const int root = uf.find(static_cast<int>(i));
    auto [it, inserted] = part_of_root.emplace(root, static_cast<int>(parts.size()));
    if (inserted) parts.emplace_back();
    parts[it->second].push_back(faces[i]);
  }
  return parts;
}

// The parts a piece that cannot lie flat is split into: the two sides of a
// chord, else the halves across its principal axis (each connected part).
std::vector<std::vector<int>> split_piece(const Positions& positions, const Triangles& triangles,
                                          const LocalPiece& piece, const std::vector<int>& face_groups) {
  auto halves = split_along_chord(positions, piece, SplitThrough::largest_defect);
  if (halves[0].empty()) halves = split_across_axis(positions, triangles, piece.faces, face_groups);
  std::vector<std::vector<int>> parts;
  for (const auto& half : halves)
    for (auto& part : connected_parts(triangles, half)) parts.push_back(std::move(part));
  return parts;
}

// Piece `id` of the result from its flat map: corners, strain, areas,
// outline rows.
UnfoldPiece record_piece(const Positions& positions, const Triangles& triangles, const std::vector<int>& faces,
                         const FlatPiece& flat, int id, UnfoldResult& result) {
  UnfoldPiece out;
  out.faces = static_cast<Eigen::Index>(faces.size());
  out.cut_edges = static_cast<int>(flat.cut_keys.size());
  out.arap_iterations = flat.arap_iterations;
  double strain_sum = 0.0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const int f = faces[i];
    result.piece_of_face[f] = id;
    double face_max = 0.0;
    for (int k = 0; k < 3; ++k) {
      result.corners.row(3 * f + k) = flat.corner_uv[3 * i + k].transpose();
      const double l3 = (positions.row(triangles(f, k)) - positions.row(triangles(f, (k + 1) % 3))).norm();
      const double l2 = (flat.corner_uv[3 * i + k] - flat.corner_uv[3 * i + (k + 1) % 3]).norm();
      const double strain = std::abs(l2 / l3 - 1.0);
      face_max = std::max(face_max, strain);
      strain_sum += strain;
    }
    result.face_strain[f] = face_max;
    out.max_strain = std::max(out.max_strain, face_max);
    const Vec3 p0 = positions.row(triangles(f, 0)).transpose();
    out.area_3d +=
        0.5 *
        (positions.row(triangles(f, 1)).transpose() - p0).cross(positions.row(triangles(f, 2)).transpose() - p0).norm();
    const Vec2& q0 = flat.corner_uv[3 * i];
    out.area_flat += 0.5 * cross2(flat.corner_uv[3 * i + 1] - q0, flat.corner_uv[3 * i + 2] - q0);
  }
  out.mean_strain = strain_sum / (3.0 * faces.size());
  out.area_change = out.area_flat / out.area_3d - 1.0;
  for (const auto& loop : flat.outline) {
    std::vector<Eigen::Index> rows;
    for (int fe : loop) {
      const int i = fe / 3, k = fe % 3;
      rows.push_back(3 * static_cast<Eigen::Index>(faces[i]) + k);
      out.outline_length += (flat.corner_uv[3 * i + (k + 1) % 3] - flat.corner_uv[fe]).norm();
    }
    out.outline.push_back(std::move(rows));
  }
  return out;
}

}  // namespace

UnfoldResult unfold(const Positions& positions, const Triangles& triangles, const std::vector<int>& patch_ids,
                    const UnfoldOptions& options, const std::vector<int>& face_groups, const Progress& progress) {
  const Eigen::Index nf = triangles.rows();
  check_arguments(nf, patch_ids, options, face_groups);
  std::vector<std::array<int, 3>> all_tris(nf);
  for (Eigen::Index f = 0; f < nf; ++f) all_tris[f] = {triangles(f, 0), triangles(f, 1), triangles(f, 2)};
  const EdgeTable mesh_edges = edge_table(all_tris);
  progress.report(0.0, "unfolding");

  UnfoldResult result;
  result.corners.setZero(3 * nf, 2);
  result.piece_of_face.assign(nf, -1);
  result.face_strain = Eigen::VectorXd::Zero(nf);
  std::vector<uint64_t> cut_keys;
  std::vector<Job> stack = first_jobs(mesh_edges, nf, patch_ids);
  Eigen::Index faces_done = 0;
  while (!stack.empty()) {
    const double done = static_cast<double>(faces_done) / static_cast<double>(nf);
    progress.report(0.9 * done, "unfolding");
    Job job = std::move(stack.back());
    stack.pop_back();
    const LocalPiece piece = local_piece(triangles, job.faces, face_groups);
    const double share = static_cast<double>(job.faces.size()) / static_cast<double>(nf);
    FlatPiece flat;
    if (!flatten_piece(positions, piece, options, progress.sub(0.9 * done, 0.9 * (done + share)), &flat)) {
      if (job.faces.size() <= 1)
        throw EngineError(Status::numerical_failure,
                          "triangle " + std::to_string(job.faces[0]) + " could not be laid flat");
      ++result.split_count;
      for (auto& part : split_piece(positions, triangles, piece, face_groups))
        stack.push_back({std::move(part), job.splits + 1});
      continue;
    }
    faces_done += static_cast<Eigen::Index>(job.faces.size());
    const int id = static_cast<int>(result.pieces.size());
    UnfoldPiece out = record_piece(positions, triangles, job.faces, flat, id, result);
    out.patch = patch_ids.empty() ? 0 : patch_ids[job.faces[0]];
    out.splits = job.splits;
    cut_keys.insert(cut_keys.end(), flat.cut_keys.begin(), flat.cut_keys.end());
    result.pieces.push_back(std::move(out));
  }
  std::sort(cut_keys.begin(), cut_keys.end());
  progress.report(0.9, "unfolding: seams");
  result.seams = seam_chains(positions, triangles, patch_ids, mesh_edges, cut_keys, result);
  progress.report(0.95, "unfolding: outlines");
  smooth_outlines(triangles, result.seams, result);
  return result;
}

}  // namespace developable

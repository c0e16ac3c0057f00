#include "pipeline/judge.h"

#include <algorithm>
#include <cmath>

namespace developable {

IterateScore::IterateScore(std::vector<bool> scored, bool median) : scored_(std::move(scored)), median_(median) {
  for (bool s : scored_) count_ += s ? 1 : 0;
}

double IterateScore::operator()(const Eigen::VectorXd& defects) const {
  if (!median_) return mean(defects);
  if (count_ == 0) return 0.0;
  values_.clear();
  for (Eigen::Index v = 0; v < defects.size(); ++v)
    if (scored_[static_cast<size_t>(v)]) values_.push_back(std::abs(defects[v]));
  const auto middle = values_.begin() + static_cast<std::ptrdiff_t>(values_.size() / 2);
  std::nth_element(values_.begin(), middle, values_.end());
  return *middle;
}

double IterateScore::mean(const Eigen::VectorXd& defects) const {
  if (count_ == 0) return 0.0;
  double sum = 0.0;
  for (Eigen::Index v = 0; v < defects.size(); ++v)
    if (scored_[static_cast<size_t>(v)]) sum += std::abs(defects[v]);
  return sum / static_cast<double>(count_);
}

double flat_share(const Eigen::VectorXd& defects, const std::vector<bool>& interior) {
  Eigen::Index flat = 0, count = 0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (!interior[static_cast<size_t>(v)]) continue;
    ++count;
    if (std::abs(defects[v]) < kFlatDefect) ++flat;
  }
  return count > 0 ? static_cast<double>(flat) / static_cast<double>(count) : 0.0;
}

Motion motion_of(const Positions& positions, const Positions& input) {
  return {std::sqrt((positions - input).rowwise().squaredNorm().mean()),
          (positions - input).rowwise().norm().maxCoeff()};
}

Judge::Judge(const Triangles& triangles, const std::vector<bool>& interior, const VertexFaces& connectivity,
             const Normals& input_normals, IterateScore score, Measured input, bool closed, bool object,
             CreaseGuard crease_guard)
    : triangles_(triangles),
      interior_(interior),
      connectivity_(connectivity),
      input_normals_(input_normals),
      score_(std::move(score)),
      input_(std::move(input)),
      closed_(closed),
      object_(object),
      crease_guard_(std::move(crease_guard)) {}

Measured Judge::measure(const Positions& positions, const Normals& normals, Detail detail) const {
  Measured m;
  m.defects = angle_defects(positions, triangles_, interior_);
  const DefectStats stats = defect_stats(m.defects, interior_);
  m.figures.mean = stats.mean_abs;
  m.figures.max = stats.max_abs;
  m.figures.flat = flat_share(m.defects, interior_);
  m.figures.turned = static_cast<Eigen::Index>(turned_over_faces(normals, input_normals_).size());
  m.figures.score = score_(m.defects);
  m.figures.mean_inside = score_.mean(m.defects);
  if (detail == Detail::candidate) {
    m.figures.creased = static_cast<Eigen::Index>(crease_guard_.creased_faces(normals).size());
    complete(m, positions, normals);
  }
  return m;
}

void Judge::complete(Measured& measured, const Positions& positions, const Normals& normals) const {
  if (object_) measure_rulings(measured, positions, normals);
}

void Judge::measure_rulings(Measured& measured, const Positions& positions, const Normals& normals) const {
  measured.figures.ruled =
      vertex_shares(measured.defects, ruling_spreads(positions, triangles_, normals, connectivity_, interior_),
                    interior_)
          .ruled;
  measured.figures.ruled_read = true;
}

bool Judge::admissible(const Measured& candidate) {
  const Admission admission = admit(candidate.figures, input_.figures, closed_, object_);
  rejected_.record(admission, candidate.figures.score, input_.figures.score, candidate.figures.turned);
  return admission.ok();
}

}  // namespace developable

#include "pipeline/target_field.h"

#include "core/measures.h"

namespace developable {

TargetField::TargetField(Patches patches, const Positions& positions, const Triangles& triangles,
                         const Eigen::VectorXd& areas, const VertexFaces& connectivity, const PipelineOptions& options,
                         bool piecewise)
    : patches_(std::move(patches)),
      triangles_(triangles),
      options_(options),
      searches_(patch_curve_searches(patches_.curves, patches_.count)),
      smoothing_rounds_(smoothing_rounds(options, piecewise)) {
  // The first projection, again with hints so that later ones start there.
  targets_ =
      patch_target_normals(face_normals(positions, triangles), patches_.faces, searches_, &hints_, options.threads);
  if (smoothing_rounds_ > 0) {
    smoother_.emplace(triangles, patches_.ids, connectivity);
    targets_ = smoother_->smooth(targets_, areas, smoothing_rounds_);
  }
}

void TargetField::update(const Positions& current, const Normals& normals, int iteration) {
  const bool refit = refit_next_ || (iteration - 1) % kRefitInterval == 0;
  refit_next_ = false;
  const Eigen::VectorXd areas = refit || smoother_ ? face_areas(current, triangles_) : Eigen::VectorXd();
  if (refit) {
    patches_.curves = fit_patch_curves(normals, areas, patches_.faces, options_.curve_options);
    searches_ = patch_curve_searches(patches_.curves, patches_.count);
  }
  targets_ = patch_target_normals(normals, patches_.faces, searches_, &hints_, options_.threads);
  if (smoother_) targets_ = smoother_->smooth(targets_, areas, smoothing_rounds_);
}

void TargetField::refit(const Positions& current, const Normals& normals) {
  refit_next_ = true;
  update(current, normals, 2);
}

}  // namespace developable

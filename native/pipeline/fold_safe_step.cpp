#include "pipeline/fold_safe_step.h"

#include "deformation/move_limit.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace developable {
namespace {

constexpr double kFoldDamping = 0.25;
constexpr double kFoldRecovery = 1.5;
// Retries of a folding step with more damping before it is shortened.
constexpr int kFoldRetries = 2;
// Rounds of putting back the corners of faces that still turn over before
// the whole step is dropped.
constexpr int kFoldRevertRounds = 20;

}  // namespace

Eigen::VectorXd triangle_quality(const Positions& positions, const Triangles& triangles) {
  Eigen::VectorXd quality(triangles.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Eigen::RowVector3d a = positions.row(triangles(f, 0)), b = positions.row(triangles(f, 1)),
                             c = positions.row(triangles(f, 2));
    const double squares = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
    const double area = 0.5 * (b - a).cross(c - a).norm();
    quality[f] = squares > 0.0 ? 4.0 * std::sqrt(3.0) * area / squares : 0.0;
  }
  return quality;
}

Eigen::VectorXd sliver_trust(const Positions& positions, const Triangles& triangles) {
  return (2.0 * triangle_quality(positions, triangles)).cwiseMin(1.0);
}

FoldDamping::FoldDamping(const Triangles& triangles, const VertexFaces& vertex_faces)
    : triangles_(triangles), vertex_faces_(vertex_faces), damping_(Eigen::VectorXd::Ones(triangles.rows())) {}

void FoldDamping::damp_around(const std::vector<Eigen::Index>& turned) {
  for (Eigen::Index f : turned)
    for (int c = 0; c < 3; ++c) {
      const int v = triangles_(f, c);
      for (const int* g = vertex_faces_.begin(v); g != vertex_faces_.end(v); ++g)
        damping_[*g] = std::min(damping_[*g], 1.0) * kFoldDamping;
    }
  damped_ = true;
}

void FoldDamping::recover() {
  if (!damped_) return;
  damping_ = (damping_ * kFoldRecovery).cwiseMin(1.0);
  damped_ = damping_.minCoeff() < 1.0;
}

FoldSafeStep::FoldSafeStep(NormalGuidedDeformation& deformation, const Positions& input, const Normals& input_normals,
                           const Triangles& triangles, const VertexFaces& connectivity, bool can_damp, double limit,
                           Mode mode, CreaseGuard crease_guard)
    : deformation_(deformation),
      input_(input),
      input_normals_(input_normals),
      triangles_(triangles),
      can_damp_(can_damp),
      limit_(limit),
      mode_(mode),
      trust_(can_damp ? sliver_trust(input, triangles) : Eigen::VectorXd::Ones(triangles.rows())),
      crease_guard_(std::move(crease_guard)),
      damping_(triangles, connectivity) {
  if (can_damp_ && trust_.minCoeff() < 1.0) deformation_.set_normal_weights(trust_);
}

int FoldSafeStep::advance(Positions& current, Normals& normals) {
  int retries = 0;
  Positions proposal = propose(current, normals);
  Normals proposal_normals = face_normals(proposal, triangles_);
  std::vector<Eigen::Index> turned = turned_over_faces(proposal_normals, input_normals_);
  for (int retry = 0; retry < kFoldRetries && !turned.empty() && can_damp_; ++retry) {
    damping_.damp_around(turned);
    deformation_.set_normal_weights(trust_.cwiseProduct(damping_.factors()));
    proposal = propose(current, normals);
    proposal_normals = face_normals(proposal, triangles_);
    turned = turned_over_faces(proposal_normals, input_normals_);
    ++retries;
  }
  // Creased faces are only put back (solving again around them cost the
  // mountain 3 times the iteration time).
  if (crease_guard_.active()) turned = folded_faces(proposal_normals, input_normals_, crease_guard_);
  for (int round = 0; !turned.empty(); ++round) {
    if (round == kFoldRevertRounds) {
      proposal = current;
      proposal_normals = normals;
      break;
    }
    for (Eigen::Index f : turned)
      for (int c = 0; c < 3; ++c) proposal.row(triangles_(f, c)) = current.row(triangles_(f, c));
    proposal_normals = face_normals(proposal, triangles_);
    turned = folded_faces(proposal_normals, input_normals_, crease_guard_);
    ++retries;
  }
  current = std::move(proposal);
  normals = std::move(proposal_normals);
  if (can_damp_ && damping_.any()) {
    damping_.recover();
    deformation_.set_normal_weights(trust_.cwiseProduct(damping_.factors()));
  }
  return retries;
}

bool FoldSafeStep::accepts(const Normals& normals) const {
  return folded_faces(normals, input_normals_, crease_guard_).empty();
}

Positions FoldSafeStep::propose(const Positions& current, const Normals& normals) const {
  Positions next = mode_ == Mode::refit ? deformation_.step(current, normals) : deformation_.step(current);
  clamp_moves(next, input_, limit_);
  return next;
}

}  // namespace developable

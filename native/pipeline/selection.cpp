#include "pipeline/selection.h"

#include <algorithm>

namespace developable {

Admission admit(const Figures& candidate, const Figures& input, bool closed) {
  Admission a;
  a.folded = candidate.turned > 0;
  a.defect_grew = candidate.mean > input.mean * (closed ? 1.0 + kClosedMeshGrowth : 1.0);
  a.flat_share_fell = candidate.flat < input.flat;
  return a;
}

bool visible_gain(const Figures& result, const Figures& input) {
  return result.flat > input.flat || result.mean < (1.0 - kLeastGain) * input.mean;
}

bool as_developable(const Figures& candidate, const Figures& current, const Figures& input) {
  return candidate.flat >= current.flat - kFlatSlack && candidate.mean <= current.mean + kDefectSlack * input.mean &&
         candidate.max <= std::max(current.max, input.max);
}

double allowed_largest_defect(double competing, double input) {
  return (1.0 + kLargestDefectGrowth) * std::max(competing, input);
}

bool moves_less(const Motion& candidate, const Motion& current, bool at_most_as_far) {
  return candidate.rms < current.rms && (!at_most_as_far || candidate.largest <= current.largest);
}

bool smooth_enough(double roughness, double reference) { return roughness <= kLeastMoveRoughness * reference; }

bool more_developable(const PipelineStats& a, const PipelineStats& b) {
  if (a.result != b.result) return a.result == ResultKind::improved;
  return a.flat_share_after >= b.flat_share_after && a.mean_defect_after <= b.mean_defect_after &&
         (a.flat_share_after > b.flat_share_after || a.mean_defect_after < b.mean_defect_after) &&
         a.max_defect_after <= allowed_largest_defect(b.max_defect_after, a.max_defect_before);
}

void Rejections::record(const Admission& admission, double score, double input_score, Eigen::Index turned) {
  if (!(score < input_score)) return;
  if (admission.folded) {
    ++folded;
    if (fewest_turned_over < 0 || turned < fewest_turned_over) fewest_turned_over = turned;
  }
  if (admission.defect_grew) ++defect_grew;
  if (admission.flat_share_fell) ++flat_share_fell;
}

UnchangedReason unchanged_reason(const Rejections& r, double flat_share_before) {
  if (r.developable_patches) return UnchangedReason::developable_piecewise;
  if (r.no_visible_gain) return UnchangedReason::no_visible_gain;
  if (r.folded == 0 && r.defect_grew == 0 && r.flat_share_fell == 0 && r.creased == 0)
    return flat_share_before >= 1.0 ? UnchangedReason::already_flat : UnchangedReason::no_better_iterate;
  return UnchangedReason::rejected;
}

int worse_figures(const PipelineStats& s) {
  int worse = 0;
  if (s.mean_defect_after > s.mean_defect_before) worse |= worse_mean_defect;
  if (s.max_defect_after > s.max_defect_before) worse |= worse_max_defect;
  if (s.flat_share_after < s.flat_share_before) worse |= worse_flat_share;
  if (s.shares_after.ruled < s.shares_before.ruled) worse |= worse_ruled_share;
  if (s.faces_turned_over > 0) worse |= worse_turned_faces;
  return worse;
}

}  // namespace developable

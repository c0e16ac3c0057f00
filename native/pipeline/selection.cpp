#include "pipeline/selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace developable {

Admission admit(const Figures& candidate, const Figures& input, bool closed, bool object) {
  Admission a;
  a.folded = candidate.turned > 0;
  a.creased = candidate.creased > 0;
  const double mean = object ? candidate.mean_inside : candidate.mean;
  const double input_mean = object ? input.mean_inside : input.mean;
  a.defect_grew = mean > input_mean * (closed ? 1.0 + kClosedMeshGrowth : 1.0);
  a.flat_share_fell = candidate.flat < input.flat;
  a.ruled_share_fell = object && candidate.ruled_read && candidate.ruled < input.ruled;
  a.no_score_gain = !(candidate.score < (1.0 - kLeastGain) * input.score);
  a.no_visible_gain = !visible_gain(candidate, input);
  return a;
}

bool visible_gain(const Figures& result, const Figures& input) {
  return result.flat > input.flat || result.mean < (1.0 - kDefectSlack) * input.mean;
}

bool is_object(bool closed, double total_curvature) { return closed || total_curvature >= kObjectCurvature; }

bool as_developable(const Figures& candidate, const Figures& other, const Figures& input, bool object) {
  if (object && candidate.ruled < other.ruled - kFlatSlack) return false;
  return candidate.flat >= other.flat - kFlatSlack && candidate.mean <= other.mean + kDefectSlack * input.mean &&
         candidate.max <= allowed_largest_defect(other.max, input.max);
}

double allowed_largest_defect(double other, double input) {
  return (1.0 + kLargestDefectGrowth) * std::max(other, input);
}

bool more_developable(const Figures& a, const Figures& b, bool object) {
  if (object && a.ruled != b.ruled) return a.ruled > b.ruled;
  return a.flat > b.flat || (a.flat == b.flat && a.mean < b.mean);
}

bool worth_ruled_finish(const Figures& choice) { return choice.crumpled() > kFlatSlack; }

bool ruled_finish_can_gain(double choice_objective, double input_objective) {
  return choice_objective < input_objective;
}

bool ruled_finish_kept(const Figures& finished, const Motion& finished_motion, const Figures& choice,
                       const Motion& choice_motion, const Figures& input) {
  const double gain = finished.ruled - choice.ruled;
  return gain > kFlatSlack && gain > choice.flat - finished.flat &&
         finished.max <= allowed_largest_defect(choice.max, input.max) &&
         finished_motion.largest <= kFinishReach * choice_motion.largest;
}

bool crumpled(const Figures& result, const Figures& input) {
  return result.crumpled() > input.crumpled() + kCrumpleSlack;
}

bool moves_less(const Motion& candidate, const Motion& other) { return candidate.rms < other.rms; }

bool smooth_enough(double roughness, double reference) { return roughness <= kLeastMoveRoughness * reference; }

int select(const std::vector<Contestant>& contestants, const Figures& input, double reference_roughness, bool object) {
  const int count = static_cast<int>(contestants.size());
  double nearest = std::numeric_limits<double>::infinity();  // the smallest largest move of the others
  for (const Contestant& c : contestants)
    if (!c.at_most_as_far && smooth_enough(c.roughness, reference_roughness))
      nearest = std::min(nearest, c.motion.largest);
  const auto takes_part = [&](int i) {
    const Contestant& c = contestants[static_cast<size_t>(i)];
    return smooth_enough(c.roughness, reference_roughness) && (!c.at_most_as_far || c.motion.largest <= nearest);
  };
  int anchor = -1;
  for (int i = 0; i < count; ++i)
    if (takes_part(i) && (anchor < 0 || more_developable(contestants[static_cast<size_t>(i)].figures,
                                                         contestants[static_cast<size_t>(anchor)].figures, object)))
      anchor = i;
  if (anchor < 0) return -1;
  const Contestant& a = contestants[static_cast<size_t>(anchor)];
  int winner = anchor;
  for (int i = 0; i < count; ++i) {
    const Contestant& c = contestants[static_cast<size_t>(i)];
    if (i != anchor && takes_part(i) && as_developable(c.figures, a.figures, input, object) &&
        moves_less(c.motion, contestants[static_cast<size_t>(winner)].motion))
      winner = i;
  }
  return winner;
}

void Rejections::record(const Admission& admission, double score, double input_score, Eigen::Index turned) {
  if (!(score < input_score)) return;
  if (admission.folded) {
    ++folded;
    if (fewest_turned_over < 0 || turned < fewest_turned_over) fewest_turned_over = turned;
  }
  if (admission.creased) ++creased;
  if (admission.defect_grew) ++defect_grew;
  if (admission.flat_share_fell) ++flat_share_fell;
  if (admission.ruled_share_fell) ++ruled_share_fell;
  if (admission.no_visible_gain && !admission.no_score_gain && !admission.folded && !admission.creased &&
      !admission.defect_grew && !admission.flat_share_fell && !admission.ruled_share_fell)
    ++no_visible_gain;
}

UnchangedReason unchanged_reason(const Rejections& r, double flat_share_before) {
  if (r.developable_patches) return UnchangedReason::developable_piecewise;
  const bool nothing_broke =
      r.folded == 0 && r.defect_grew == 0 && r.flat_share_fell == 0 && r.ruled_share_fell == 0 && r.creased == 0;
  if (nothing_broke && flat_share_before >= 1.0) return UnchangedReason::already_flat;
  if (r.no_visible_gain > 0) return UnchangedReason::no_visible_gain;
  return nothing_broke ? UnchangedReason::no_better_iterate : UnchangedReason::rejected;
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

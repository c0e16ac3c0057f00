#include "pipeline/messages.h"

#include "core/measures.h"
#include "core/mesh_input.h"

#include <cstdio>

namespace developable {
namespace {

// "0.001 rad": the flat threshold as the messages say it.
std::string flat_threshold_words() {
  char text[32];
  std::snprintf(text, sizeof text, "%g rad", kFlatDefect);
  return text;
}

}  // namespace

std::string unchanged_message(const Rejections& r, const PipelineStats& stats) {
  switch (stats.unchanged_reason) {
    case UnchangedReason::developable_piecewise:
      return "Returned the input unchanged: it is already developable piecewise. Every vertex inside its " +
             std::to_string(stats.patches) + " patches is flat (|defect| under " + flat_threshold_words() +
             "); the curvature sits on the seams between them.";
    case UnchangedReason::no_visible_gain:
      return "Returned the input unchanged: the best result made no vertex flat and did not lower the mean "
             "|defect| (its curvature could only move, not leave), so it would have moved the mesh for nothing.";
    case UnchangedReason::already_flat:
      return "Returned the input unchanged: every interior vertex is already flat (|defect| under " +
             flat_threshold_words() + ") and no iterate lowered the curvature further.";
    case UnchangedReason::no_better_iterate:
      return "Returned the input unchanged: no iterate lowered its curvature. Try a larger "
             "tolerance or more iterations.";
    case UnchangedReason::already_developable:
      return "The mesh is already developable: returned unchanged.";
    case UnchangedReason::none:
    case UnchangedReason::rejected:
      break;
  }
  std::string reasons, advice;
  auto add = [](std::string& list, const std::string& item) {
    if (list.find(item) == std::string::npos) list += (list.empty() ? "" : ", ") + item;
  };
  if (r.folded > 0) {
    add(reasons, "turning faces over (at least " + std::to_string(r.fewest_turned_over) + ")");
    add(advice, "a smaller tolerance");
  }
  if (r.defect_grew > 0) {
    add(reasons, "raising the mean |defect|");
    add(advice, "segmentation with more patches");
  }
  if (r.flat_share_fell > 0) {
    add(reasons, "losing flat vertices");
    if (r.folded == 0) add(advice, "a larger tolerance");
  }
  if (r.ruled_share_fell > 0) {
    add(reasons, "crumpling flat vertices into facets (fewer flat and ruled)");
    add(advice, "segmentation with more patches");
  }
  if (r.creased > 0) {
    add(reasons, "creasing the surface inside a patch");
    if (r.folded == 0) add(advice, "a smaller tolerance");
  }
  return "Returned the input unchanged: every iterate that lowered the curvature did so by " + reasons + ". Try " +
         advice + ".";
}

std::string finer_split_also_unchanged(const std::string& message, int finer_patches) {
  const std::string patches = std::to_string(finer_patches) + " patches";
  const size_t advice = message.find(". Try ");
  if (advice == std::string::npos)
    return message + " Split twice as finely (" + patches + "), it came back unchanged too.";
  return message.substr(0, advice) + ", also when split twice as finely (" + patches + ")" + message.substr(advice);
}

std::string no_interior_vertex_message(const Positions& positions) {
  std::string message =
      "the mesh has no interior vertex: every vertex is on the boundary, so there is no curvature to reduce";
  const Eigen::Index shared = coincident_vertices(positions);
  if (shared > 0)
    message += "; " + std::to_string(shared) + " of " + std::to_string(positions.rows()) +
               " vertices share a position with another vertex (a polygon soup?): weld them first "
               "(Blender: Merge by Distance)";
  return message;
}

std::string result_message(const PipelineStats& stats, const Rejections& rejected) {
  if (stats.result == ResultKind::unchanged) return unchanged_message(rejected, stats);
  // Every figure that got worse is named (a twisted torus: the mean +0.2 %
  // and the largest +113 % for 1 % more flat vertices).
  char largest[128] = "";
  if (stats.max_defect_after > stats.max_defect_before)
    std::snprintf(largest, sizeof largest, "the largest |defect| grew from %.4g to %.4g rad (+%.3g %%)",
                  stats.max_defect_before, stats.max_defect_after,
                  100.0 * (stats.max_defect_after / stats.max_defect_before - 1.0));
  // A sheet's rulings are not held by the rule (admit), only said.
  char ruled[160] = "";
  if (stats.shares_after.ruled < stats.shares_before.ruled)
    std::snprintf(ruled, sizeof ruled,
                  "fewer vertices are flat and ruled (%.1f %% -> %.1f %%): some flat ones are crumpled into facets",
                  100.0 * stats.shares_before.ruled, 100.0 * stats.shares_after.ruled);
  if (stats.mean_defect_after > stats.mean_defect_before) {
    char grew[96];
    std::snprintf(grew, sizeof grew, "the mean |defect| grew by %.1f %%",
                  100.0 * (stats.mean_defect_after / stats.mean_defect_before - 1.0));
    return std::string("Improved, but ") + grew + (largest[0] ? " and " : "") + largest +
           ": a whole object keeps its total curvature, which gathered on the seams between its pieces." +
           (ruled[0] ? std::string(" Also ") + ruled + "." : "");
  }
  if (!largest[0] && !ruled[0]) return "";
  return std::string("Improved, but ") + largest + (largest[0] && ruled[0] ? ", and " : "") + ruled + ".";
}

// The largest distance a vertex may move from its input position (caller's

}  // namespace developable

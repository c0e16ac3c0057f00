// The plan of a run: which patch alternatives it runs and which result it
// returns. One patch when one set of ideal curves carries the whole Gauss
// image; the pieces the curvature already cuts the mesh into; else the
// segmentation's patches, with a second opinion (the same mesh as one patch)
// on small open meshes, a finer split when a closed mesh came back unchanged
// and, beside the segmented run of a closed mesh, the thinned-pieces
// generator's candidates (thinned_pieces.h). The decisions are pure
// functions (tests/unit/plan_test.cpp).
#pragma once

#include "pipeline/options.h"
#include "pipeline/run_context.h"
#include "pipeline/run_result.h"

#include <Eigen/Core>

namespace developable {

// RMS angle (rad) between the normals and one set of ideal curves above which
// automatic segmentation splits the mesh into patches (docs/segmentation.md).
inline constexpr double kAutoSegmentationError = 0.12;

// Open meshes automatic segmentation splits, up to this many interior
// vertices, are also run as one patch (the second opinion): a second run,
// which a 1k-vertex family mesh pays in 0.1-0.5 s.
inline constexpr Eigen::Index kSecondOpinionVertices = 10000;

// Whether automatic segmentation splits a mesh: always when it is closed (a
// closed surface is never one developable piece: its curvature sums to
// 4 pi on a sphere-like one; the fit of one curve let rounded boxes through,
// their flat sides carrying most of the area), else when the one-patch
// curves miss the normals by more than kAutoSegmentationError (rad, RMS).
bool splits_automatically(bool closed, double one_patch_fit_error);

// Whether a split open mesh is also run as one patch: automatic
// segmentation, more than one patch, a boundary, up to kSecondOpinionVertices
// interior vertices, and curvature to lose. The misfit that chose the split
// also grows where the fit of one curve fails on a developable (a coarse or
// noisy Gauss image the fit calls a blob), and there the split run is worse
// on every figure.
bool wants_second_opinion(const PipelineOptions& options, int patch_count, bool closed, Eigen::Index interior_vertices,
                          double mean_defect);

// Whether a closed mesh split automatically is split again twice as finely:
// its run came back unchanged because every better candidate was
// inadmissible, none was better, or none showed a gain (not because it was
// developable already): smaller patches gather less curvature on each seam.
bool splits_finer(const PipelineStats& automatic);

// Runs the plan on a measured input and returns its result.
PipelineResult run_plan(const MeasuredInput& input, const Progress& progress);

}  // namespace developable

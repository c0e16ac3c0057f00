// The plan of a run: which patch alternatives it runs and which result it
// returns. One patch when one set of ideal curves carries the whole Gauss
// image; the pieces the curvature already cuts the mesh into; the pieces the
// crease lines of a noisy mesh part it into (beside the alternatives below
// where the input may be one developable sheet); else the segmentation's
// patches, with a second opinion (the same mesh as one patch) on small
// meshes, a finer split when a whole object came back unchanged and, beside
// the segmented run of a whole object, the thinned-pieces generator's
// candidates (thinned_pieces.h). The decisions are pure functions
// (tests/unit/plan_test.cpp).
#pragma once

#include "pipeline/options.h"
#include "pipeline/run_context.h"
#include "pipeline/run_result.h"
#include "pipeline/selection.h"

#include <Eigen/Core>

#include <vector>

namespace developable {

// RMS angle (rad) between the normals and one set of ideal curves above which
// automatic segmentation splits the mesh into patches (docs/segmentation.md).
inline constexpr double kAutoSegmentationError = 0.12;

// Open meshes automatic segmentation splits, up to this many interior
// vertices, are also run as one patch (the second opinion): a second run,
// which a 1k-vertex family mesh pays in 0.1-0.5 s.
inline constexpr Eigen::Index kSecondOpinionVertices = 10000;

// Whether automatic segmentation splits a mesh: always when it is a whole
// object (is_object, selection.h: closed, or of total curvature at least pi;
// such a surface is never one developable piece: its curvature sums to 4 pi
// on a sphere-like one; the fit of one curve let rounded boxes through,
// their flat sides carrying most of the area), else when the one-patch
// curves miss the normals by more than kAutoSegmentationError (rad, RMS).
bool splits_automatically(bool object, double one_patch_fit_error);

// Whether a split mesh is also run as one patch: automatic segmentation,
// more than one patch, not a whole object, up to kSecondOpinionVertices
// interior vertices, and curvature to lose. The misfit that chose the split
// also grows where the fit of one curve fails on a developable (a coarse or
// noisy Gauss image the fit calls a blob), and there the split run is worse
// on every figure.
bool wants_second_opinion(const PipelineOptions& options, int patch_count, bool object, Eigen::Index interior_vertices,
                          double mean_defect);

// Whether a whole object split automatically is split again twice as finely:
// its run came back unchanged because every better candidate was
// inadmissible, none was better, or none showed a gain (not because it was
// developable already): smaller patches gather less curvature on each seam.
bool splits_finer(const PipelineStats& automatic);

// The curvature must sit on the crease pieces' borders: the mean |angle
// defect| of the interior vertices on a border at least this many times that
// of the vertices inside the pieces. A crease carries angle defect, noise
// spreads it everywhere, a tangent seam carries none: on seeds 0-19 of
// devkit/assemblies.py the true pieces of every part but the square-to-round
// transition give 4.4-285 (noise 0.5-5 %), the transitions' tangent seams
// 0.8-1.4, and the pieces found on a transition where its apex fans made
// lines 0.44 (docs/method.md, "Crease pieces").
inline constexpr double kBorderCurvature = 2.0;

// Whether the crease pieces (segmentation/crease_pieces.h) are the patches of
// a run: the caller wants no patch count of its own (wanted_patches 0), there
// are two pieces or more, each fits its cone within the noise (worst_fit at
// most kCreasePieceFit) and the curvature sits on their borders
// (border_defect at least kBorderCurvature times inside_defect; both mean
// |defect|, rad).
bool takes_crease_pieces(int wanted_patches, int count, double worst_fit, double border_defect, double inside_defect);

// On crease pieces a vertex moves at most this many times the noise that
// leaves their cones (its standard deviation along the normal, crease_pieces.h's
// cone_noise): the run removes noise, it does not reshape the part. Uniform
// noise of amplitude a per coordinate has a standard deviation of a / sqrt(3)
// along the normal and moves a vertex along it by at most a, 1.73 times that.
// Under the user's limit alone (1 % of the diagonal), the deformation moved a
// tee's branch and a cup's side as a whole by up to 20 times the noise to
// make them flat (seeds 0-19: Hausdorff distance to the noise-free twin 7-20
// times the input's); with 3 times the noise 16 of 160 runs ended farther
// than 1.5 times the input's, the polish pushing single vertices of irregular
// triangulations outward to the limit; with 2 times, 2 (1.61, 1.66; flat
// shares 99-100 %); with 1.5 times, the 12 farthest of 3 times within 1.5, but
// flat shares down to 91 %.
inline constexpr double kCreaseMoveNoise = 2.0;

// Whether the result of the plan's other alternatives competes with the run
// on crease pieces (whose creases did not decide, crease_pieces_compete):
// when it shows one developable sheet within the noise
// (one_sheet_within_noise), or when the crease pieces' run improved nothing
// (then the order returns the other result if it improved the input: with
// the polish off, a curved fold's run on its pieces comes back unchanged
// and its one-patch deformation is the result, as without crease pieces).
bool others_compete(bool crease_pieces_improved, bool one_sheet);

// The move limit (caller's units) of a run on crease pieces: the smaller of
// the run's `limit` (0: none) and kCreaseMoveNoise times `noise` (> 0).
double crease_move_limit(double limit, double noise);

// How far the angle defects on the crease pieces' borders exceed what the
// noise gives the vertices of a fold: the sum of their squared defects over
// noise^2 times the sum of their noise gains (core/measures.h's
// angle_defect_noise_gain: the defect variance per unit noise variance, to
// first order). A fold's vertices are flat on one developable sheet (a
// curved fold, the edge of a tangent developable, both one piece), but noise
// gives them defects of first order where a flat vertex's are of second: the
// border-over-inside test of takes_crease_pieces passes them (curved folds
// of devkit/families.py, seeds 100-102: 3.4-18). On such a sheet the figure
// is about 1 whatever the noise or the triangulation (0.65-1.35 on those
// folds, the noise estimated as crease_pieces.h's cone_noise); a tee, a
// Y-branch, an elbow's mitre carry curvature of their own (on seeds 0-19 of
// devkit/assemblies.py 85 of the 121 runs whose crease lines part the mesh
// give 4-3700), but where the triangulation's slivers make every defect
// noisy the mitres too fall to 1-3, and a cup's rim to 1.3-3.2
// (docs/method.md, "Crease pieces"). 0 without border vertices; infinite
// when the gains are 0 and a defect is not.
//   defects, gains: per border vertex; noise: standard deviation per
//   coordinate (caller's units), > 0.
double crease_defect_excess(const std::vector<double>& defects, const std::vector<double>& gains, double noise);

// Crease pieces whose border defects exceed what a fold's noise gives by at
// least this factor (crease_defect_excess) carry curvature one developable
// sheet cannot have, and their run is the result. Below it the input may be
// one developable sheet, and the plan's other alternatives run too
// (one_sheet_within_noise). The figure's noise is an estimate from above
// (cone_noise holds what the facets make of the cone fits), so the factor
// only errs toward the second run; 4 is the RMS defect twice the fold's
// noise, ten standard deviations of the mean of 50 squared standard normal
// variables above its mean 1.
inline constexpr double kCreaseDefectExcess = 4.0;

// Whether the run on crease pieces competes with the plan's other
// alternatives instead of being the result (kCreaseDefectExcess).
bool crease_pieces_compete(double defect_excess);

// Whether the result of the plan's other alternatives shows the input to be
// one developable sheet within its noise, so that it competes with the run on
// the crease pieces under the one order (select, selection.h): as developable
// as a developable mesh (as_developable against a 100 % flat one: at least
// 99 % flat, mean |defect| within 1 % of the input's) and moved by no more
// than the noise the crease pieces' run is held to (RMS motion at most
// kCreaseMoveNoise times `noise`). Curved folds, a generalized cone and a
// tangent developable of devkit/families.py come back so as one patch, 100 %
// flat within 0.14-1.06 times the noise (RMS), where their crease pieces
// leave the fold's vertices curved (93-97 % flat); on the assemblies whose
// creases the noise buries (slivers, cups; seeds 0-19 and 100-119) the other
// alternatives reached at most 97 % flat, or moved up to 21 times the noise
// (a reducer's cone 87 % flat as one patch, 17 times the noise, 12 times the
// input's distance to its twin), and the order alone, which takes the more
// developable, would take them.
//   other, input: the figures (selection.h); other_rms_motion: its RMS
//   motion from the input, noise: as crease_move_limit's (caller's units).
bool one_sheet_within_noise(const Figures& other, const Figures& input, double other_rms_motion, double noise);

// Runs the plan on a measured input and returns its result.
PipelineResult run_plan(const MeasuredInput& input, const Progress& progress);

}  // namespace developable

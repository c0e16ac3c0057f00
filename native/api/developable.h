/* C ABI of the developable engine.
 *
 * Plain C, so that Python's ctypes (the Blender add-on) and any other language
 * can call it. Rules every function keeps:
 *   - no C++ exception crosses this boundary, nothing aborts the process;
 *   - nothing is written outside the buffers the caller passes, whose sizes
 *     are checked against the counts the caller gives;
 *   - no global state: calls on different data may run on different threads.
 * Errors come back as a DEV_STATUS_* code plus a message naming the first bad
 * element, copied into the caller's `message` buffer (always NUL-terminated).
 *
 * One result per input: the same mesh and parameters give bit-identical
 * output on one machine, whatever ran before and whatever the thread count.
 * The environment variable DEVELOPABLE_THREADS (0 or unset: the machine's
 * cores, at most 8) sets how many threads dev_run uses; it changes only the
 * time. DEVELOPABLE_MEMORY_BUDGET_MB sets the memory budget (memory_budget.h). */
#ifndef DEVELOPABLE_H
#define DEVELOPABLE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define DEV_API __declspec(dllexport)
#else
#define DEV_API __attribute__((visibility("default")))
#endif

/* Bumped whenever a struct layout or a signature below changes. */
#define DEV_ABI_VERSION 11

/* Status codes (values are stable). */
enum {
  DEV_STATUS_OK = 0,
  DEV_STATUS_EMPTY_INPUT = 1,
  DEV_STATUS_INDEX_OUT_OF_RANGE = 2,
  DEV_STATUS_NON_FINITE_COORDINATE = 3,
  DEV_STATUS_DEGENERATE_TRIANGLE = 4,
  DEV_STATUS_DUPLICATE_TRIANGLE = 5,
  DEV_STATUS_NON_MANIFOLD = 6,
  DEV_STATUS_INVALID_ARGUMENT = 7,
  DEV_STATUS_NO_FREE_VERTEX = 8,
  DEV_STATUS_CANCELLED = 9,
  DEV_STATUS_NUMERICAL_FAILURE = 10,
  DEV_STATUS_OUT_OF_MEMORY = 11,
  DEV_STATUS_INTERNAL_ERROR = 12,
  DEV_STATUS_NO_INTERIOR_VERTEX = 13
};

/* Deformation modes. */
enum {
  DEV_MODE_REFIT = 0, /* refit the ideal curve and targets from the deformed mesh each iteration (default) */
  DEV_MODE_PAPER = 1  /* the paper: one set of targets, the 11-row system factored once */
};

/* How the normal rows enter the linear system (dev_params.solver). */
enum {
  DEV_SOLVER_DECOUPLED = 0, /* normal rows moved to the right-hand side: one n x n matrix shared by
                               x, y and z, factored once even when the targets change (default) */
  DEV_SOLVER_COUPLED = 1    /* the paper's 11 rows per triangle in one 3n x 3n matrix, refactored
                               (numerically only) whenever the targets change */
};

/* Why the iteration stopped (dev_stats.stop_reason). */
enum {
  DEV_STOP_ALREADY_DEVELOPABLE = 0, /* nothing to deform, mesh untouched: mean |defect| already below
                                       developable_threshold, or the curvature on cuts that part the
                                       mesh into pieces flat inside (dev_stats.unchanged_reason) */
  DEV_STOP_CONVERGED = 1,           /* mean |defect| changed by less than stop_relative_change
                                       (not on a segmented mesh in the refit mode, which stops
                                       by stalling) */
  DEV_STOP_ITERATION_LIMIT = 2,     /* max_iterations reached */
  DEV_STOP_STALLED = 3              /* the best score improved by less than 5 % in 10 iterations (1 %
                                       in 30 on a segmented mesh in the refit mode). The score is the
                                       mean |defect|; on a segmented mesh in the refit mode, the
                                       median |defect| inside the patches */
};

/* What the run returned (dev_stats.result). */
enum {
  DEV_RESULT_IMPROVED = 0, /* the returned mesh is admissible and better (docs/method.md, "The rule"):
                              no face turned over, no crease inside a patch, within the move limit,
                              the mean |defect| not above the input's (a closed mesh's up to 5 %
                              above), the flat share not below it, a gain a user sees; any figure
                              that got worse all the same (the largest |defect|, a closed mesh's
                              mean) is in dev_stats.worse_figures and the message */
  DEV_RESULT_UNCHANGED = 1 /* the input is returned (no honest improvement within the limits, or
                              already developable); why: dev_stats.unchanged_reason, in words
                              dev_stats.result_message */
};

/* Why the input came back (dev_stats.unchanged_reason, ABI 7). The first three
 * mean there was nothing to do; the others that nothing good was found. */
enum {
  DEV_UNCHANGED_NONE = 0,                  /* the result is DEV_RESULT_IMPROVED */
  DEV_UNCHANGED_ALREADY_DEVELOPABLE = 1,   /* mean |defect| below developable_threshold */
  DEV_UNCHANGED_DEVELOPABLE_PIECEWISE = 2, /* every vertex inside the patches is flat (|defect| <
                                              1e-3 rad): the curvature sits on the seams. The
                                              patches are the pieces the curvature cuts the mesh
                                              into (a lobster-back elbow), or the segmentation's,
                                              each fitting its cone */
  DEV_UNCHANGED_ALREADY_FLAT = 3,          /* every interior vertex is flat already and no iterate
                                              lowered the curvature further */
  DEV_UNCHANGED_NO_VISIBLE_GAIN = 4,       /* the best result made no vertex flat and did not lower
                                              the mean |defect|: it moved the curvature only */
  DEV_UNCHANGED_NO_BETTER_ITERATE = 5,     /* no iterate lowered the curvature (a larger tolerance
                                              or more iterations may) */
  DEV_UNCHANGED_REJECTED = 6               /* every iterate that lowered the curvature turned faces
                                              over, raised the mean |defect| or lost flat vertices
                                              (the message names which) */
};

/* Which generator made the returned mesh (dev_stats.result_origin, ABI 9). */
enum {
  DEV_ORIGIN_INPUT = 0,                 /* the input, returned unchanged (dev_stats.unchanged_reason) */
  DEV_ORIGIN_DEFORMATION = 1,           /* an iterate of the normal-guided deformation */
  DEV_ORIGIN_DEFORMATION_POLISH = 2,    /* ... finished by the angle-defect polish */
  DEV_ORIGIN_NEAR_FLAT_POLISH = 3,      /* ... then its nearly flat vertices polished on their own */
  DEV_ORIGIN_INPUT_POLISH = 4,          /* least motion: the angle-defect polish of the input itself */
  DEV_ORIGIN_SMOOTHED_INPUT_POLISH = 5, /* ... of the input with its noise smoothed */
  DEV_ORIGIN_SMOOTHED_STEP_POLISH = 6,  /* ... of that after one deformation step */
  DEV_ORIGIN_PROJECTED_INPUT = 7,       /* ... the input projected onto developable meshes from its smoothing */
  DEV_ORIGIN_THINNED_PIECES = 8,        /* ruled pieces from the thinned Gauss image (closed meshes) */
  DEV_ORIGIN_RULED_FINISH = 9           /* ABI 11: a sheet's result finished flat and ruled (noisy scans) */
};

/* Figures of an improved result that a user sees worse than the input's (dev_stats.worse_figures,
 * or-ed flags, ABI 9). A result with any of them is still better by the engine's rule, but a front
 * end shows it as a warning. */
enum {
  DEV_WORSE_MEAN_DEFECT = 1,  /* mean |defect| grew (a closed surface's curvature gathers on seams) */
  DEV_WORSE_MAX_DEFECT = 2,   /* largest |defect| grew */
  DEV_WORSE_FLAT_SHARE = 4,   /* fewer flat vertices */
  DEV_WORSE_RULED_SHARE = 8,  /* fewer flat-and-ruled vertices */
  DEV_WORSE_TURNED_FACES = 16 /* faces turned over */
};

/* Seam treatment for segmented meshes (issue: segmentation). */
enum {
  DEV_SEAMS_FREE = 0,  /* one global solve, seams move freely (default) */
  DEV_SEAMS_PINNED = 1 /* the paper: patch borders pinned, patches deformed one by one */
};

typedef struct dev_params {
  double omega;                 /* weight of the normal rows (Eq. 3), > 0. Default 5. */
  double tolerance;             /* E_allow: largest vertex move, in multiples of the average edge
                                   length AE; <= 0 means no limit. Default 10. */
  int32_t max_iterations;       /* >= 1. Default 400 (most runs stop earlier, see DEV_STOP_*). */
  int32_t mode;                 /* DEV_MODE_*. Default DEV_MODE_REFIT. */
  int32_t pin_boundary;         /* nonzero: pin every boundary vertex. Default 0. */
  int32_t use_mls_weights;      /* nonzero: Eq. 5 moving-least-squares row weights around pins. Default 1. */
  double stop_relative_change;  /* one patch: stop when mean |defect| changes by less than this fraction
                                   between iterations. Default 1e-5 (0.001 %). */
  double developable_threshold; /* mean |defect| (rad) below which the mesh counts as developable
                                   and is returned unchanged. Default 1e-10. */
  int32_t segmentation;         /* -1 automatic (default), 0 off (one patch), 1 on. */
  int32_t target_patches;       /* segmentation: wanted number of patches, 0 = automatic. */
  double segment_max_error;     /* segmentation: largest cone-fitting error of a patch (rad); 0 = default. */
  int32_t seams;                /* DEV_SEAMS_*. Default DEV_SEAMS_FREE. */
  int32_t grid_resolution;      /* effect-field grid cells per side; 0 = automatic (default):
                                   2 sqrt(#faces of the patch), from 32 to 128. */
  int32_t solver;               /* DEV_SOLVER_*. Default DEV_SOLVER_DECOUPLED; DEV_MODE_PAPER always
                                   uses the coupled system, as the paper does. */
  int32_t target_smoothing;     /* rounds of averaging the target normals over neighbouring faces of
                                   the same patch, 0-100; -1 = automatic (default): 1 on a segmented
                                   mesh, 0 on one patch. */
  /* ABI 4: */
  double max_move; /* largest vertex move as a fraction of the bounding box's diagonal;
                      the smaller of this and `tolerance` applies; <= 0 means no limit.
                      Default 0.01 (1 % of the size). */
  int32_t polish;  /* the angle-defect polish after the deformation: -1 automatic
                      (default: on in DEV_MODE_REFIT, off in DEV_MODE_PAPER), 0 off, 1 on. */
  /* ABI 6: */
  int32_t polish_smoothed_input; /* nonzero: where the polish of the input competes with the
                                   deformation's result (least motion, at every size), the
                                   polish of the input with its noise smoothed (local quadric fits),
                                   of that after one deformation step and, on one patch, the input
                                   projected onto developable meshes from its smoothing compete
                                   too. Default 1. */
} dev_params;

typedef struct dev_stats {
  int64_t vertices;
  int64_t faces;
  int64_t interior_vertices;
  int64_t patches;
  int64_t curves;
  int32_t iterations;
  int32_t stop_reason;        /* DEV_STOP_* */
  double average_edge_length; /* AE, caller's units */
  double mean_defect_before;  /* E_before: mean |angle defect| over interior vertices, rad */
  double mean_defect_after;   /* E_after */
  double max_defect_before;
  double max_defect_after;
  double change_percent;    /* dE = 100 (E_after - E_before) / E_before; 0 when E_before is 0 */
  double max_vertex_move;   /* largest distance a vertex moved, caller's units */
  double time_decompose_ms; /* t_D: building and factoring the normal matrix */
  double time_iterate_ms;   /* t_I: the iterations */
  double time_total_ms;     /* t_T: the whole call, checks and fitting included */
  /* ABI 3: */
  int32_t result;            /* DEV_RESULT_*: the admissible candidate the order returns (see
                                DEV_RESULT_IMPROVED), or the input, UNCHANGED */
  int64_t faces_turned_over; /* faces of the result whose normal is > 90 degrees from the
                                input's (not counting faces already turned in the input) */
  double flat_share_before;  /* share of interior vertices with |defect| < 1e-3 rad, 0..1 */
  double flat_share_after;
  char result_message[256]; /* plain-words sentence for the user, NUL-terminated; empty if none */
  /* ABI 4: */
  int32_t polish_iterations; /* steps of the angle-defect polish kept (0: none, or it was off) */
  double time_polish_ms;     /* the polish's share of t_T */
  /* ABI 7: */
  int32_t unchanged_reason; /* DEV_UNCHANGED_*: why the input came back (0 when improved) */
  /* ABI 9: */
  int32_t result_origin;     /* DEV_ORIGIN_*: which generator made the returned mesh */
  int32_t worse_figures;     /* DEV_WORSE_* flags: figures of the result worse than the input's */
  double ruled_share_before; /* share of interior vertices flat AND ruled: |defect| < flat_threshold
                                and the normals of their faces within ruled_threshold (rms, rad) of
                                one great circle (the faces bend about one axis) */
  double ruled_share_after;
  double crumpled_share_before; /* flat but not ruled: zero angle defect bought with a zigzag of facets */
  double crumpled_share_after;
  double move_limit;      /* the largest move a vertex was allowed, caller's units (the smaller
                             of tolerance * AE and max_move * diagonal); 0: no limit */
  double flat_threshold;  /* rad: the |defect| under which a vertex counts as flat (1e-3) */
  double ruled_threshold; /* rad: the normals' spread under which a flat vertex counts as ruled */
  /* ABI 10: */
  char orientation_note[256]; /* what the run turned before it ran (orientation.h), the words dev_validate
                                 gives after "ok: ": how many triangles were wound the other way, or
                                 that the surface is one-sided and where it is cut. NUL-terminated,
                                 never cut short; empty when every face agreed with its neighbours
                                 as given */
} dev_stats;

/* Opaque result of one run; free with dev_result_free. */
typedef struct dev_result dev_result;

/* Progress callback: fraction in [0, 1] and a stage name. Return 0 to cancel,
 * nonzero to go on. Called on the thread that called dev_run. */
typedef int (*dev_progress_fn)(double fraction, const char* stage, void* user);

/* DEV_ABI_VERSION of the loaded library: compare before any other call. */
DEV_API int32_t dev_abi_version(void);

/* Engine version string, e.g. "0.1.0". Static storage, never freed. */
DEV_API const char* dev_version_string(void);

/* Fills *params with the defaults. */
DEV_API void dev_default_params(dev_params* params);

/* Runs the whole pipeline.
 *   positions: n_vertices * 3 float64 (x, y, z per vertex).
 *   triangles: n_triangles * 3 int32 zero-based vertex indices.
 *   pinned:    NULL, or n_vertices bytes; nonzero = vertex must not move.
 *   params:    NULL for the defaults.
 *   progress:  NULL, or a callback (see above).
 *   result:    receives a new result on DEV_STATUS_OK, NULL otherwise.
 *   message, message_capacity: receives the error (or "ok"), truncated to fit.
 * Returns a DEV_STATUS_* code. The input buffers are only read. */
DEV_API int32_t dev_run(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                        const uint8_t* pinned, const dev_params* params, dev_progress_fn progress, void* user,
                        dev_result** result, char* message, size_t message_capacity);

/* Only the input check of dev_run (stage 1): same codes and messages. Either winding of every
 * triangle is accepted: dev_run and dev_unfold turn faces so that neighbours agree
 * (native/core/orientation.h), on a one-sided surface (a Möbius strip) everywhere but along a
 * short cut, and hand per-face and per-corner outputs back in the caller's winding. On
 * DEV_STATUS_OK the message is "ok", or "ok: " and a sentence saying what is turned (how many
 * triangles, or that the surface is one-sided and where it is cut); dev_run's result carries the
 * same sentence (dev_stats.orientation_note), so a caller that runs needs no check first. */
DEV_API int32_t dev_validate(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                             char* message, size_t message_capacity);

DEV_API void dev_result_free(dev_result* result);

/* Accessors. Each copies into a caller buffer whose length (in elements of
 * the pointed type) is `capacity`; returns DEV_STATUS_OK, or
 * DEV_STATUS_INVALID_ARGUMENT when the buffer is NULL or too small. */
DEV_API int32_t dev_result_stats(const dev_result* result, dev_stats* stats);
/* n_vertices * 3 float64: the deformed positions. */
DEV_API int32_t dev_result_positions(const dev_result* result, double* out, int64_t capacity);
/* n_vertices float64: angle defect (rad) per vertex before / after; 0 on boundary vertices. */
DEV_API int32_t dev_result_defect_before(const dev_result* result, double* out, int64_t capacity);
DEV_API int32_t dev_result_defect_after(const dev_result* result, double* out, int64_t capacity);
/* n_vertices bytes: 1 for interior vertices (where the defect is defined). */
DEV_API int32_t dev_result_interior(const dev_result* result, uint8_t* out, int64_t capacity);
/* n_triangles * 3 float64: the target normal of each face in the step that made the returned
 * positions (the input's fit when the input is returned), in the caller's winding: beside the
 * face's own normal as the caller winds it, also where the engine turned the face over. */
DEV_API int32_t dev_result_target_normals(const dev_result* result, double* out, int64_t capacity);
/* n_triangles int32: patch id of each face, 0 .. patches-1. */
DEV_API int32_t dev_result_patch_ids(const dev_result* result, int32_t* out, int64_t capacity);

/* Ideal curves behind those targets, as polylines on the unit sphere (the Gauss image of the
 * engine's winding: a face it turned over has its target's antipode on them). */
DEV_API int64_t dev_result_curve_count(const dev_result* result);
/* Point count, patch id and closed flag of curve `index`; returns DEV_STATUS_INVALID_ARGUMENT
 * for an index out of range. Any output pointer may be NULL. */
DEV_API int32_t dev_result_curve_info(const dev_result* result, int64_t index, int64_t* n_points, int32_t* patch,
                                      int32_t* closed);
/* n_points * 3 float64 of curve `index`. */
DEV_API int32_t dev_result_curve_points(const dev_result* result, int64_t index, double* out, int64_t capacity);

/* ---- Flat patterns (ABI 3): unfold the patches, lay them out, export SVG ----
 * Pipeline: unfold (native/unfold.h), pattern_layout.h, pattern_svg.h. */

typedef struct dev_pattern_params {
  double sheet_width_mm;      /* > 0. Default 210 (A4 portrait). */
  double sheet_height_mm;     /* > 0. Default 297. */
  double margin_mm;           /* >= 0, kept free on every side. Default 10. */
  double spacing_mm;          /* >= 0, at least between two pieces. Default 4. */
  double scale;               /* paper length per model length (1 = 1:1, 0.1 = 1:10), > 0; 0 = automatic:
                                 the largest of 1, 1/2, 1/5, 1/10, ... at which every piece fits.
                                 Default 1. */
  double unit_mm;             /* one model unit in mm, > 0. Default 1000 (metres). */
  double seam_tolerance;      /* >= 0: largest |l_flat / l_3d - 1| of a piece's outline edge; a piece beyond
                                 it is split, so both sides of a seam match within twice this. 0 = no
                                 limit (split only what overlaps). Default 0.0025. */
  int32_t arap_iterations;    /* >= 0: as-rigid-as-possible rounds after the conformal start. Default 50. */
  int32_t layout;             /* nonzero: lay the pieces out on sheets (sheet UVs, labels, SVG);
                                 0: unfold only. Default 1. */
  char unit_name[8];          /* the model unit's name for the scale bar, NUL-terminated ("m", "cm",
                                 "mm", "in"). Default "m". */
  const char* svg_path;       /* NULL or "": write no file; else the SVG: this path for one sheet,
                                 <stem>-1.svg, <stem>-2.svg, ... for more. Default NULL. */
  const int32_t* face_groups; /* NULL, or n_triangles int32: triangles with the same value (e.g. the
                               polygon they were cut from) are never cut apart nor split apart,
                               unless that group alone cannot lie flat. Default NULL. */
  /* ABI 8: */
  double seam_allowance_mm; /* >= 0, on the sheet: the cut line runs this far outside every piece's
                               outline (round corners; a slot narrower than twice it is bridged),
                               and the outline is drawn as a dashed seam line. 0: the outline is
                               the cut line. Default 0. */
  double glue_tabs_mm;      /* >= 0, on the sheet: a glue tab this high on one side of every seam
                               (45 degree ends, halved or left out where it would cross the piece
                               or another tab), its fold line dashed. 0: none. Not with a seam
                               allowance. Default 0. */
} dev_pattern_params;

typedef struct dev_pattern_stats {
  int64_t faces;
  int64_t pieces;
  int64_t sheets; /* 0 without layout */
  int64_t seams;
  int64_t cut_edges; /* edges cut inside patches to make discs */
  int64_t splits;    /* pieces split because their flat map overlapped itself */
  int64_t svg_files;
  double max_strain;      /* largest |l_flat / l_3d - 1| over all face edges */
  double mean_strain;     /* mean of the same over all face edges */
  double max_area_change; /* largest |area_flat / area_3d - 1| over the pieces */
  double scale;           /* as used (resolved when automatic); 0 without layout */
  double time_unfold_ms;
  double time_layout_ms; /* layout and SVG */
  double time_total_ms;
  /* ABI 8: */
  int64_t cut_lines_from_hull; /* with a seam allowance: pieces whose cut line follows the offset of
                                  their convex hull (the exact offset did not close, on a
                                  near-degenerate outline); wider than asked in the hull's pockets */
  int64_t glue_tabs;           /* tabs placed */
  int64_t glue_tabs_dropped;   /* seams without a tab: none fitted on either side, not even at half
                                  height (a seam in runs on the outline: each run) */
} dev_pattern_stats;

typedef struct dev_pattern_piece {
  int32_t patch; /* the patch id its faces came from */
  int32_t sheet; /* 0-based; -1 without layout */
  int64_t faces;
  int32_t cut_edges;
  int32_t splits;    /* how often its patch was split to get here */
  double max_strain; /* relative edge-length change, as in dev_pattern_stats */
  double mean_strain;
  double area_3d; /* model units squared */
  double area_flat;
  double area_change;    /* area_flat / area_3d - 1 */
  double outline_length; /* flat outline, model units */
  double width_mm;       /* bounding box on the sheet (seam allowance included); 0 without layout */
  double height_mm;
  char label[16]; /* "A", "B", ... (also without layout) */
} dev_pattern_piece;

typedef struct dev_pattern_seam {
  int32_t piece_a; /* the piece left of the seam's directed edges */
  int32_t piece_b; /* == piece_a for a cut inside one piece; on the cut of a one-sided surface
                      both sides run the edges the same way */
  int32_t cut;     /* 1: both sides are of the same patch (cut or split); 0: a patch border */
  int64_t edges;
  double length_3d; /* model units */
  double length_a;  /* flat length on piece a, model units */
  double length_b;
  char label[16]; /* the match label both sides carry on the sheets: "1", "2", ... */
} dev_pattern_seam;

typedef struct dev_pattern dev_pattern;

DEV_API void dev_default_pattern_params(dev_pattern_params* params);

/* Unfolds the mesh patch by patch, lays the pieces out and optionally writes the SVG.
 *   positions, triangles: as for dev_run (checked by the same validation).
 *   patch_ids: NULL (one patch) or n_triangles int32 >= 0, e.g. dev_result_patch_ids.
 *   params: NULL for the defaults.
 *   progress, user: NULL, or a callback as for dev_run (ABI 9); returning 0 cancels the call
 *     (DEV_STATUS_CANCELLED, nothing written).
 *   result: receives a new pattern on DEV_STATUS_OK, NULL otherwise.
 * Returns a DEV_STATUS_* code; a piece that does not fit the sheet at the given scale, a bad
 * sheet size or an unwritable svg_path is DEV_STATUS_INVALID_ARGUMENT with the reason. */
DEV_API int32_t dev_unfold(const double* positions, int64_t n_vertices, const int32_t* triangles, int64_t n_triangles,
                           const int32_t* patch_ids, const dev_pattern_params* params, dev_progress_fn progress,
                           void* user, dev_pattern** result, char* message, size_t message_capacity);

DEV_API void dev_pattern_free(dev_pattern* pattern);

/* Accessors, same rules as the dev_result ones. */
DEV_API int32_t dev_pattern_stats_get(const dev_pattern* pattern, dev_pattern_stats* stats);
/* n_triangles * 3 * 2 float64: corner k of face f at 6 f + 2 k, piece-local, model units; the
 * caller's corner k (a face the engine turned over runs clockwise). */
DEV_API int32_t dev_pattern_corner_uvs(const dev_pattern* pattern, double* out, int64_t capacity);
/* n_triangles * 3 * 2 float64: the same on the sheets, mm, x right and y down from the top left
 * corner of the piece's sheet. DEV_STATUS_INVALID_ARGUMENT without layout. */
DEV_API int32_t dev_pattern_sheet_uvs(const dev_pattern* pattern, double* out, int64_t capacity);
/* n_triangles int32: piece of each face. */
DEV_API int32_t dev_pattern_piece_ids(const dev_pattern* pattern, int32_t* out, int64_t capacity);
/* n_triangles float64: largest |l_flat / l_3d - 1| of the face's edges. */
DEV_API int32_t dev_pattern_face_strain(const dev_pattern* pattern, double* out, int64_t capacity);
DEV_API int32_t dev_pattern_piece_get(const dev_pattern* pattern, int64_t index, dev_pattern_piece* piece);
DEV_API int32_t dev_pattern_seam_get(const dev_pattern* pattern, int64_t index, dev_pattern_seam* seam);
/* edges * 2 int32 of seam `index`: (from, to) vertex ids in chain order. */
DEV_API int32_t dev_pattern_seam_edges(const dev_pattern* pattern, int64_t index, int32_t* out, int64_t capacity);
/* Path of SVG file `index` (0 .. svg_files-1), NUL-terminated, into a buffer of `capacity` chars. */
DEV_API int32_t dev_pattern_svg_file(const dev_pattern* pattern, int64_t index, char* out, int64_t capacity);

#ifdef __cplusplus
}
#endif

#endif /* DEVELOPABLE_H */

# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of the developable engine (native/api/developable.h).

No bpy here: this module can be imported and tested from any Python with numpy.

The library is searched, in order:
  1. $DEVELOPABLE_LIBRARY (a path to the .so), when set;
  2. inside the add-on's folder, the parent of this core/ folder (where the
     packaged zip puts it);
  3. the repository's build/lib (development checkout: addon/ beside build/).

From a checkout (the repository on sys.path): `from addon.core import native`.
"""

import ctypes
import os
import sys
import threading

import numpy as np

ABI_VERSION = 11  # DEV_ABI_VERSION this binding was written against

# Status codes (developable.h), values are stable.
STATUS_NAMES = {
    0: "OK",
    1: "EMPTY_INPUT",
    2: "INDEX_OUT_OF_RANGE",
    3: "NON_FINITE_COORDINATE",
    4: "DEGENERATE_TRIANGLE",
    5: "DUPLICATE_TRIANGLE",
    6: "NON_MANIFOLD",
    7: "INVALID_ARGUMENT",
    8: "NO_FREE_VERTEX",
    9: "CANCELLED",
    10: "NUMERICAL_FAILURE",
    11: "OUT_OF_MEMORY",
    12: "INTERNAL_ERROR",
    13: "NO_INTERIOR_VERTEX",
}
STATUS_OK = 0
STATUS_CANCELLED = 9

MODE_REFIT = 0
MODE_PAPER = 1
SEAMS_FREE = 0
SEAMS_PINNED = 1
SOLVER_DECOUPLED = 0
SOLVER_COUPLED = 1

STOP_REASONS = {0: "already developable", 1: "converged", 2: "iteration limit", 3: "stalled"}

# dev_stats.result: what the run returned.
RESULT_IMPROVED = 0
RESULT_UNCHANGED = 1
RESULT_NAMES = {RESULT_IMPROVED: "improved", RESULT_UNCHANGED: "unchanged"}

# dev_stats.unchanged_reason: why the input came back (DEV_UNCHANGED_*).
UNCHANGED_NONE = 0
UNCHANGED_ALREADY_DEVELOPABLE = 1
UNCHANGED_DEVELOPABLE_PIECEWISE = 2
UNCHANGED_ALREADY_FLAT = 3
UNCHANGED_NO_VISIBLE_GAIN = 4
UNCHANGED_NO_BETTER_ITERATE = 5
UNCHANGED_REJECTED = 6

# dev_stats.result_origin: which generator made the returned mesh (DEV_ORIGIN_*).
ORIGIN_INPUT = 0
ORIGIN_INPUT_POLISH = 4
ORIGIN_RULED_FINISH = 9
ORIGIN_NAMES = {
    0: "input",
    1: "deformation",
    2: "deformation_polish",
    3: "near_flat_polish",
    4: "input_polish",
    5: "smoothed_input_polish",
    6: "smoothed_step_polish",
    7: "projected_input",
    8: "thinned_pieces",
    9: "ruled_finish",
}

# Least motion's candidates: the polish of the input itself, or of its smoothing.
LEAST_MOTION_ORIGINS = frozenset((4, 5, 6, 7))
SMOOTHED_ORIGINS = frozenset((5, 6, 7))

# dev_stats.worse_figures: or-ed DEV_WORSE_* flags of an improved result.
WORSE_MEAN_DEFECT = 1
WORSE_MAX_DEFECT = 2
WORSE_FLAT_SHARE = 4
WORSE_RULED_SHARE = 8
WORSE_TURNED_FACES = 16

if sys.platform.startswith("win"):
    LIBRARY_FILE = "developable.dll"
elif sys.platform == "darwin":
    LIBRARY_FILE = "libdevelopable.dylib"
else:
    LIBRARY_FILE = "libdevelopable.so"

ENV_VAR = "DEVELOPABLE_LIBRARY"
# The add-on package folder (this module is in its core/ subpackage).
ADDON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class dev_params(ctypes.Structure):
    _fields_ = [
        ("omega", ctypes.c_double),
        ("tolerance", ctypes.c_double),
        ("max_iterations", ctypes.c_int32),
        ("mode", ctypes.c_int32),
        ("pin_boundary", ctypes.c_int32),
        ("use_mls_weights", ctypes.c_int32),
        ("stop_relative_change", ctypes.c_double),
        ("developable_threshold", ctypes.c_double),
        ("segmentation", ctypes.c_int32),
        ("target_patches", ctypes.c_int32),
        ("segment_max_error", ctypes.c_double),
        ("seams", ctypes.c_int32),
        ("grid_resolution", ctypes.c_int32),
        ("solver", ctypes.c_int32),
        ("target_smoothing", ctypes.c_int32),
        # ABI 4
        ("max_move", ctypes.c_double),
        ("polish", ctypes.c_int32),
        # ABI 6
        ("polish_smoothed_input", ctypes.c_int32),
    ]


class _ParamsBuffer(ctypes.Union):
    """dev_params with room to spare, so that a library whose struct grew
    without an ABI bump cannot write past our buffer."""

    _fields_ = [("params", dev_params), ("_reserve", ctypes.c_char * 512)]


# The engine parameters, in struct order (properties.py builds one Blender
# property per name).
PARAM_NAMES = tuple(name for name, _ in dev_params._fields_)


class dev_stats(ctypes.Structure):
    _fields_ = [
        ("vertices", ctypes.c_int64),
        ("faces", ctypes.c_int64),
        ("interior_vertices", ctypes.c_int64),
        ("patches", ctypes.c_int64),
        ("curves", ctypes.c_int64),
        ("iterations", ctypes.c_int32),
        ("stop_reason", ctypes.c_int32),
        ("average_edge_length", ctypes.c_double),
        ("mean_defect_before", ctypes.c_double),
        ("mean_defect_after", ctypes.c_double),
        ("max_defect_before", ctypes.c_double),
        ("max_defect_after", ctypes.c_double),
        ("change_percent", ctypes.c_double),
        ("max_vertex_move", ctypes.c_double),
        ("time_decompose_ms", ctypes.c_double),
        ("time_iterate_ms", ctypes.c_double),
        ("time_total_ms", ctypes.c_double),
        # ABI 3
        ("result", ctypes.c_int32),
        ("faces_turned_over", ctypes.c_int64),
        ("flat_share_before", ctypes.c_double),
        ("flat_share_after", ctypes.c_double),
        ("result_message", ctypes.c_char * 256),
        # ABI 4
        ("polish_iterations", ctypes.c_int32),
        ("time_polish_ms", ctypes.c_double),
        # ABI 7
        ("unchanged_reason", ctypes.c_int32),
        # ABI 9
        ("result_origin", ctypes.c_int32),
        ("worse_figures", ctypes.c_int32),
        ("ruled_share_before", ctypes.c_double),
        ("ruled_share_after", ctypes.c_double),
        ("crumpled_share_before", ctypes.c_double),
        ("crumpled_share_after", ctypes.c_double),
        ("move_limit", ctypes.c_double),
        ("flat_threshold", ctypes.c_double),
        ("ruled_threshold", ctypes.c_double),
        # ABI 10
        ("orientation_note", ctypes.c_char * 256),
    ]


class dev_pattern_params(ctypes.Structure):
    _fields_ = [
        ("sheet_width_mm", ctypes.c_double),
        ("sheet_height_mm", ctypes.c_double),
        ("margin_mm", ctypes.c_double),
        ("spacing_mm", ctypes.c_double),
        ("scale", ctypes.c_double),
        ("unit_mm", ctypes.c_double),
        ("seam_tolerance", ctypes.c_double),
        ("arap_iterations", ctypes.c_int32),
        ("layout", ctypes.c_int32),
        ("unit_name", ctypes.c_char * 8),
        ("svg_path", ctypes.c_char_p),
        ("face_groups", ctypes.POINTER(ctypes.c_int32)),
        # ABI 8
        ("seam_allowance_mm", ctypes.c_double),
        ("glue_tabs_mm", ctypes.c_double),
    ]


class dev_pattern_stats(ctypes.Structure):
    _fields_ = [
        ("faces", ctypes.c_int64),
        ("pieces", ctypes.c_int64),
        ("sheets", ctypes.c_int64),
        ("seams", ctypes.c_int64),
        ("cut_edges", ctypes.c_int64),
        ("splits", ctypes.c_int64),
        ("svg_files", ctypes.c_int64),
        ("max_strain", ctypes.c_double),
        ("mean_strain", ctypes.c_double),
        ("max_area_change", ctypes.c_double),
        ("scale", ctypes.c_double),
        ("time_unfold_ms", ctypes.c_double),
        ("time_layout_ms", ctypes.c_double),
        ("time_total_ms", ctypes.c_double),
        # ABI 8
        ("cut_lines_from_hull", ctypes.c_int64),
        ("glue_tabs", ctypes.c_int64),
        ("glue_tabs_dropped", ctypes.c_int64),
    ]


class dev_pattern_piece(ctypes.Structure):
    _fields_ = [
        ("patch", ctypes.c_int32),
        ("sheet", ctypes.c_int32),
        ("faces", ctypes.c_int64),
        ("cut_edges", ctypes.c_int32),
        ("splits", ctypes.c_int32),
        ("max_strain", ctypes.c_double),
        ("mean_strain", ctypes.c_double),
        ("area_3d", ctypes.c_double),
        ("area_flat", ctypes.c_double),
        ("area_change", ctypes.c_double),
        ("outline_length", ctypes.c_double),
        ("width_mm", ctypes.c_double),
        ("height_mm", ctypes.c_double),
        ("label", ctypes.c_char * 16),
    ]


class dev_pattern_seam(ctypes.Structure):
    _fields_ = [
        ("piece_a", ctypes.c_int32),
        ("piece_b", ctypes.c_int32),
        ("cut", ctypes.c_int32),
        ("edges", ctypes.c_int64),
        ("length_3d", ctypes.c_double),
        ("length_a", ctypes.c_double),
        ("length_b", ctypes.c_double),
        ("label", ctypes.c_char * 16),
    ]


# Pattern parameters settable through unfold(params=...), in struct order.
PATTERN_PARAM_NAMES = (
    "sheet_width_mm",
    "sheet_height_mm",
    "margin_mm",
    "spacing_mm",
    "scale",
    "unit_mm",
    "seam_tolerance",
    "arap_iterations",
    "layout",
    "unit_name",
    "seam_allowance_mm",
    "glue_tabs_mm",
)

# Length of one model unit in mm, for the unit names the tool and the add-on offer.
UNIT_MM = {"m": 1000.0, "cm": 10.0, "mm": 1.0, "in": 25.4}

# Sheet sizes by name, portrait (width, height) in mm.
SHEETS_MM = {"a4": (210.0, 297.0), "a3": (297.0, 420.0), "letter": (215.9, 279.4)}


PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, ctypes.c_char_p, ctypes.c_void_p)

_P = ctypes.POINTER
_dbl_p = _P(ctypes.c_double)
_i32_p = _P(ctypes.c_int32)
_i64_p = _P(ctypes.c_int64)
_u8_p = _P(ctypes.c_uint8)
_result_p = ctypes.c_void_p


class LibraryError(RuntimeError):
    """The native library is missing, unloadable or of another ABI version.
    The message says what to do; the add-on reports it instead of a traceback."""


class EngineError(RuntimeError):
    """dev_run/dev_validate returned a status other than OK."""

    def __init__(self, status, message):
        self.status = status
        self.status_name = STATUS_NAMES.get(status, "UNKNOWN(%d)" % status)
        self.message = message
        super().__init__("%s: %s" % (self.status_name, message))


def candidate_paths():
    """Where the library is looked for, in order."""
    paths = []
    env = os.environ.get(ENV_VAR)
    if env:
        paths.append(env)
    paths.append(os.path.join(ADDON_DIR, LIBRARY_FILE))
    paths.append(os.path.join(os.path.dirname(ADDON_DIR), "build", "lib", LIBRARY_FILE))
    return paths


_HOW_TO_FIX = (
    "Install the add-on from the release zip (it ships %s), or build the engine "
    "(cmake -S <repo> -B <repo>/build && cmake --build <repo>/build) or point %s at the library."
    % (LIBRARY_FILE, ENV_VAR)
)

_lock = threading.Lock()
_library = None
_library_path = None


def _declare(lib):
    lib.dev_abi_version.restype = ctypes.c_int32
    lib.dev_abi_version.argtypes = []
    lib.dev_version_string.restype = ctypes.c_char_p
    lib.dev_version_string.argtypes = []
    lib.dev_default_params.restype = None
    lib.dev_default_params.argtypes = [_P(dev_params)]
    lib.dev_run.restype = ctypes.c_int32
    lib.dev_run.argtypes = [
        _dbl_p,
        ctypes.c_int64,
        _i32_p,
        ctypes.c_int64,
        _u8_p,
        _P(dev_params),
        PROGRESS_FN,
        ctypes.c_void_p,
        _P(_result_p),
        ctypes.c_char_p,
        ctypes.c_size_t,
    ]
    lib.dev_validate.restype = ctypes.c_int32
    lib.dev_validate.argtypes = [_dbl_p, ctypes.c_int64, _i32_p, ctypes.c_int64, ctypes.c_char_p, ctypes.c_size_t]
    lib.dev_result_free.restype = None
    lib.dev_result_free.argtypes = [_result_p]
    lib.dev_result_stats.restype = ctypes.c_int32
    lib.dev_result_stats.argtypes = [_result_p, _P(dev_stats)]
    for name, ptr in (
        ("dev_result_positions", _dbl_p),
        ("dev_result_defect_before", _dbl_p),
        ("dev_result_defect_after", _dbl_p),
        ("dev_result_interior", _u8_p),
        ("dev_result_target_normals", _dbl_p),
        ("dev_result_patch_ids", _i32_p),
    ):
        fn = getattr(lib, name)
        fn.restype = ctypes.c_int32
        fn.argtypes = [_result_p, ptr, ctypes.c_int64]
    lib.dev_result_curve_count.restype = ctypes.c_int64
    lib.dev_result_curve_count.argtypes = [_result_p]
    lib.dev_result_curve_info.restype = ctypes.c_int32
    lib.dev_result_curve_info.argtypes = [_result_p, ctypes.c_int64, _i64_p, _i32_p, _i32_p]
    lib.dev_result_curve_points.restype = ctypes.c_int32
    lib.dev_result_curve_points.argtypes = [_result_p, ctypes.c_int64, _dbl_p, ctypes.c_int64]
    lib.dev_default_pattern_params.restype = None
    lib.dev_default_pattern_params.argtypes = [_P(dev_pattern_params)]
    lib.dev_unfold.restype = ctypes.c_int32
    lib.dev_unfold.argtypes = [
        _dbl_p,
        ctypes.c_int64,
        _i32_p,
        ctypes.c_int64,
        _i32_p,
        _P(dev_pattern_params),
        PROGRESS_FN,
        ctypes.c_void_p,
        _P(_result_p),
        ctypes.c_char_p,
        ctypes.c_size_t,
    ]
    lib.dev_pattern_free.restype = None
    lib.dev_pattern_free.argtypes = [_result_p]
    lib.dev_pattern_stats_get.restype = ctypes.c_int32
    lib.dev_pattern_stats_get.argtypes = [_result_p, _P(dev_pattern_stats)]
    for name, ptr in (
        ("dev_pattern_corner_uvs", _dbl_p),
        ("dev_pattern_sheet_uvs", _dbl_p),
        ("dev_pattern_piece_ids", _i32_p),
        ("dev_pattern_face_strain", _dbl_p),
    ):
        fn = getattr(lib, name)
        fn.restype = ctypes.c_int32
        fn.argtypes = [_result_p, ptr, ctypes.c_int64]
    lib.dev_pattern_piece_get.restype = ctypes.c_int32
    lib.dev_pattern_piece_get.argtypes = [_result_p, ctypes.c_int64, _P(dev_pattern_piece)]
    lib.dev_pattern_seam_get.restype = ctypes.c_int32
    lib.dev_pattern_seam_get.argtypes = [_result_p, ctypes.c_int64, _P(dev_pattern_seam)]
    lib.dev_pattern_seam_edges.restype = ctypes.c_int32
    lib.dev_pattern_seam_edges.argtypes = [_result_p, ctypes.c_int64, _i32_p, ctypes.c_int64]
    lib.dev_pattern_svg_file.restype = ctypes.c_int32
    lib.dev_pattern_svg_file.argtypes = [_result_p, ctypes.c_int64, ctypes.c_char_p, ctypes.c_int64]


def load(force_reload=False, path=None):
    """Returns the loaded library (ctypes.CDLL); raises LibraryError with advice.
    path: load this file instead of searching (a development or sanitizer
    build); a later load() without a path returns it."""
    global _library, _library_path
    wanted = None if path is None else str(path)
    with _lock:
        if _library is not None and not force_reload and wanted in (None, _library_path):
            return _library
        tried = []
        for path in [wanted] if wanted else candidate_paths():
            if not os.path.isfile(path):
                tried.append("%s (not found)" % path)
                continue
            try:
                lib = ctypes.CDLL(path)
            except OSError as exc:
                raise LibraryError(
                    "Could not load the developable engine %s: %s. %s" % (path, exc, _HOW_TO_FIX)
                ) from None
            try:
                lib.dev_abi_version.restype = ctypes.c_int32
                abi = lib.dev_abi_version()
            except AttributeError:
                raise LibraryError(
                    "%s is not the developable engine (no dev_abi_version). %s" % (path, _HOW_TO_FIX)
                ) from None
            if abi != ABI_VERSION:
                raise LibraryError(
                    "The developable engine %s has ABI version %d but this add-on needs %d: "
                    "install the add-on and library from the same release (rebuild the library "
                    "or update the add-on)." % (path, abi, ABI_VERSION)
                )
            try:
                _declare(lib)
            except AttributeError as exc:
                raise LibraryError(
                    "The developable engine %s lacks a function (%s). %s" % (path, exc, _HOW_TO_FIX)
                ) from None
            _library, _library_path = lib, path
            return lib
        raise LibraryError(
            "The developable engine library was not found; looked at: %s. %s" % ("; ".join(tried), _HOW_TO_FIX)
        )


def library_path():
    return _library_path


def try_load():
    """(library or None, error message or "")."""
    try:
        return load(), ""
    except LibraryError as exc:
        return None, str(exc)


def version():
    return load().dev_version_string().decode("utf-8", "replace")


def _defaults_buffer():
    buf = _ParamsBuffer()
    load().dev_default_params(ctypes.cast(ctypes.byref(buf), _P(dev_params)))
    return buf


def default_params():
    """dict name -> default value, from the library."""
    p = _defaults_buffer().params
    return {name: getattr(p, name) for name in PARAM_NAMES}


def make_params(values):
    """dev_params (in a padded buffer) from the library's defaults overridden by
    `values` (a dict)."""
    buf = _defaults_buffer()
    for name, value in (values or {}).items():
        if name in PARAM_NAMES:
            setattr(buf.params, name, value)
    return buf


def _as_positions(positions):
    a = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
    return a


def _as_triangles(triangles):
    return np.ascontiguousarray(triangles, dtype=np.int32).reshape(-1, 3)


def validate(positions, triangles):
    """(status, message) of the engine's input check: on STATUS_OK "ok", or "ok: " and what a run
    turns, the words run() also returns (Result.stats["orientation_note"])."""
    lib = load()
    pos = _as_positions(positions)
    tri = _as_triangles(triangles)
    msg = ctypes.create_string_buffer(1024)
    status = lib.dev_validate(
        pos.ctypes.data_as(_dbl_p), pos.shape[0], tri.ctypes.data_as(_i32_p), tri.shape[0], msg, len(msg)
    )
    return status, msg.value.decode("utf-8", "replace")


class Result:
    """Everything the add-on needs from one successful run, copied out of the
    native result (which is freed before this object is returned)."""

    def __init__(self):
        self.stats = {}
        self.positions = None  # (n, 3) float64
        self.defect_before = None  # (n,) float64
        self.defect_after = None  # (n,) float64
        self.interior = None  # (n,) bool
        self.target_normals = None  # (t, 3) float64
        self.patch_ids = None  # (t,) int32
        self.curves = []  # list of (points (k,3) float64, patch, closed)


def _copy_result(lib, res, n_vertices, n_triangles):
    out = Result()
    st = dev_stats()
    _check(lib.dev_result_stats(res, ctypes.byref(st)), "dev_result_stats")
    out.stats = {name: getattr(st, name) for name, _ in dev_stats._fields_}
    for name in ("result_message", "orientation_note"):
        out.stats[name] = getattr(st, name).decode("utf-8", "replace")

    def get(fn, shape, dtype, ptr):
        a = np.empty(shape, dtype=dtype)
        _check(fn(res, a.ctypes.data_as(ptr), a.size), fn.__name__)
        return a

    out.positions = get(lib.dev_result_positions, (n_vertices, 3), np.float64, _dbl_p)
    out.defect_before = get(lib.dev_result_defect_before, (n_vertices,), np.float64, _dbl_p)
    out.defect_after = get(lib.dev_result_defect_after, (n_vertices,), np.float64, _dbl_p)
    out.interior = get(lib.dev_result_interior, (n_vertices,), np.uint8, _u8_p).astype(bool)
    out.target_normals = get(lib.dev_result_target_normals, (n_triangles, 3), np.float64, _dbl_p)
    out.patch_ids = get(lib.dev_result_patch_ids, (n_triangles,), np.int32, _i32_p)
    count = lib.dev_result_curve_count(res)
    for i in range(max(0, count)):
        n_points = ctypes.c_int64(0)
        patch = ctypes.c_int32(0)
        closed = ctypes.c_int32(0)
        _check(
            lib.dev_result_curve_info(res, i, ctypes.byref(n_points), ctypes.byref(patch), ctypes.byref(closed)),
            "dev_result_curve_info",
        )
        pts = np.empty((n_points.value, 3), dtype=np.float64)
        if n_points.value:
            _check(lib.dev_result_curve_points(res, i, pts.ctypes.data_as(_dbl_p), pts.size), "dev_result_curve_points")
        out.curves.append((pts, patch.value, bool(closed.value)))
    return out


def _check(status, what):
    if status != STATUS_OK:
        raise EngineError(status, "%s failed" % what)


def _progress_callback(progress, errors):
    """A PROGRESS_FN calling progress(fraction, stage) -> bool (False cancels), or going on
    when progress is None; a Python error it raises is kept in `errors` and cancels."""

    def _callback(fraction, stage, _user):
        if progress is None:
            return 1
        try:
            go_on = progress(float(fraction), stage.decode("utf-8", "replace") if stage else "")
            return 1 if go_on else 0
        except Exception as exc:  # never let a Python error cross into C
            errors.append(exc)
            return 0

    return PROGRESS_FN(_callback)


def run(positions, triangles, pinned=None, params=None, progress=None):
    """Runs the engine. Blocks; ctypes releases the GIL during dev_run, so this
    may run on a worker thread while Blender's UI keeps going.

    positions: (n, 3); triangles: (t, 3) int; pinned: None or (n,) bool;
    params: dict of PARAM_NAMES -> value (missing ones keep the defaults);
    progress: None or callable(fraction, stage) -> bool (False cancels).
    Returns Result; raises EngineError (status != OK, CANCELLED included) or LibraryError.
    """
    lib = load()
    pos = _as_positions(positions)
    tri = _as_triangles(triangles)
    n, t = pos.shape[0], tri.shape[0]
    pin_ptr = None
    if pinned is not None:
        pin = np.ascontiguousarray(pinned, dtype=np.uint8).reshape(-1)
        if pin.shape[0] != n:
            raise EngineError(7, "pinned has %d entries for %d vertices" % (pin.shape[0], n))
        pin_ptr = pin.ctypes.data_as(_u8_p)
    p = make_params(params)
    errors = []
    cb = _progress_callback(progress, errors)  # kept alive for the duration of the call
    res = _result_p()
    msg = ctypes.create_string_buffer(1024)
    status = lib.dev_run(
        pos.ctypes.data_as(_dbl_p),
        n,
        tri.ctypes.data_as(_i32_p),
        t,
        pin_ptr,
        ctypes.cast(ctypes.byref(p), _P(dev_params)),
        cb,
        None,
        ctypes.byref(res),
        msg,
        len(msg),
    )
    message = msg.value.decode("utf-8", "replace")
    if status != STATUS_OK:
        if res.value:
            lib.dev_result_free(res)
        if errors:
            message = "%s (progress callback raised %r)" % (message, errors[0])
        raise EngineError(status, message)
    try:
        return _copy_result(lib, res, n, t)
    finally:
        lib.dev_result_free(res)


class Pattern:
    """One unfolding (dev_unfold), copied out of the native result.

    corner_uvs: (t, 3, 2) piece-local flat corners, model units;
    sheet_uvs: (t, 3, 2) corners on their sheets in mm (x right, y down), or None without layout;
    piece_ids: (t,) int32; face_strain: (t,) float64;
    pieces: list of dicts (dev_pattern_piece fields, label as str);
    seams: list of dicts (dev_pattern_seam fields, label as str, "vertices": (k, 2) int32 directed
    edges in chain order); files: SVG paths written; stats: dict (dev_pattern_stats)."""

    def __init__(self):
        self.stats = {}
        self.corner_uvs = None
        self.sheet_uvs = None
        self.piece_ids = None
        self.face_strain = None
        self.pieces = []
        self.seams = []
        self.files = []


def default_pattern_params():
    p = dev_pattern_params()
    load().dev_default_pattern_params(ctypes.byref(p))
    return {
        name: (getattr(p, name).decode() if name == "unit_name" else getattr(p, name)) for name in PATTERN_PARAM_NAMES
    }


def _struct_dict(st):
    out = {}
    for name, _ in st._fields_:
        value = getattr(st, name)
        out[name] = value.decode("utf-8", "replace") if isinstance(value, bytes) else value
    return out


def unfold(positions, triangles, patch_ids=None, params=None, svg_path=None, face_groups=None, progress=None):
    """Unfolds (dev_unfold). Blocks; ctypes releases the GIL during the call, so this may run
    on a worker thread. params: dict of PATTERN_PARAM_NAMES -> value (unit_name may also
    set unit_mm when that is not given); svg_path: None or the SVG to write; face_groups: None
    or (t,) ints, triangles of one group (e.g. polygon) kept in one piece; progress: None or
    callable(fraction, stage) -> bool (False cancels: EngineError CANCELLED, nothing written).
    Returns Pattern; raises EngineError or LibraryError."""
    lib = load()
    pos = _as_positions(positions)
    tri = _as_triangles(triangles)
    n, t = pos.shape[0], tri.shape[0]
    p = dev_pattern_params()
    lib.dev_default_pattern_params(ctypes.byref(p))
    values = dict(params or {})
    if "unit_name" in values and "unit_mm" not in values and values["unit_name"] in UNIT_MM:
        values["unit_mm"] = UNIT_MM[values["unit_name"]]
    for name, value in values.items():
        if name not in PATTERN_PARAM_NAMES:
            raise EngineError(7, "unknown pattern parameter %r" % name)
        setattr(p, name, value.encode() if name == "unit_name" else value)
    path_bytes = os.fsencode(svg_path) if svg_path else None
    p.svg_path = path_bytes
    ids_ptr = None
    if patch_ids is not None:
        ids = np.ascontiguousarray(patch_ids, dtype=np.int32).reshape(-1)
        if ids.shape[0] != t:
            raise EngineError(7, "patch_ids has %d entries for %d triangles" % (ids.shape[0], t))
        ids_ptr = ids.ctypes.data_as(_i32_p)
    if face_groups is not None:
        groups = np.ascontiguousarray(face_groups, dtype=np.int32).reshape(-1)
        if groups.shape[0] != t:
            raise EngineError(7, "face_groups has %d entries for %d triangles" % (groups.shape[0], t))
        p.face_groups = groups.ctypes.data_as(_i32_p)
    res = _result_p()
    msg = ctypes.create_string_buffer(1024)
    errors = []
    cb = _progress_callback(progress, errors)  # kept alive for the duration of the call
    status = lib.dev_unfold(
        pos.ctypes.data_as(_dbl_p),
        n,
        tri.ctypes.data_as(_i32_p),
        t,
        ids_ptr,
        ctypes.byref(p),
        cb,
        None,
        ctypes.byref(res),
        msg,
        len(msg),
    )
    if status != STATUS_OK:
        if res.value:
            lib.dev_pattern_free(res)
        message = msg.value.decode("utf-8", "replace")
        if errors:
            message = "%s (progress callback raised %r)" % (message, errors[0])
        raise EngineError(status, message)
    try:
        out = Pattern()
        st = dev_pattern_stats()
        _check(lib.dev_pattern_stats_get(res, ctypes.byref(st)), "dev_pattern_stats_get")
        out.stats = _struct_dict(st)

        def get(fn, shape, dtype, ptr):
            a = np.empty(shape, dtype=dtype)
            _check(fn(res, a.ctypes.data_as(ptr), a.size), fn.__name__)
            return a

        out.corner_uvs = get(lib.dev_pattern_corner_uvs, (t, 3, 2), np.float64, _dbl_p)
        if p.layout:
            out.sheet_uvs = get(lib.dev_pattern_sheet_uvs, (t, 3, 2), np.float64, _dbl_p)
        out.piece_ids = get(lib.dev_pattern_piece_ids, (t,), np.int32, _i32_p)
        out.face_strain = get(lib.dev_pattern_face_strain, (t,), np.float64, _dbl_p)
        for i in range(st.pieces):
            piece = dev_pattern_piece()
            _check(lib.dev_pattern_piece_get(res, i, ctypes.byref(piece)), "dev_pattern_piece_get")
            out.pieces.append(_struct_dict(piece))
        for i in range(st.seams):
            seam = dev_pattern_seam()
            _check(lib.dev_pattern_seam_get(res, i, ctypes.byref(seam)), "dev_pattern_seam_get")
            d = _struct_dict(seam)
            edges = np.empty((seam.edges, 2), dtype=np.int32)
            _check(
                lib.dev_pattern_seam_edges(res, i, edges.ctypes.data_as(_i32_p), edges.size), "dev_pattern_seam_edges"
            )
            d["vertices"] = edges
            out.seams.append(d)
        buf = ctypes.create_string_buffer(4096)
        for i in range(st.svg_files):
            _check(lib.dev_pattern_svg_file(res, i, buf, len(buf)), "dev_pattern_svg_file")
            out.files.append(os.fsdecode(buf.value))
        return out
    finally:
        lib.dev_pattern_free(res)

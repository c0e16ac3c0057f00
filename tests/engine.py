"""Test-side ctypes access to the engine's C ABI (native/developable.h).

Kept independent of the add-on so that engine tests run without Blender."""
import ctypes
import os

import numpy as np

STATUS = {
    0: "ok", 1: "empty_input", 2: "index_out_of_range", 3: "non_finite_coordinate",
    4: "degenerate_triangle", 5: "duplicate_triangle", 6: "non_manifold",
    7: "invalid_argument", 8: "no_free_vertex", 9: "cancelled", 10: "numerical_failure",
    11: "out_of_memory", 12: "internal_error", 13: "no_interior_vertex",
}
MODES = {"refit": 0, "paper": 1}
SOLVERS = {"decoupled": 0, "coupled": 1}
SEAMS = {"free": 0, "pinned": 1}
STOP_REASONS = {0: "already_developable", 1: "converged", 2: "iteration_limit", 3: "stalled"}


class Params(ctypes.Structure):
    _fields_ = [
        ("omega", ctypes.c_double), ("tolerance", ctypes.c_double),
        ("max_iterations", ctypes.c_int32), ("mode", ctypes.c_int32),
        ("pin_boundary", ctypes.c_int32), ("use_mls_weights", ctypes.c_int32),
        ("stop_relative_change", ctypes.c_double), ("developable_threshold", ctypes.c_double),
        ("segmentation", ctypes.c_int32), ("target_patches", ctypes.c_int32),
        ("segment_max_error", ctypes.c_double), ("seams", ctypes.c_int32),
        ("grid_resolution", ctypes.c_int32), ("solver", ctypes.c_int32),
        ("target_smoothing", ctypes.c_int32),
    ]


class Stats(ctypes.Structure):
    _fields_ = [
        ("vertices", ctypes.c_int64), ("faces", ctypes.c_int64),
        ("interior_vertices", ctypes.c_int64), ("patches", ctypes.c_int64),
        ("curves", ctypes.c_int64), ("iterations", ctypes.c_int32),
        ("stop_reason", ctypes.c_int32),
        ("average_edge_length", ctypes.c_double), ("mean_defect_before", ctypes.c_double),
        ("mean_defect_after", ctypes.c_double), ("max_defect_before", ctypes.c_double),
        ("max_defect_after", ctypes.c_double), ("change_percent", ctypes.c_double),
        ("max_vertex_move", ctypes.c_double), ("time_decompose_ms", ctypes.c_double),
        ("time_iterate_ms", ctypes.c_double), ("time_total_ms", ctypes.c_double),
        ("result", ctypes.c_int32), ("faces_turned_over", ctypes.c_int64),
        ("flat_share_before", ctypes.c_double), ("flat_share_after", ctypes.c_double),
        ("result_message", ctypes.c_char * 256),
    ]


PROGRESS = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, ctypes.c_char_p, ctypes.c_void_p)


class EngineError(Exception):
    def __init__(self, status, message):
        super().__init__("%s: %s" % (STATUS.get(status, status), message))
        self.status = STATUS.get(status, status)
        self.message = message


class Result:
    """Everything dev_run returns, copied into numpy arrays."""


class Engine:
    def __init__(self, path):
        lib = ctypes.CDLL(path)
        p, i64, i32 = ctypes.c_void_p, ctypes.c_int64, ctypes.c_int32
        lib.dev_abi_version.restype = i32
        lib.dev_run.restype = i32
        lib.dev_run.argtypes = [p, i64, p, i64, p, ctypes.POINTER(Params), PROGRESS, p,
                                ctypes.POINTER(p), ctypes.c_char_p, ctypes.c_size_t]
        lib.dev_validate.restype = i32
        lib.dev_validate.argtypes = [p, i64, p, i64, ctypes.c_char_p, ctypes.c_size_t]
        lib.dev_default_params.argtypes = [ctypes.POINTER(Params)]
        lib.dev_result_free.argtypes = [p]
        lib.dev_result_stats.argtypes = [p, ctypes.POINTER(Stats)]
        lib.dev_result_curve_count.restype = i64
        lib.dev_result_curve_count.argtypes = [p]
        lib.dev_result_curve_info.argtypes = [p, i64, ctypes.POINTER(i64), ctypes.POINTER(i32),
                                              ctypes.POINTER(i32)]
        for name in ("positions", "defect_before", "defect_after", "interior",
                     "target_normals", "patch_ids"):
            getattr(lib, "dev_result_" + name).argtypes = [p, p, i64]
            getattr(lib, "dev_result_" + name).restype = i32
        lib.dev_result_curve_points.argtypes = [p, i64, p, i64]
        self.lib = lib

    def params(self, **overrides):
        params = Params()
        self.lib.dev_default_params(ctypes.byref(params))
        for key, value in overrides.items():
            if key == "mode":
                value = MODES[value]
            elif key == "solver":
                value = SOLVERS[value]
            elif key == "seams":
                value = SEAMS[value]
            setattr(params, key, value)
        return params

    def validate(self, positions, triangles):
        pos = np.ascontiguousarray(positions, dtype=np.float64)
        tri = np.ascontiguousarray(triangles, dtype=np.int32)
        message = ctypes.create_string_buffer(512)
        status = self.lib.dev_validate(pos.ctypes.data, len(pos), tri.ctypes.data, len(tri),
                                       message, len(message))
        return STATUS[status], message.value.decode()

    def run(self, positions, triangles, pinned=None, progress=None, **overrides):
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        tri = np.ascontiguousarray(triangles, dtype=np.int32).reshape(-1, 3)
        pins = None if pinned is None else np.ascontiguousarray(pinned, dtype=np.uint8)
        params = self.params(**overrides)
        callback = PROGRESS(progress) if progress else PROGRESS(0)
        handle = ctypes.c_void_p()
        message = ctypes.create_string_buffer(1024)
        status = self.lib.dev_run(pos.ctypes.data, len(pos), tri.ctypes.data, len(tri),
                                  None if pins is None else pins.ctypes.data,
                                  ctypes.byref(params), callback, None, ctypes.byref(handle),
                                  message, len(message))
        if status != 0:
            assert not handle.value, "a failed run must not return a result"
            raise EngineError(status, message.value.decode())
        try:
            return self._collect(handle, len(pos), len(tri))
        finally:
            self.lib.dev_result_free(handle)

    def _collect(self, handle, n, m):
        r = Result()
        stats = Stats()
        assert self.lib.dev_result_stats(handle, ctypes.byref(stats)) == 0
        r.stats = {name: getattr(stats, name) for name, _ in Stats._fields_}
        r.stats["stop_reason"] = STOP_REASONS[stats.stop_reason]
        r.stats["result_message"] = stats.result_message.decode("utf-8", "replace")

        def fetch(name, shape, dtype):
            out = np.zeros(shape, dtype=dtype)
            assert getattr(self.lib, "dev_result_" + name)(handle, out.ctypes.data, out.size) == 0
            return out

        r.positions = fetch("positions", (n, 3), np.float64)
        r.defect_before = fetch("defect_before", n, np.float64)
        r.defect_after = fetch("defect_after", n, np.float64)
        r.interior = fetch("interior", n, np.uint8).astype(bool)
        r.target_normals = fetch("target_normals", (m, 3), np.float64)
        r.patch_ids = fetch("patch_ids", m, np.int32)
        r.curves = []
        for c in range(self.lib.dev_result_curve_count(handle)):
            count, patch, closed = ctypes.c_int64(), ctypes.c_int32(), ctypes.c_int32()
            self.lib.dev_result_curve_info(handle, c, ctypes.byref(count), ctypes.byref(patch),
                                           ctypes.byref(closed))
            points = np.zeros((count.value, 3))
            self.lib.dev_result_curve_points(handle, c, points.ctypes.data, points.size)
            r.curves.append({"patch": patch.value, "closed": bool(closed.value), "points": points})
        return r


def load(path=None):
    return Engine(path or os.environ["DEVELOPABLE_LIBRARY"])

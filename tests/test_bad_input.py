"""Every bad input of stage 1, and every refusal of the pipeline, through the C
ABI and the command-line tool: a distinct code, a message naming the first bad
element, never a crash, never an output file."""
import json
import subprocess

import numpy as np
import pytest

import meshgen
from engine import PROGRESS

NO_PROGRESS = PROGRESS(0)

SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.2]], float)
FAN = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], np.int32)


def bowtie():
    """Two fans sharing only their centre vertex 0."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                    [-1, 0, 0.1], [-1, -1, 0.1], [0, -1, 0.1]], float)
    tri = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 5], [0, 5, 6]], np.int32)
    return pos, tri


def fin():
    """Three triangles on edge (0, 1)."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]], float)
    tri = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]], np.int32)
    return pos, tri


def with_nan():
    pos = SQUARE.copy()
    pos[2, 1] = np.nan
    return pos, FAN


def with_inf():
    pos = SQUARE.copy()
    pos[3, 0] = np.inf
    return pos, FAN


BAD_MESHES = {
    # name: (positions, triangles, status, words the message must contain)
    "no vertices": (np.zeros((0, 3)), np.zeros((0, 3), np.int32), "empty_input", "no vertices"),
    "no triangles": (SQUARE, np.zeros((0, 3), np.int32), "empty_input", "no triangles"),
    "index too large": (SQUARE, np.vstack([FAN, [[0, 1, 9]]]), "index_out_of_range",
                        "triangle 4 (0, 1, 9)"),
    "negative index": (SQUARE, np.vstack([FAN, [[0, -1, 2]]]), "index_out_of_range",
                       "vertex -1"),
    "NaN coordinate": with_nan() + ("non_finite_coordinate", "vertex 2"),
    "infinite coordinate": with_inf() + ("non_finite_coordinate", "vertex 3"),
    "repeated vertex": (SQUARE, np.vstack([FAN, [[1, 1, 2]]]), "degenerate_triangle",
                        "triangle 4 (1, 1, 2) repeats a vertex"),
    "zero area": (np.vstack([SQUARE, [[2, 0, 0]]]), np.vstack([FAN, [[0, 1, 5]]]),
                  "degenerate_triangle", "triangle 4 (0, 1, 5) has zero area"),
    "duplicate triangle": (SQUARE, np.vstack([FAN, [[4, 1, 2]]]), "duplicate_triangle",
                           "triangle 4"),
    "non-manifold edge": fin() + ("non_manifold", "edge (0, 1)"),
    "inconsistent orientation": (SQUARE, np.vstack([FAN[:1], [[2, 1, 4]], FAN[2:]]),
                                 "non_manifold", "inconsistent orientation"),
    "non-manifold vertex": bowtie() + ("non_manifold", "vertex 0 is non-manifold"),
}


@pytest.mark.parametrize("name", sorted(BAD_MESHES))
def test_bad_mesh_through_the_c_abi(engine, name):
    positions, triangles, status, words = BAD_MESHES[name]
    checked_status, message = engine.validate(positions, triangles)
    assert checked_status == status and words in message
    with pytest.raises(Exception) as error:
        engine.run(positions, triangles)
    assert error.value.status == status
    assert words in error.value.message


def test_no_interior_vertex(engine):
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.3]], float)
    tri = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    with pytest.raises(Exception) as error:
        engine.run(pos, tri)
    assert error.value.status == "no_interior_vertex"


def test_everything_pinned(engine):
    positions, triangles = meshgen.noisy_cylinder_patch()
    with pytest.raises(Exception) as error:
        engine.run(positions, triangles, pinned=np.ones(len(positions), bool))
    assert error.value.status == "no_free_vertex"
    assert "pinned" in error.value.message


@pytest.mark.parametrize("field,value", [
    ("omega", 0.0), ("omega", -1.0), ("omega", float("nan")), ("tolerance", float("inf")),
    ("max_iterations", 0), ("segmentation", 4), ("grid_resolution", 3),
    ("stop_relative_change", -1.0), ("target_patches", -2), ("segment_max_error", -1.0),
    ("target_smoothing", -2), ("target_smoothing", 101),
])
def test_parameters_out_of_range(engine, field, value):
    positions, triangles = meshgen.noisy_cylinder_patch()
    with pytest.raises(Exception) as error:
        engine.run(positions, triangles, **{field: value})
    assert error.value.status == "invalid_argument"
    assert field.split("_")[0] in error.value.message


@pytest.mark.parametrize("field,value", [("mode", 7), ("solver", 3), ("seams", 5)])
def test_enumerations_out_of_range(engine, field, value):
    import ctypes
    positions, triangles = meshgen.noisy_cylinder_patch()
    pos = np.ascontiguousarray(positions)
    tri = np.ascontiguousarray(triangles)
    params = engine.params()
    setattr(params, field, value)
    handle = ctypes.c_void_p()
    message = ctypes.create_string_buffer(256)
    status = engine.lib.dev_run(pos.ctypes.data, len(pos), tri.ctypes.data, len(tri), None,
                                ctypes.byref(params), NO_PROGRESS, None, ctypes.byref(handle),
                                message, len(message))
    assert status == 7 and not handle.value and field in message.value.decode()


def test_null_and_negative_buffers(engine):
    import ctypes
    lib = engine.lib
    message = ctypes.create_string_buffer(256)
    handle = ctypes.c_void_p()
    assert lib.dev_run(None, 3, None, 1, None, None, NO_PROGRESS, None, ctypes.byref(handle),
                       message, len(message)) == 7
    assert b"null" in message.value
    assert lib.dev_run(None, -3, None, 1, None, None, NO_PROGRESS, None, ctypes.byref(handle),
                       message, len(message)) == 7
    assert lib.dev_run(None, 3, None, 1, None, None, NO_PROGRESS, None, None, message,
                       len(message)) == 7
    # A message buffer of one byte still gets its terminating NUL, and none at all is fine.
    tiny = ctypes.create_string_buffer(b"x", 1)
    assert lib.dev_run(None, 0, None, 0, None, None, NO_PROGRESS, None, ctypes.byref(handle), tiny, 1) == 1
    assert tiny.raw == b"\0"
    assert lib.dev_run(None, 0, None, 0, None, None, NO_PROGRESS, None, ctypes.byref(handle), None, 0) == 1


def test_result_accessors_check_their_buffers(engine):
    import ctypes
    positions, triangles = meshgen.plane()
    pos, tri = np.ascontiguousarray(positions), np.ascontiguousarray(triangles)
    handle = ctypes.c_void_p()
    assert engine.lib.dev_run(pos.ctypes.data, len(pos), tri.ctypes.data, len(tri), None, None,
                              NO_PROGRESS, None, ctypes.byref(handle), None, 0) == 0
    try:
        small = np.zeros(3 * len(pos) - 1)
        assert engine.lib.dev_result_positions(handle, small.ctypes.data, small.size) == 7
        assert engine.lib.dev_result_positions(handle, None, 10 ** 6) == 7
        assert engine.lib.dev_result_curve_info(handle, 10 ** 6, None, None, None) == 7
        assert engine.lib.dev_result_curve_info(handle, -1, None, None, None) == 7
    finally:
        engine.lib.dev_result_free(handle)
    engine.lib.dev_result_free(None)


def write_bad_obj(path, positions, triangles):
    """Writes even what write_obj would refuse: NaN, negative indices."""
    with open(path, "w") as f:
        for p in positions:
            f.write("v %r %r %r\n" % tuple(float(x) for x in p))
        for t in triangles:
            f.write("f %s\n" % " ".join(str(int(i) + 1 if i >= 0 else 10 ** 6) for i in t))


@pytest.mark.parametrize("name", ["NaN coordinate", "non-manifold edge", "non-manifold vertex",
                                  "inconsistent orientation", "duplicate triangle",
                                  "repeated vertex", "zero area", "index too large",
                                  "no triangles"])
def test_bad_mesh_through_the_tool(tool_path, tmp_path, name):
    positions, triangles, status, words = BAD_MESHES[name]
    source, target, report = tmp_path / "in.obj", tmp_path / "out.obj", tmp_path / "r.json"
    write_bad_obj(source, positions, triangles)
    run = subprocess.run([str(tool_path), str(source), str(target), "--report", str(report)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2, run.stderr
    error_lines = [line for line in run.stderr.splitlines() if "error" in line]
    assert len(error_lines) == 1 and words.split(" (")[0] in error_lines[0], run.stderr
    assert not target.exists() and not report.exists()
    assert list(tmp_path.iterdir()) == [source]

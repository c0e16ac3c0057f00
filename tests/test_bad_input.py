"""Every bad input of stage 1, and every refusal of the pipeline, through the C
ABI and the command-line tool: a distinct code, a message naming the first bad
element, never a crash, never an output file."""
import ctypes
import subprocess

import numpy as np
import pytest

from devkit import meshes
from devkit.binding import native
from devkit.obj import write_obj

NO_PROGRESS = native.PROGRESS_FN(0)


def pointer(array, ctype):
    """A numpy array as the typed pointer the binding's declarations ask for."""
    return array.ctypes.data_as(ctypes.POINTER(ctype))


SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.2]], float)
FAN = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], np.int32)


def bowtie():
    """Two fans sharing only their centre vertex 0."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [-1, 0, 0.1], [-1, -1, 0.1], [0, -1, 0.1]], float)
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
    "no vertices": (np.zeros((0, 3)), np.zeros((0, 3), np.int32), "EMPTY_INPUT", "no vertices"),
    "no triangles": (SQUARE, np.zeros((0, 3), np.int32), "EMPTY_INPUT", "no triangles"),
    "index too large": (SQUARE, np.vstack([FAN, [[0, 1, 9]]]), "INDEX_OUT_OF_RANGE", "triangle 4 (0, 1, 9)"),
    "negative index": (SQUARE, np.vstack([FAN, [[0, -1, 2]]]), "INDEX_OUT_OF_RANGE", "vertex -1"),
    "NaN coordinate": with_nan() + ("NON_FINITE_COORDINATE", "vertex 2"),
    "infinite coordinate": with_inf() + ("NON_FINITE_COORDINATE", "vertex 3"),
    "repeated vertex": (
        SQUARE,
        np.vstack([FAN, [[1, 1, 2]]]),
        "DEGENERATE_TRIANGLE",
        "triangle 4 (1, 1, 2) repeats a vertex",
    ),
    "zero area": (
        np.vstack([SQUARE, [[2, 0, 0]]]),
        np.vstack([FAN, [[0, 1, 5]]]),
        "DEGENERATE_TRIANGLE",
        "triangle 4 (0, 1, 5) has zero area",
    ),
    "duplicate triangle": (SQUARE, np.vstack([FAN, [[4, 1, 2]]]), "DUPLICATE_TRIANGLE", "triangle 4"),
    "non-manifold edge": fin() + ("NON_MANIFOLD", "edge (0, 1) is shared by 3 triangles"),
    # Wound any way: still the first edge of more than two triangles, and the first bad vertex.
    "non-manifold edge, faces wound at random": (
        fin()[0],
        np.array([[0, 1, 2], [0, 1, 3], [1, 0, 4]], np.int32),
        "NON_MANIFOLD",
        "edge (0, 1) is shared by 3 triangles",
    ),
    "non-manifold vertex": bowtie() + ("NON_MANIFOLD", "vertex 0 is non-manifold"),
    "non-manifold vertex, one fan turned over": (
        bowtie()[0],
        np.array([[0, 1, 2], [0, 2, 3], [0, 5, 4], [0, 6, 5]], np.int32),
        "NON_MANIFOLD",
        "vertex 0 is non-manifold",
    ),
}


def moebius_band():
    """The smallest Möbius strip with an interior vertex: a band of four quads round a square, joined
    upside down, and a centre vertex on one quad (its faces run the join's edges the same way)."""
    pos = np.array(
        [[1, 0, -0.3], [1, 0, 0.3], [0, 1, -0.3], [0, 1, 0.3], [-1, 0, -0.3], [-1, 0, 0.3], [0, -1, -0.3], [0, -1, 0.3]]
        + [[0.5, 0.5, 0.05]],
        float,
    )
    tri = [[0, 2, 8], [2, 3, 8], [3, 1, 8], [1, 0, 8]]  # the quad (0, 2, 3, 1) round the centre vertex 8
    tri += [[2, 4, 5], [2, 5, 3], [4, 6, 7], [4, 7, 5]]  # (2, 4, 5, 3), (4, 6, 7, 5)
    tri += [[6, 1, 0], [6, 0, 7]]  # (6, 1, 0, 7): joins 6-7 to 1-0, half a twist
    return pos, np.array(tri, np.int32)


# Meshes that were refused once for "edges between faces of opposite direction": the engine turns the
# faces itself now (tests/test_one_sided.py has the figures).
WOUND_ANY_WAY = {
    # name: (positions, triangles, what dev_validate says after "ok: ")
    "inconsistent orientation": (
        SQUARE,
        np.vstack([FAN[:1], [[2, 1, 4]], FAN[2:]]),
        "1 of 4 triangles is wound the other way round from the neighbours; the run turns it over",
    ),
    "one-sided (Möbius strip)": moebius_band() + ("the surface is one-sided (like a Möbius strip)",),
}


@pytest.mark.parametrize("name", sorted(WOUND_ANY_WAY))
def test_either_winding_is_accepted(library, tool_path, tmp_path, name):
    positions, triangles, note = WOUND_ANY_WAY[name]
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    assert len(np.unique(directed, axis=0)) < len(directed)  # two faces run an edge the same way
    status, message = native.validate(positions, triangles)
    assert status == 0 and message.startswith("ok: " + note), message
    result = native.run(positions, triangles)
    assert np.isfinite(result.positions).all()
    assert result.stats["orientation_note"] == message[len("ok: ") :]  # the run says it too
    source, target = tmp_path / "in.obj", tmp_path / "out.obj"
    write_obj(source, positions, triangles)
    run = subprocess.run([str(tool_path), str(source), str(target)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and target.exists(), run.stderr
    assert "orientation" not in run.stderr and "opposite direction" not in run.stderr


@pytest.mark.parametrize("name", sorted(BAD_MESHES))
def test_bad_mesh_through_the_c_abi(library, name):
    positions, triangles, status, words = BAD_MESHES[name]
    checked_status, message = native.validate(positions, triangles)
    assert native.STATUS_NAMES[checked_status] == status and words in message
    with pytest.raises(native.EngineError) as error:
        native.run(positions, triangles)
    assert error.value.status_name == status
    assert words in error.value.message


def test_no_interior_vertex(library):
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.3]], float)
    tri = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    with pytest.raises(native.EngineError) as error:
        native.run(pos, tri)
    assert error.value.status_name == "NO_INTERIOR_VERTEX"


def test_everything_pinned(library):
    positions, triangles = meshes.noisy_cylinder_patch()
    with pytest.raises(native.EngineError) as error:
        native.run(positions, triangles, pinned=np.ones(len(positions), bool))
    assert error.value.status_name == "NO_FREE_VERTEX"
    assert "pinned" in error.value.message


@pytest.mark.parametrize(
    "field,value",
    [
        ("omega", 0.0),
        ("omega", -1.0),
        ("omega", float("nan")),
        ("tolerance", float("inf")),
        ("max_iterations", 0),
        ("segmentation", 4),
        ("grid_resolution", 3),
        ("stop_relative_change", -1.0),
        ("target_patches", -2),
        ("segment_max_error", -1.0),
        ("target_smoothing", -2),
        ("target_smoothing", 101),
    ],
)
def test_parameters_out_of_range(library, field, value):
    positions, triangles = meshes.noisy_cylinder_patch()
    with pytest.raises(native.EngineError) as error:
        native.run(positions, triangles, params={field: value})
    assert error.value.status_name == "INVALID_ARGUMENT"
    assert field.split("_")[0] in error.value.message


@pytest.mark.parametrize("field,value", [("mode", 7), ("solver", 3), ("seams", 5)])
def test_enumerations_out_of_range(library, field, value):
    positions, triangles = meshes.noisy_cylinder_patch()
    pos = np.ascontiguousarray(positions)
    tri = np.ascontiguousarray(triangles)
    params = native.make_params({})
    setattr(params.params, field, value)
    handle = ctypes.c_void_p()
    message = ctypes.create_string_buffer(256)
    status = library.dev_run(
        pointer(pos, ctypes.c_double),
        len(pos),
        pointer(tri, ctypes.c_int32),
        len(tri),
        None,
        ctypes.byref(params.params),
        NO_PROGRESS,
        None,
        ctypes.byref(handle),
        message,
        len(message),
    )
    assert status == 7 and not handle.value and field in message.value.decode()


def test_null_and_negative_buffers(library):
    lib = library
    message = ctypes.create_string_buffer(256)
    handle = ctypes.c_void_p()
    assert (
        lib.dev_run(None, 3, None, 1, None, None, NO_PROGRESS, None, ctypes.byref(handle), message, len(message)) == 7
    )
    assert b"null" in message.value
    assert (
        lib.dev_run(None, -3, None, 1, None, None, NO_PROGRESS, None, ctypes.byref(handle), message, len(message)) == 7
    )
    assert lib.dev_run(None, 3, None, 1, None, None, NO_PROGRESS, None, None, message, len(message)) == 7
    # A message buffer of one byte still gets its terminating NUL, and none at all is fine.
    tiny = ctypes.create_string_buffer(b"x", 1)
    assert lib.dev_run(None, 0, None, 0, None, None, NO_PROGRESS, None, ctypes.byref(handle), tiny, 1) == 1
    assert tiny.raw == b"\0"
    assert lib.dev_run(None, 0, None, 0, None, None, NO_PROGRESS, None, ctypes.byref(handle), None, 0) == 1


def test_result_accessors_check_their_buffers(library):
    positions, triangles = meshes.plane()
    pos, tri = np.ascontiguousarray(positions), np.ascontiguousarray(triangles)
    handle = ctypes.c_void_p()
    assert (
        library.dev_run(
            pointer(pos, ctypes.c_double),
            len(pos),
            pointer(tri, ctypes.c_int32),
            len(tri),
            None,
            None,
            NO_PROGRESS,
            None,
            ctypes.byref(handle),
            None,
            0,
        )
        == 0
    )
    try:
        small = np.zeros(3 * len(pos) - 1)
        assert library.dev_result_positions(handle, pointer(small, ctypes.c_double), small.size) == 7
        assert library.dev_result_positions(handle, None, 10**6) == 7
        assert library.dev_result_curve_info(handle, 10**6, None, None, None) == 7
        assert library.dev_result_curve_info(handle, -1, None, None, None) == 7
    finally:
        library.dev_result_free(handle)
    library.dev_result_free(None)


@pytest.mark.parametrize(
    "name",
    [
        "NaN coordinate",
        "non-manifold edge",
        "non-manifold vertex",
        "non-manifold vertex, one fan turned over",
        "duplicate triangle",
        "repeated vertex",
        "zero area",
        "index too large",
        "no triangles",
    ],
)
def test_bad_mesh_through_the_tool(tool_path, tmp_path, name):
    positions, triangles, status, words = BAD_MESHES[name]
    source, target, report = tmp_path / "in.obj", tmp_path / "out.obj", tmp_path / "r.json"
    # a negative index would be a relative one in OBJ: written past the end instead
    write_obj(source, positions, np.where(triangles < 0, 10**6 - 1, triangles))
    run = subprocess.run(
        [str(tool_path), str(source), str(target), "--report", str(report)], capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 2, run.stderr
    error_lines = [line for line in run.stderr.splitlines() if "error" in line]
    assert len(error_lines) == 1 and words.split(" (")[0] in error_lines[0], run.stderr
    assert not target.exists() and not report.exists()
    assert list(tmp_path.iterdir()) == [source]

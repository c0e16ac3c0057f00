"""Hardening (docs/hardening.md): the bad inputs test_bad_input.py does not
cover, numerical extremes, limits, cancellation, threads and the fuzz corpus,
through the C ABI and the command-line tool. Every case ends in a result that
is right or in one clear status naming the problem: never a crash, never NaN
positions, never a partial output file."""
import ctypes
import json
import os
import pathlib
import subprocess
import sys
import threading

import numpy as np
import pytest

from devkit import meshes
from devkit.binding import native
from devkit.measures import turned_faces
from devkit.obj import read_obj, write_obj

REPO = pathlib.Path(__file__).resolve().parent.parent
CORPUS = REPO / "tests" / "fuzz_corpus"
# Set by the sanitizer run (test_hardening_sanitizers.py): skip what is too
# slow under ASan or is a known engine bug the sanitizers would stop on.
SANITIZED = os.environ.get("DEVELOPABLE_SANITIZED") == "1"


# -- helpers -----------------------------------------------------------------------


def refused(positions, triangles, pinned=None, progress=None, **params):
    """(status name, message) of a run that must fail (the binding frees any
    result and raises)."""
    with pytest.raises(native.EngineError) as error:
        native.run(positions, triangles, pinned=pinned, params=params, progress=progress)
    assert error.value.message
    return error.value.status_name, error.value.message


def assert_sound(result, positions, tolerance_ae=None):
    """A result the caller may write back: finite, not worse than the input,
    within E_allow of the input."""
    s = result.stats
    assert np.isfinite(result.positions).all()
    assert np.isfinite(result.defect_after).all() and np.isfinite(result.defect_before).all()
    for key in ("mean_defect_before", "mean_defect_after", "max_vertex_move", "average_edge_length"):
        assert np.isfinite(s[key]), key
    assert s["mean_defect_after"] <= s["mean_defect_before"]
    moves = np.linalg.norm(result.positions - positions, axis=1)
    assert moves.max() == pytest.approx(s["max_vertex_move"], rel=1e-9, abs=1e-300)
    if tolerance_ae is not None and tolerance_ae > 0:
        # E_allow holds up to the rounding of the coordinates themselves
        slack = 8 * np.finfo(float).eps * np.abs(positions).max()
        assert moves.max() <= tolerance_ae * s["average_edge_length"] * (1 + 1e-9) + slack


def run_tool(tool_path, *args, env=None, timeout=300):
    return subprocess.run([str(tool_path), *map(str, args)], capture_output=True, text=True, timeout=timeout, env=env)


def tool_refuses(tool_path, tmp_path, positions, triangles, words, *args, env=None):
    """The tool exits 2 with one error line containing `words` and writes nothing."""
    source, target, report = tmp_path / "in.obj", tmp_path / "out.obj", tmp_path / "r.json"
    write_obj(source, positions, triangles)
    before = sorted(p.name for p in tmp_path.iterdir())
    run = run_tool(tool_path, source, target, "--report", report, *args, env=env)
    assert run.returncode == 2, (run.returncode, run.stderr)
    errors = [line for line in run.stderr.splitlines() if "error" in line]
    assert len(errors) == 1 and words in errors[0], run.stderr
    # nothing written, not even a partial file
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    return run


def tool_runs(tool_path, tmp_path, positions, triangles, *args):
    source, target = tmp_path / "in.obj", tmp_path / "out.obj"
    write_obj(source, positions, triangles)
    run = run_tool(tool_path, source, target, "--quiet", *args)
    assert run.returncode == 0, run.stderr
    return read_obj(target)


def one_triangle():
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.2]], float), np.array([[0, 1, 2]], np.int32)


def two_components():
    """A noisy cylinder patch and a noisy cone band, side by side, one mesh."""
    p1, t1 = meshes.noisy_cylinder_patch()
    p2, t2 = meshes.cone(rows=8, cols=32, bulge=0.08)
    p2 = meshes.add_noise(p2, 0.005, seed=3) + [5.0, 0, 0]
    return np.vstack([p1, p2]), np.vstack([t1, t2 + len(p1)]).astype(np.int32), len(p1), len(t1)


def with_isolated_vertices():
    p, t = meshes.noisy_cylinder_patch()
    loose = np.array([[9.0, 9.0, 9.0], [-3.0, 0.5, 1e3], [0.0, 0.0, 0.0]])
    # loose vertices first and last, so every index of the surface shifts by 2
    return np.vstack([loose[:2], p, loose[2:]]), (t + 2).astype(np.int32)


def polygon_soup():
    """Each triangle its own three vertices (an unwelded STL/OBJ export)."""
    p, t = meshes.noisy_cylinder_patch()
    return p[t].reshape(-1, 3), np.arange(3 * len(t), dtype=np.int32).reshape(-1, 3)


def weld(positions, triangles):
    """Exact-position welding: what 'Merge by Distance' with distance 0 does."""
    unique, inverse = np.unique(positions, axis=0, return_inverse=True)
    return unique, inverse.reshape(-1)[triangles].astype(np.int32)


# -- bad inputs not in test_bad_input.py -------------------------------------------


def test_one_triangle_has_no_interior_vertex(library):
    status, message = refused(*one_triangle())
    assert status == "NO_INTERIOR_VERTEX" and "no interior vertex" in message


def test_one_triangle_through_the_tool(tool_path, tmp_path):
    """Nothing to lower and nothing to refuse: written back as it is, with a note."""
    p, t = one_triangle()
    out_p, out_t = tool_runs(tool_path, tmp_path, p, t)
    assert np.array_equal(out_p, read_obj(tmp_path / "in.obj")[0]) and np.array_equal(out_t, t)


def test_infinite_coordinate_through_the_tool(tool_path, tmp_path):
    p, t = meshes.noisy_cylinder_patch()
    p[7, 2] = -np.inf
    tool_refuses(tool_path, tmp_path, p, t, "vertex 7 has a non-finite coordinate")


def test_negative_index_through_the_c_abi_names_the_triangle(library):
    p, t = meshes.noisy_cylinder_patch()
    t[5, 1] = -7
    status, message = refused(p, t)
    assert status == "INDEX_OUT_OF_RANGE" and "triangle 5" in message and "-7" in message


def test_index_past_the_end_through_the_tool(tool_path, tmp_path):
    p, t = meshes.noisy_cylinder_patch()
    t[3, 2] = len(p)
    tool_refuses(tool_path, tmp_path, p, t, "triangle 3")


def test_index_at_int32_limits(library):
    p, t = meshes.noisy_cylinder_patch()
    for bad in (np.iinfo(np.int32).max, np.iinfo(np.int32).min):
        t2 = t.copy()
        t2[0, 0] = bad
        status, message = refused(p, t2)
        assert status == "INDEX_OUT_OF_RANGE" and str(bad) in message


def test_zero_area_sliver_of_three_collinear_vertices(library):
    p, t = meshes.noisy_cylinder_patch()
    p = np.vstack([p, [[10, 0, 0], [11, 0, 0], [12, 0, 0]]])
    t = np.vstack([t, [[len(p) - 3, len(p) - 2, len(p) - 1]]]).astype(np.int32)
    status, message = refused(p, t)
    assert status == "DEGENERATE_TRIANGLE" and "zero area" in message


def test_repeated_triangle_with_other_orientation(library):
    p, t = meshes.noisy_cylinder_patch()
    t = np.vstack([t, t[10, ::-1]]).astype(np.int32)
    status, message = refused(p, t)
    assert status == "DUPLICATE_TRIANGLE" and "repeats the vertices of triangle 10" in message


def test_non_manifold_vertex_through_the_tool(tool_path, tmp_path):
    # two cylinder patches glued at one corner vertex
    p, t = meshes.noisy_cylinder_patch(rows=6, cols=6)
    q = p + (p[0] - p[-1])  # the copy's last vertex lands on vertex 0
    t2 = t + len(p)
    t2[t2 == 2 * len(p) - 1] = 0
    pos = np.vstack([p, q])
    tool_refuses(tool_path, tmp_path, pos, np.vstack([t, t2]), "non-manifold")


def test_non_manifold_edge_through_the_c_abi_in_a_real_mesh(library):
    p, t = meshes.noisy_cylinder_patch()
    p = np.vstack([p, [[0.0, 0.0, 5.0]]])
    # An edge of two faces gets a third (on the rim a second face, either way round, is no error).
    edges = [tuple(sorted((t[20, k], t[20, (k + 1) % 3]))) for k in range(3)]
    a, b = next(e for e in edges if sum(set(e) <= set(face) for face in t.tolist()) == 2)
    t = np.vstack([t, [[a, b, len(p) - 1]]]).astype(np.int32)
    status, message = refused(p, t)
    assert status == "NON_MANIFOLD" and ("edge (%d, %d)" % (a, b) in message or "edge (%d, %d)" % (b, a) in message)


def test_inconsistent_orientation_through_the_tool(tool_path, tmp_path):
    # No refusal any more: the engine turns the face back (tests/test_one_sided.py), the result is the
    # consistently wound twin's and the file keeps the caller's winding.
    p, t = meshes.noisy_cylinder_patch()
    flipped = t.copy()
    flipped[40] = t[40, [0, 2, 1]]
    (tmp_path / "flipped").mkdir()
    (tmp_path / "twin").mkdir()
    mine = tool_runs(tool_path, tmp_path / "flipped", p, flipped)
    twin = tool_runs(tool_path, tmp_path / "twin", p, t)
    assert np.array_equal(mine[0], twin[0]) and np.array_equal(mine[1], flipped)


def test_several_components_are_processed_together(library):
    p, t, n1, m1 = two_components()
    r = native.run(p, t)
    assert_sound(r, p, 10)
    # both components got more developable
    for vertices in (slice(0, n1), slice(n1, None)):
        inside = r.interior[vertices]
        before = np.abs(r.defect_before[vertices][inside]).mean()
        after = np.abs(r.defect_after[vertices][inside]).mean()
        assert after < 0.7 * before


def test_several_components_through_the_tool(tool_path, tmp_path):
    p, t, _, _ = two_components()
    out_p, out_t = tool_runs(tool_path, tmp_path, p, t)
    assert out_p.shape == p.shape and np.array_equal(out_t, t)
    assert np.isfinite(out_p).all()


def test_isolated_vertices_never_move(library):
    p, t = with_isolated_vertices()
    r = native.run(p, t)
    assert_sound(r, p, 10)
    loose = [0, 1, len(p) - 1]
    assert np.array_equal(r.positions[loose], p[loose])
    assert not r.interior[loose].any() and (r.defect_after[loose] == 0).all()
    # AE and the result do not depend on where the loose vertices are
    r2 = native.run(p[2:-1], t - 2)
    assert np.array_equal(r.positions[2:-1], r2.positions)


def test_isolated_vertices_through_the_tool(tool_path, tmp_path):
    p, t = with_isolated_vertices()
    out_p, out_t = tool_runs(tool_path, tmp_path, p, t)
    assert out_p.shape == p.shape and np.array_equal(out_t, t)
    assert np.array_equal(out_p[[0, 1, -1]], p[[0, 1, -1]])


def test_no_interior_vertex_through_the_tool(tool_path, tmp_path):
    """Two triangles folded along their edge: no vertex inside, so no curvature to lower;
    the tool writes them back unchanged and says why (tests/test_pattern_tool.py unfolds such
    a band). A polygon soup, also without an interior vertex, stays an error (below)."""
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.3]], float)
    t = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    write_obj(tmp_path / "in.obj", p, t)
    run = run_tool(tool_path, tmp_path / "in.obj", tmp_path / "out.obj")
    assert run.returncode == 0 and "note: Returned the input unchanged: every vertex is on the boundary" in run.stderr
    assert np.array_equal(read_obj(tmp_path / "out.obj")[0], read_obj(tmp_path / "in.obj")[0])


def test_every_vertex_pinned_through_the_tool(tool_path, tmp_path):
    p, t = meshes.noisy_cylinder_patch()
    pins = tmp_path / "pins.txt"
    pins.write_text("".join("%d\n" % v for v in range(len(p))))
    tool_refuses(tool_path, tmp_path, p, t, "pinned", "--pin", pins)
    assert pins.exists()


def test_boundary_pins_plus_interior_pins_leave_nothing_free(library):
    p, t = meshes.noisy_cylinder_patch()
    interior = np.zeros(len(p), bool)
    r = native.run(p, t, params=dict(max_iterations=1))
    interior = r.interior
    status, message = refused(p, t, pinned=interior, pin_boundary=1)
    assert status == "NO_FREE_VERTEX"


def test_any_nonzero_pin_byte_pins(library):
    p, t = meshes.noisy_cylinder_patch()
    pins = np.zeros(len(p), np.uint8)
    pins[[0, 5]] = 255  # any nonzero byte pins
    r = native.run(p, t, pinned=pins, params=dict(max_iterations=3))
    assert np.array_equal(r.positions[[0, 5]], p[[0, 5]])


# -- scale ---------------------------------------------------------------------------


def relative(result, positions):
    """The result as a fraction of the input's size, about the input's centre."""
    centre = positions.mean(0)
    size = np.linalg.norm(positions.max(0) - positions.min(0))
    return (result.positions - centre) / size


@pytest.mark.parametrize("scale", [2.0**-40, 2.0**40])
def test_power_of_two_scale_gives_the_same_result_exactly(library, scale):
    """Scaling by a power of two is exact in floating point: a scale-invariant
    engine returns the scaled result bit for bit."""
    p, t = meshes.noisy_cylinder_patch()
    r1 = native.run(p, t)
    r2 = native.run(p * scale, t)
    assert_sound(r2, p * scale, 10)
    assert r2.stats["iterations"] == r1.stats["iterations"]
    assert r2.stats["mean_defect_after"] == pytest.approx(r1.stats["mean_defect_after"], rel=1e-12)
    assert np.abs(r2.positions / scale - r1.positions).max() <= 1e-12 * np.abs(p).max()


STABLE_SETTINGS = {"refit, 5 iterations": dict(segmentation=0, max_iterations=5), "paper": dict(mode=native.MODE_PAPER)}


@pytest.mark.parametrize("settings", sorted(STABLE_SETTINGS))
@pytest.mark.parametrize("scale", [1e-12, 1e12])
def test_extreme_scale_gives_the_same_relative_result(library, scale, settings):
    """A decimal factor rounds every coordinate, which is all that separates
    the scaled run from the scaled result (the power-of-two test above shows
    the engine itself is scale-invariant). Measured gaps equal those of a
    random 1-ulp perturbation of the coordinates: 5e-9 .. 5e-5 of the mesh
    size, depending on how close a normal sits to an effect-field cell border
    (docs/hardening.md)."""
    p, t = meshes.noisy_cylinder_patch()
    kw = STABLE_SETTINGS[settings]
    r1 = native.run(p, t, params=kw)
    r2 = native.run(p * scale, t, params=kw)
    assert_sound(r2, p * scale, 10)
    assert np.abs(relative(r2, p * scale) - relative(r1, p)).max() < 1e-3
    # Within 1 %, or both far below the flat threshold, where the polish stops
    # anywhere: 2.37e-10 and 2.24e-10 rad on one machine, equal on another.
    assert r2.stats["mean_defect_after"] == pytest.approx(r1.stats["mean_defect_after"], rel=1e-2, abs=1e-8)
    assert r2.stats["average_edge_length"] == pytest.approx(r1.stats["average_edge_length"] * scale, rel=1e-12)


@pytest.mark.parametrize("scale", [1e-12, 1e12])
def test_extreme_scale_with_the_defaults(library, scale):
    """The default run (automatic segmentation, refits, stall rule) is not a
    smooth function of the input: a random 1-ulp change of the coordinates
    moves its result by 0.1-0.8 % of the mesh size (docs/hardening.md). At
    1e-12 and 1e12 it is as good as at 1, not bit-equal."""
    p, t = meshes.noisy_cylinder_patch()
    r1 = native.run(p, t)
    r2 = native.run(p * scale, t)
    assert_sound(r2, p * scale, 10)
    assert np.abs(relative(r2, p * scale) - relative(r1, p)).max() < 0.05
    assert r2.stats["mean_defect_after"] < 0.5 * r2.stats["mean_defect_before"]
    # As good: within 30 %, or both far below the flat threshold (the polish
    # stops anywhere under 1e-7 rad).
    e1, e2 = r1.stats["mean_defect_after"], r2.stats["mean_defect_after"]
    assert e2 <= max(1.3 * e1, 1e-7) and e1 <= max(1.3 * e2, 1e-7)


@pytest.mark.parametrize("scale", [1e-12, 1e12])
def test_extreme_scale_through_the_tool(tool_path, tmp_path, scale):
    p, t = meshes.noisy_cylinder_patch()
    a = tmp_path / "a"
    b = tmp_path / "b"
    a.mkdir()
    b.mkdir()
    out1, _ = tool_runs(tool_path, a, p, t, "--segmentation", "off", "--max-iterations", "5")
    out2, _ = tool_runs(tool_path, b, p * scale, t, "--segmentation", "off", "--max-iterations", "5")
    assert np.isfinite(out2).all()
    size = np.linalg.norm(p.max(0) - p.min(0))
    assert np.abs(out2 / scale - out1).max() < 1e-3 * size


def test_far_from_the_origin(library):
    """A small mesh far away: coordinates lose digits, the result stays sound."""
    p, t = meshes.noisy_cylinder_patch()
    shifted = p + 1e6
    r = native.run(shifted, t)
    assert_sound(r, shifted, 10)
    assert r.stats["mean_defect_after"] < r.stats["mean_defect_before"]


# -- polygon soup ---------------------------------------------------------------------


def test_polygon_soup_is_refused_with_a_welding_hint(library):
    p, t = polygon_soup()
    status, message = refused(p, t)
    assert status == "NO_INTERIOR_VERTEX"
    assert "share a position" in message and "weld" in message, message


def test_welded_soup_is_the_original_mesh(library):
    """What the hint asks for works: welding gives back a processable mesh."""
    p, t = polygon_soup()
    wp, wt = weld(p, t)
    r = native.run(wp, wt)
    assert_sound(r, wp, 10)
    assert r.stats["interior_vertices"] > 0


def test_polygon_soup_through_the_tool(tool_path, tmp_path):
    tool_refuses(tool_path, tmp_path, *polygon_soup(), "weld")


# -- numerical extremes -----------------------------------------------------------------


def sliver_mesh():
    """A noisy grid whose middle column is squeezed to 1e-6 of the spacing:
    needle triangles just above the degenerate threshold."""
    p, t = meshes.noisy_cylinder_patch(rows=12, cols=12)
    p = p.reshape(12, 12, 3)
    p[:, 6] = p[:, 5] + 1e-6 * (p[:, 7] - p[:, 5])
    return p.reshape(-1, 3), t


# name: settings, and what the run must end in: "sound" (assert_sound: finite,
# not worse, every vertex within E_allow), "improved" (sound and better),
# "developable" (sound with at most a tenth of the mean |defect| left),
# "unmoved" (sound, no vertex moved by more than 1e-9 AE: normal rows of
# weight ~0), or NUMERICAL_FAILURE (no result, that status and a message).
NUMERICAL = {
    "default": ({}, "developable"),
    "omega 1e12": (dict(omega=1e12), "developable"),
    # the deformation's normal rows weigh ~0, so it stays put; the polish
    # (no omega) then does all the work
    "omega 1e-12": (dict(omega=1e-12), "developable"),
    "omega 1e-12 no polish": (dict(omega=1e-12, polish=0), "unmoved"),
    # the coupled 3n x 3n matrix with normal rows 1e12 times the position rows
    # is not positive definite in double precision: refused, not a bad result
    "omega 1e12 coupled": (dict(omega=1e12, solver=native.SOLVER_COUPLED), "NUMERICAL_FAILURE"),
    "omega 1e-12 paper": (dict(omega=1e-12, mode=native.MODE_PAPER), "unmoved"),
    "tolerance 1e-9": (dict(tolerance=1e-9), "sound"),  # every vertex within 1e-9 AE
    "no tolerance": (dict(tolerance=0.0), "developable"),
    "one iteration": (dict(max_iterations=1), "improved"),
    "stop never": (dict(stop_relative_change=0.0, max_iterations=60), "developable"),
}


def assert_outcome(positions, triangles, params, expected):
    """Runs with `params` and checks that the run ends in `expected` (above)."""
    if expected == "NUMERICAL_FAILURE":
        status, message = refused(positions, triangles, **params)
        assert status == expected, message
        return None
    r = native.run(positions, triangles, params=params)
    assert_sound(r, positions, params.get("tolerance", 10.0))
    s = r.stats
    if expected == "developable":
        assert s["mean_defect_after"] <= 0.1 * s["mean_defect_before"], s
    elif expected == "unmoved":
        assert s["max_vertex_move"] <= 1e-9 * s["average_edge_length"], s
    elif expected == "improved":
        assert s["mean_defect_after"] < s["mean_defect_before"], s
    else:
        assert expected == "sound", expected
    return r


@pytest.mark.parametrize("name", sorted(NUMERICAL))
def test_numerical_extremes_end_as_stated(library, name):
    p, t = meshes.noisy_cylinder_patch()
    r = assert_outcome(p, t, *NUMERICAL[name])
    if name == "one iteration":
        assert r.stats["iterations"] == 1
    if name == "stop never":
        assert r.stats["iterations"] <= 60


# The sliver mesh ends as the plain patch does, except that its needles keep
# more curvature than a tenth: "improved" where the patch is "developable".
SLIVER = {"default": "improved", "omega 1e12": "improved", "omega 1e-12 paper": "unmoved"}


@pytest.mark.parametrize("name", sorted(SLIVER))
def test_sliver_mesh(library, name):
    p, t = sliver_mesh()
    assert native.validate(p, t)[0] == native.STATUS_OK
    assert_outcome(p, t, NUMERICAL[name][0], SLIVER[name])


@pytest.mark.parametrize("name", ["default", "omega 1e12", "no tolerance"])
def test_no_triangle_flips(library, name):
    """The result keeps every face's orientation (a flipped face is a fold)."""
    p, t = meshes.noisy_cylinder_patch()
    r = native.run(p, t, params=NUMERICAL[name][0])
    assert (turned_faces(p, r.positions, t) < 0).sum() == 0


def test_sliver_mesh_no_triangle_flips(library):
    p, t = sliver_mesh()
    r = native.run(p, t)
    assert (turned_faces(p, r.positions, t) < 0).sum() == 0


def test_pinned_everything_but_one_vertex(library):
    """One free vertex: the run ends in a sound result that moved only it."""
    p, t = meshes.noisy_cylinder_patch()
    r0 = native.run(p, t, params=dict(max_iterations=1))
    free = int(np.flatnonzero(r0.interior)[len(p) // 4])
    pins = np.ones(len(p), bool)
    pins[free] = False
    r = native.run(p, t, pinned=pins)
    assert_sound(r, p, 10)
    others = np.arange(len(p)) != free
    assert np.array_equal(r.positions[others], p[others])


# -- limits: memory budget ----------------------------------------------------------------


@pytest.fixture
def small_budget(monkeypatch):
    monkeypatch.setenv("DEVELOPABLE_MEMORY_BUDGET_MB", "64")


def test_over_the_budget_is_refused_before_anything_is_allocated(library, small_budget):
    p, t = meshes.noisy_grid(400_000)
    stages = []
    status, message = refused(p, t, progress=lambda fraction, stage: stages.append(stage) or True)
    assert set(stages) <= {"checking input"}, stages  # refused before any stage began
    assert status == "OUT_OF_MEMORY"
    assert "memory budget" in message and "GiB" in message and "DEVELOPABLE_MEMORY_BUDGET_MB" in message


def test_the_coupled_solver_is_refused_sooner(library, monkeypatch):
    p, t = meshes.noisy_grid(100_000)
    monkeypatch.setenv("DEVELOPABLE_MEMORY_BUDGET_MB", "600")
    status, message = refused(p, t, solver=native.SOLVER_COUPLED)
    assert status == "OUT_OF_MEMORY" and "decoupled" in message
    if SANITIZED:
        return  # the run that fits polishes 100k faces: minutes under ASan, seconds here
    r = native.run(p, t, params=dict(solver=native.SOLVER_DECOUPLED, max_iterations=1))  # fits
    assert_sound(r, p, 10)


def test_budget_through_the_tool(tool_path, tmp_path):
    p, t = meshes.noisy_grid(200_000)
    env = dict(os.environ, DEVELOPABLE_MEMORY_BUDGET_MB="32")
    tool_refuses(tool_path, tmp_path, p, t, "memory budget", env=env)


def test_counts_near_the_int32_limit_are_refused_without_reading(library):
    """Counts the caller claims are checked before the buffers are read."""
    message = ctypes.create_string_buffer(512)
    handle = ctypes.c_void_p()
    one = np.zeros(3)
    tri = np.zeros(3, np.int32)
    status = library.dev_run(
        one.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
        2**31 + 1,
        tri.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)),
        1,
        None,
        None,
        native.PROGRESS_FN(0),
        None,
        ctypes.byref(handle),
        message,
        len(message),
    )
    assert native.STATUS_NAMES[status] == "INVALID_ARGUMENT" and b"2^31" in message.value
    assert not handle.value


TWO_MILLION = r"""
import json, resource, sys, time
sys.path.insert(0, %(repo)r)
import numpy as np
from devkit import meshes
from devkit.binding import native
p, t = meshes.noisy_grid(2_000_000)
native.load(path=%(lib)r)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
start = time.perf_counter()
try:
    r = native.run(p, t, params=dict(max_iterations=1, segmentation=0, polish=%(polish)d))
    out = {"status": "OK", "finite": bool(np.isfinite(r.positions).all()),
           "better": r.stats["mean_defect_after"] <= r.stats["mean_defect_before"]}
except native.EngineError as error:
    out = {"status": error.status_name, "message": error.message}
out.update(faces=len(t), vertices=len(p), seconds=time.perf_counter() - start,
           peak_mib=(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024)
print("RESULT " + json.dumps(out))
"""


@pytest.mark.skipif(SANITIZED, reason="2M faces under ASan: minutes; the normal build covers it")
def test_two_million_faces_work_or_are_refused_cleanly(library_path, tmp_path):
    """One iteration, no polish: a polish of raw noise on 2M faces takes minutes
    (its memory is in the estimate all the same; the next test runs it)."""
    script = tmp_path / "two_million.py"
    script.write_text(TWO_MILLION % {"repo": str(REPO), "lib": str(library_path), "polish": 0})
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=1200)
    assert run.returncode == 0, run.stderr[-3000:]
    line = [x for x in run.stdout.splitlines() if x.startswith("RESULT ")][-1]
    out = json.loads(line[len("RESULT ") :])
    print(out)
    assert out["faces"] >= 2_000_000
    if out["status"] == "OK":
        assert out["finite"] and out["better"]
        # the estimate behind the budget is above what the run really took
        assert out["peak_mib"] < 2_000_000 * 900 / 2**20 + 400
    else:
        assert out["status"] == "OUT_OF_MEMORY" and "memory budget" in out["message"]


# -- cancellation --------------------------------------------------------------------------


def progress_reports(p, t, **params):
    stages = []
    native.run(p, t, progress=lambda f, s: stages.append((f, s)) or True, params=params)
    return stages


def test_cancel_at_every_stage(library):
    """Cancelling at any report ends in cancelled, no result, and the next run
    on the same data gives the same result as one never cancelled. The count
    of the last reports may differ between runs (least motion's polish of the
    input gives up when the polish beside it ends, concurrent_jobs.h): a run
    that ends before its k-th report is a whole one."""
    p, t = two_components()[:2]
    p_before = p.copy()
    reports = progress_reports(p, t, segmentation=1)
    stages = sorted({s for _, s in reports})
    assert {"checking input", "ideal curve", "deformation"} <= set(stages), stages
    fractions = [f for f, _ in reports]
    assert fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] <= 1
    reference = native.run(p, t, params=dict(segmentation=1))
    # every stage's first report, plus a spread of the others
    picks = sorted(
        {next(i for i, (_, s) in enumerate(reports) if s == stage) for stage in stages}
        | set(range(0, len(reports), max(1, len(reports) // 8)))
    )
    for k in picks:
        seen = []

        def cancel_after_k(fraction, stage, k=k):
            seen.append(stage)
            return len(seen) <= k

        try:
            whole = native.run(p, t, params=dict(segmentation=1), progress=cancel_after_k)
        except native.EngineError as error:
            assert error.status_name == "CANCELLED"
            assert "cancelled during " + seen[k] in error.message
            assert len(seen) == k + 1  # no report after the one that said stop
        else:
            # only the polish's reports vary in count
            assert len(seen) <= k and reports[k][1] == "polish", (k, len(seen), reports[k])
            assert np.array_equal(whole.positions, reference.positions)
    assert np.array_equal(p, p_before)  # the input buffer is only read
    again = native.run(p, t, params=dict(segmentation=1))
    assert np.array_equal(again.positions, reference.positions)


# -- threads ----------------------------------------------------------------------------------


def test_two_runs_at_the_same_time_equal_two_runs_in_turn(library):
    """Python threads through ctypes (the GIL is released in dev_run): the
    engine has no global state, so concurrent runs give bit-identical results."""
    inputs = [meshes.noisy_cylinder_patch(), meshes.curved_cone(), two_components()[:2]]
    settings = [dict(), dict(solver=native.SOLVER_COUPLED, max_iterations=10), dict(segmentation=1)]
    sequential = [native.run(p, t, params=kw).positions for (p, t), kw in zip(inputs, settings)]
    for round_ in range(2):
        results = [None] * len(inputs)
        errors = []

        def work(i):
            try:
                p, t = inputs[i]
                # one with a progress callback: it takes the GIL from a worker thread
                progress = (lambda f, s: True) if i == 0 else None
                results[i] = native.run(p, t, progress=progress, params=settings[i]).positions
            except Exception as error:  # pragma: no cover - reported below
                errors.append(error)

        threads = [threading.Thread(target=work, args=(i,)) for i in range(len(inputs))]
        for th in threads:
            th.start()
        for th in threads:
            th.join(600)
        assert not errors, errors
        for i, positions in enumerate(results):
            assert np.array_equal(positions, sequential[i]), (round_, i)


def test_same_mesh_on_two_threads(library):
    p, t = meshes.curved_cone()
    reference = native.run(p, t).positions
    out = [None, None]

    def work(i):
        out[i] = native.run(p, t).positions

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(600)
    assert np.array_equal(out[0], reference) and np.array_equal(out[1], reference)


# -- fuzz corpus replay ------------------------------------------------------------------------


@pytest.fixture(scope="session")
def corpus_replayer(build_dir):
    """bin/fuzz_replay: the fuzz target's LLVMFuzzerTestOneInput with a plain
    main() (no libFuzzer), linked against the library of the build under test,
    so the corpus replays on the Release and on the ASan/UBSan build alike."""
    path = build_dir / "bin" / "fuzz_replay"
    if not path.exists():
        pytest.skip("no fuzz_replay in the build (clang's FuzzedDataProvider.h not found)")
    return path


def test_fuzz_corpus_replays_cleanly(corpus_replayer):
    files = sorted(p for p in CORPUS.iterdir() if p.is_file()) if CORPUS.is_dir() else []
    assert files, "tests/fuzz_corpus is empty"
    run = subprocess.run([str(corpus_replayer)] + [str(f) for f in files], capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-4000:]
    assert "replayed %d" % len(files) in run.stdout

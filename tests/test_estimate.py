"""The panel's time estimate (addon/core/estimate.py, no bpy): its measured block is the fit of the
runs bench/scans.py recorded (bench/scans.json), every recorded run of the sizes the panel estimates
falls in its range, closed meshes are told from open ones by their counts alone, and the other
settings keep their stage model."""
import json
import pathlib

import numpy as np
import pytest

from addon.core import estimate
from devkit import families, objects

SCANS = pathlib.Path(__file__).resolve().parents[1] / "bench" / "scans.json"
DEFAULTS = dict(mode="REFIT", solver="DECOUPLED", segmentation="AUTO", fixed_patches=0, max_iterations=400)


def recorded_runs():
    return json.loads(SCANS.read_text())["rows"]


@pytest.mark.parametrize(
    "run",
    [r for r in recorded_runs() if r["size"] >= estimate.LARGE_MESH_FACES],
    ids=lambda r: "%s-%d" % (r["name"].replace(" ", "_"), r["faces"]),
)
def test_every_recorded_large_run_falls_in_its_range(run):
    closed = run["kind"] == "object"
    shortest, longest = estimate.expected_seconds(run["faces"], closed, polish="AUTO", **DEFAULTS)
    # The block holds three significant digits.
    assert shortest * 0.99 <= run["wall_s"] <= longest * 1.01, (shortest, run["wall_s"], longest)


def test_measured_block_is_the_fit_of_the_recorded_runs():
    import bench.scans as scans  # noqa: the benchmark's own fit, not a copy of it

    fits = scans.panel_estimate(recorded_runs())
    for kind in ("sheet", "object"):
        for key, value in fits[kind].items():
            assert estimate.MEASURED[kind][key] == pytest.approx(value, rel=5e-3), (kind, key)


def counts(triangles):
    """(edges, loops) of a triangle mesh as Blender counts them."""
    pairs = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    return len(np.unique(pairs, axis=0)), 3 * len(triangles)


def boundary_of(triangles):
    pairs = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    _, times = np.unique(pairs, axis=0, return_counts=True)
    return int((times == 1).sum())


@pytest.mark.parametrize("seed", [100, 101])
def test_closed_and_open_meshes_told_apart_by_their_counts(seed):
    for kind in ("blob", "rounded_box", "torus", "limb"):
        m = objects.random_case(kind, seed)
        assert estimate.boundary_edges(*counts(m.triangles)) == 0, kind
    for family in ("cylinder_patch", "cone_band", "bent_sheet"):
        m = families.make(family, "irregular", faces=2000, noise=0.02, seed=seed)
        b = estimate.boundary_edges(*counts(m.triangles))
        assert b == boundary_of(m.triangles) > 0, family


def test_objects_are_estimated_longer_than_sheets_and_grow_with_the_faces():
    for faces in (100_000, 1_000_000):
        sheet = estimate.expected_seconds(faces, False, polish="AUTO", **DEFAULTS)
        whole = estimate.expected_seconds(faces, True, polish="AUTO", **DEFAULTS)
        assert sheet[0] < sheet[1] and whole[0] <= whole[1]
        assert whole[0] > sheet[0] and whole[1] > sheet[1]
    small = estimate.expected_seconds(100_000, True, polish="AUTO", **DEFAULTS)
    large = estimate.expected_seconds(1_000_000, True, polish="AUTO", **DEFAULTS)
    assert large[0] > 5 * small[0]


def test_other_settings_keep_the_stage_model():
    faces = 500_000
    default = estimate.expected_seconds(faces, False, polish="AUTO", **DEFAULTS)
    no_polish = estimate.expected_seconds(faces, False, polish="OFF", **DEFAULTS)
    assert no_polish[0] < default[0]
    paper = estimate.expected_seconds(faces, False, polish="AUTO", **dict(DEFAULTS, mode="PAPER"))
    assert paper[0] == paper[1] > 0
    one_patch = estimate.expected_seconds(faces, False, polish="AUTO", **dict(DEFAULTS, segmentation="OFF"))
    split = estimate.expected_seconds(faces, False, polish="AUTO", **dict(DEFAULTS, segmentation="ON"))
    assert one_patch[0] == one_patch[1] < split[0] == split[1]
    few = estimate.expected_seconds(faces, False, polish="AUTO", **dict(DEFAULTS, max_iterations=10))
    assert few[1] < split[1]

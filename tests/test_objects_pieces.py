"""Whole objects made developable as ruled pieces, not flat by zigzags (issue 35): where the
thinned-pieces generator (native/pipeline/thinned_pieces.h; docs/segmentation.md, "Thinned
pieces") wins under the one rule, the result is flat *and ruled* (the faces around each vertex
bend about one line) on far more vertices than today's default gave, and hardly more crumpled
(flat but not ruled) than the input. Shares over all interior vertices, seams included.

Bounds: bunny today 44.7 % flat and ruled (22.5 % crumpled), with the generator 68.3 % (0.7 %);
the torus 11.4 -> 62.2 %. Held-out objects (devkit/objects.py; the generator's constants came from
the prototype on the shared meshes, not from these seeds): blob 100 37.2 -> 59.7 %, blob 105
26.5 -> 53.7 %, limb 100 14.9 -> 54.9 % (2026-12-04). Spot and the sphere since the order ranks
closed meshes by their flat-and-ruled share (2026-12-05); human_woman in test_segmentation.py."""
import numpy as np
import pytest

from devkit import objects
from devkit.binding import native
from devkit.distance import bbox_diagonal, sampled_hausdorff
from devkit.measures import developability_figures, seam_vertices, turned_faces
from devkit.obj import read_obj
from result_support import check_honest

ORIGIN_THINNED_PIECES = 8  # DEV_ORIGIN_THINNED_PIECES
CRUMPLE_SLACK = 0.03  # kCrumpleSlack (selection.h)

# (case, lowest flat-and-ruled share over all interior vertices); today's default in the docstring.
CASES = [
    ("shared:bunny", 0.60),
    ("shared:torus", 0.50),
    ("object:blob:100", 0.50),
    ("object:blob:105", 0.45),
    ("object:limb:100", 0.45),
    # Ranked by the flat-and-ruled share on closed meshes (selection.h, more_developable), the
    # flat-by-zigzag results give way: spot 21.4 -> 42.5 % (53.7 % flat, 32 % crumpled before),
    # the sphere 35.5 -> 52.5 %.
    ("shared:spot_low_resolution", 0.35),
    ("shared:sphere", 0.45),
    # An open object (its curvature sums to 6.2 rad, selection.h is_object): 28.5 -> 42.7 %, crumpled
    # 22.3 -> 0.6 %.
    ("shared:hand_lowres", 0.38),
    # Held to the mean |defect| inside their pieces (selection.h, admit), the thinned pieces are no
    # longer refused for gathering the curvature on their seams (2026-12-06; designed on seeds
    # 100-105, these held out): penguin 2.9 -> 57.9 %, wingnut 76.8 -> 83.7 %, torus 108 6.6 ->
    # 70.8 %, rounded box 108 25.9 -> 68.0 %, each returned unchanged before.
    ("shared:penguin", 0.5),
    # 76.8 -> 83.7 %: its boss a shallow cone, its wing tips polygons (docs/segmentation.md).
    ("shared:wingnut", 0.8),
    ("object:torus:108", 0.6),
    ("object:rounded_box:108", 0.55),
]


@pytest.fixture(scope="module", autouse=True)
def _library(library):
    """Every test here runs the engine of the build under test."""


def mesh_of(case, meshes_dir):
    parts = case.split(":")
    if parts[0] == "shared":
        return read_obj(meshes_dir / (parts[1] + ".obj"))
    m = objects.random_case(parts[1], int(parts[2]))
    return m.positions, m.triangles


@pytest.mark.parametrize("case, lowest", CASES)
def test_objects_come_back_as_ruled_pieces(case, lowest, meshes_dir):
    positions, triangles = mesh_of(case, meshes_dir)
    r = native.run(positions, triangles)
    check_honest(positions, triangles, r)
    s = r.stats
    assert s["result_origin"] == ORIGIN_THINNED_PIECES, (case, s["result_origin"], s["result_message"])
    before = developability_figures(positions, triangles)
    after = developability_figures(r.positions, triangles)
    assert after["flat_and_ruled"] >= lowest, (case, after)
    assert after["crumpled"] <= before["crumpled"] + CRUMPLE_SLACK, (case, before, after)
    assert (turned_faces(positions, r.positions, triangles) > 0).all(), case
    assert sampled_hausdorff(r.positions, triangles, positions, triangles) <= 0.01 * bbox_diagonal(positions) * (
        1 + 1e-6
    )
    assert s["patches"] == len(np.unique(r.patch_ids)) > 1


# Open objects (devkit/objects.py open_case: a seeded object cut by a random plane; nothing was
# tuned on them): each wraps around something (its curvature sums to 4.4-9.3 rad, selection.h
# is_object), so it is planned and ordered as a closed one. Measured 2026-12-05 (flat and ruled
# before -> after): blobs 100-103 3.9 -> 66.7, 3.5 -> 60.5, 50.9 -> 90.8, 1.9 -> 53.5 %; limbs
# 2.3 -> 54.8, 12.7 -> 74.8, 26.6 -> 85.4, 4.9 -> 67.7 % (before the object rule: 35-66 %, with up
# to 26 % crumpled). Limb 101 kept its segmented run's nearly flat polish on some processors, 3.6 %
# crumpled against the input's 0.3 %; since a crumpled alternative of an object takes part only
# where every one is (selection.h, crumpled) its thinned pieces come back, 74.8 % with 0.3 %.
OPEN_CASES = [(kind, seed) for kind in ("blob", "limb") for seed in (100, 101, 102, 103)]


@pytest.mark.parametrize("kind, seed", OPEN_CASES)
def test_open_objects_come_back_flat_and_ruled(kind, seed):
    m = objects.open_case(kind, seed)
    r = native.run(m.positions, m.triangles)
    check_honest(m.positions, m.triangles, r)
    before = developability_figures(m.positions, m.triangles)
    after = developability_figures(r.positions, m.triangles)
    assert after["flat_and_ruled"] >= before["flat_and_ruled"] + 0.25, (kind, seed, before, after)
    assert after["crumpled"] <= before["crumpled"] + CRUMPLE_SLACK, (kind, seed, before, after)
    assert sampled_hausdorff(r.positions, m.triangles, m.positions, m.triangles) <= 0.01 * bbox_diagonal(
        m.positions
    ) * (1 + 1e-6)


# Inside the pieces (interior vertices off every seam: issue 35's measure). A piece still curved
# inside after the ruled polish is split in two and settled again (thinned_pieces.h, stage 5;
# docs/segmentation.md, "Pieces still curved inside"; chosen on seeds 0-9, these not tuned on).
# Measured 2026-12-07 on an AMD EPYC, before -> after the split: blob 103 66.9 -> 71.4 %, blob 104
# 74.0 -> 79.2, rounded box 101 62.5 -> 78.6, rounded box 109 75.4 -> 80.8, limb 104 67.2 -> 75.2
# (median 67.2 -> 78.6 %), in 9-22 pieces.
INSIDE_CASES = [("blob", 103), ("blob", 104), ("rounded_box", 101), ("rounded_box", 109), ("limb", 104)]


def test_pieces_are_flat_and_ruled_inside():
    shares = []
    for kind, seed in INSIDE_CASES:
        m = objects.random_case(kind, seed)
        r = native.run(m.positions, m.triangles)
        check_honest(m.positions, m.triangles, r)
        off_seams = ~seam_vertices(len(m.positions), m.triangles, np.asarray(r.patch_ids))
        inside = developability_figures(r.positions, m.triangles, interior=off_seams)
        shares.append(inside["flat_and_ruled"])
        assert inside["flat_and_ruled"] >= 0.68, (kind, seed, inside)
        assert r.stats["patches"] <= 40, (kind, seed, r.stats["patches"])
    assert np.median(shares) >= 0.75, shares

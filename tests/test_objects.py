"""Seeded random whole objects (devkit/objects.py: blobs, rounded boxes, tori and
limbs, 1k-20k faces, modelled or with scan noise) through the engine's defaults,
on seeds 100-105 (0-9 were looked at while writing the generator). What issue 11
asks of whole objects holds on shapes nobody tuned for, not only on the eleven of
../shared/meshes:
  - no face turned over; inside a patch no edge's angle grown by more than the
    crease guard's 20 degrees (90 on one patch); seams may fold;
  - the mean |defect| inside the pieces grown by at most 5 % (on the seams the
    curvature may gather, and a growth of the mean over every vertex is said);
    the flat share never lower;
  - within 1.5 % of the bounding box diagonal (Hausdorff) of the input;
  - the input returned bit for bit, with its reason, when nothing honest was found;
  - a closed mesh is always split into patches (one closed patch cannot be made
    developable: its curvature sums to 4 pi on a sphere-like one), and split
    twice as finely when the automatic count found nothing, which the message
    then says;
  - and every kind improves on some seed, so that returning everything unchanged
    cannot pass.
"""
import numpy as np
import pytest

from devkit import objects
from devkit.binding import native
from devkit.distance import bbox_diagonal, sampled_hausdorff
from devkit.measures import angle_defects, sharpened_edges
from devkit.obj import read_obj
from result_support import check_honest

SEEDS = range(100, 106)


@pytest.fixture(scope="module", autouse=True)
def _library(library):
    """Every test here runs the engine of the build under test."""


@pytest.mark.parametrize("kind", objects.KINDS)
def test_the_generator_is_seeded_closed_and_outward(kind):
    a, b = objects.random_case(kind, 3), objects.random_case(kind, 3)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.triangles, b.triangles)
    assert not np.array_equal(a.positions, objects.random_case(kind, 4).positions)
    for seed in (1, 2):  # one noisy, one modelled
        m = objects.random_case(kind, seed)
        t = m.triangles
        assert 1000 <= len(t) <= 21000
        # Closed and consistently oriented: every directed edge once, its twin once.
        directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
        assert len(np.unique(directed, axis=0)) == len(directed)
        assert len(np.unique(np.sort(directed, axis=1), axis=0)) * 2 == len(directed)
        _, interior = angle_defects(m.positions, t)
        assert interior.all()
        # Outward: positive enclosed volume.
        p = m.positions[t]
        assert np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() > 0
        assert np.abs(m.positions - m.clean).max() <= m.noise * m.info["ae"] * (1 + 1e-12)
    assert objects.random_case(kind, 2).noise == 0.0 and objects.random_case(kind, 1).noise > 0.0


@pytest.fixture(scope="module")
def runs():
    out = {}
    for kind in objects.KINDS:
        for seed in SEEDS:
            m = objects.random_case(kind, seed)
            out[(kind, seed)] = (m, native.run(m.positions, m.triangles))
    return out


@pytest.mark.parametrize("kind", objects.KINDS)
def test_whole_objects_come_back_honest_and_in_shape(runs, kind):
    improved = 0
    for seed in SEEDS:
        m, r = runs[(kind, seed)]
        s = r.stats
        where = "%s seed %d (%d faces, noise %.3f AE)" % (kind, seed, len(m.triangles), m.noise)
        check_honest(m.positions, m.triangles, r)
        assert s["patches"] > 1, where
        creased = sharpened_edges(
            m.positions, r.positions, m.triangles, patch_ids=r.patch_ids, growth_degrees=20.0 + 1e-6
        )
        assert len(creased) == 0, (where, len(creased))
        distance = sampled_hausdorff(r.positions, m.triangles, m.positions, m.triangles)
        assert distance <= 0.015 * bbox_diagonal(m.positions), where
        improved += s["result"] == native.RESULT_IMPROVED
        if s["unchanged_reason"] in (
            native.UNCHANGED_REJECTED,
            native.UNCHANGED_NO_BETTER_ITERATE,
            native.UNCHANGED_NO_VISIBLE_GAIN,
        ):
            assert (
                "also when split twice as finely" in s["result_message"]
                or "Split twice as finely" in s["result_message"]
            ), (where, s["result_message"])
    assert improved >= 1, kind


def test_penguin_comes_back_in_pieces_flat_and_ruled_inside(meshes_dir):
    """Penguin's segmented runs, at the automatic count (34 patches) and split
    twice as finely, are refused (every better iterate raised the mean |defect|
    by more than 5 %, or creased a patch). Its thinned pieces gather the
    curvature on their seams: inside them the mean |defect| falls by about 85 %,
    over every vertex it grows by about 8 %, which the message says. They come
    back (about 58 % of the vertices flat and ruled, 3 % before), not crumpled."""
    positions, triangles = read_obj(meshes_dir / "penguin.obj")
    r = native.run(positions, triangles)
    check_honest(positions, triangles, r)
    s = r.stats
    assert s["result"] == native.RESULT_IMPROVED and native.ORIGIN_NAMES[s["result_origin"]] == "thinned_pieces"
    assert s["ruled_share_after"] >= 0.5 and s["ruled_share_before"] < 0.05
    assert s["crumpled_share_after"] <= s["crumpled_share_before"] + 0.03
    assert s["mean_defect_after"] > s["mean_defect_before"]
    assert "mean |defect| grew" in s["result_message"]


def test_a_limb_the_automatic_split_left_unchanged_is_split_finer(runs):
    """Seed 101's limb came back unchanged at the automatic count (21 patches:
    every better iterate raised the mean |defect| by more than 5 %); split
    twice as finely it ends about 75 % flat (from 13 %)."""
    _, r = runs[("limb", 101)]
    assert r.stats["result"] == native.RESULT_IMPROVED and r.stats["flat_share_after"] >= 0.5

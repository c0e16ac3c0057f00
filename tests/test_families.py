"""Seeded random developables of every family of issue 11 (devkit/families.py)
through the engine's defaults, on seeds no one tuned on (100-104; the tuning
seeds are 0-9).

Every run, whatever the family: no face turned over, mean |defect| and the
flat share no worse than the input's, the input returned as is when the
result says unchanged. Per family, the bounds the engine meets today
(docs/families.md has the table; the issue's goals are stricter, see the
report there): the median dE over the seeds, the lowest flat share, and the
largest Hausdorff distance to the noise-free twin over the input's.
"""
import os
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "addon"))
from devkit import families  # noqa: E402
from devkit.distance import sampled_hausdorff  # noqa: E402
import native  # noqa: E402

SEEDS = range(100, 105)


@pytest.fixture(scope="module", autouse=True)
def _library(library_path):
    os.environ[native.ENV_VAR] = str(library_path)
    native.load(force_reload=True)


angle_defects = families.angle_defects
face_normals = families.face_normals


# -- the generator ------------------------------------------------------------------------

@pytest.mark.parametrize("family", families.FAMILIES)
def test_the_generator_is_seeded_and_its_twins_are_developable(family):
    a = families.random_case(family, 3)
    b = families.random_case(family, 3)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.triangles, b.triangles)
    assert not np.array_equal(a.positions, families.random_case(family, 4).positions)
    for triangulation in ("grid", "alternating", "slivers"):
        m = families.make(family, triangulation, faces=1500, noise=0.03, seed=1)
        assert 1000 <= len(m.triangles) <= 2000
        defects, interior = angle_defects(m.clean, m.triangles)
        noisy, _ = angle_defects(m.positions, m.triangles)
        # An exact developable sampled on a grid. A tangent developable's grid
        # quads join consecutive rulings, which are skew: a little defect is
        # left there, far below the noise's.
        if family.startswith("tangent_"):
            assert np.abs(defects[interior]).mean() < 0.05 * np.abs(noisy[interior]).mean()
        else:
            assert np.abs(defects[interior]).mean() < 1e-9, triangulation
        move = np.abs(m.positions - m.clean).max()
        assert 0.5 * 0.03 * m.info["ae"] < move <= 0.03 * m.info["ae"] * (1 + 1e-12)


def test_curved_folds_refuse_irregular_triangulations():
    with pytest.raises(ValueError):
        families.make("curved_fold", "irregular")


# -- the engine on them -------------------------------------------------------------------

# family -> (median dE % at most, lowest flat share at least, largest H/H0 at most),
# measured on this commit over seeds 100-104 (docs/families.md); None: not bounded yet.
BOUNDS = {
    "cylinder_patch": (-88.0, 0.45, 14.0),
    "cylinder_band": (-90.0, 0.25, 1.5),
    "cone_patch": (-90.0, 0.75, 16.0),
    "cone_band": (-88.0, 0.9, 2.7),
    "tangent_helix": (-50.0, 0.05, 8.0),
    "tangent_cubic": (-55.0, 0.2, 5.0),
    "tangent_random": (-8.0, None, 44.0),
    "generalized_cylinder": (-50.0, 0.4, 12.0),
    "generalized_cone": (-88.0, 0.25, 13.0),
    "bent_sheet": (-92.0, 0.7, 10.0),
    "curved_fold": (-55.0, 0.6, 4.5),
    "plane": (-99.9, 0.99, 1.0),
}


@pytest.mark.parametrize("family", families.FAMILIES)
def test_engine_on_family(family):
    changes, flats, ratios = [], [], []
    for seed in SEEDS:
        m = families.random_case(family, seed)
        r = native.run(m.positions, m.triangles)
        s = r.stats
        where = "%s seed %d (%s, %d faces, noise %.3f AE)" % (family, seed, m.triangulation,
                                                               len(m.triangles), m.noise)
        turned = np.einsum("ij,ij->i", face_normals(m.positions, m.triangles),
                           face_normals(r.positions, m.triangles)) < 0
        assert not turned.any() and s["faces_turned_over"] == 0, where
        assert s["mean_defect_after"] <= s["mean_defect_before"], where
        assert s["flat_share_after"] >= s["flat_share_before"], where
        if s["result"] == native.RESULT_UNCHANGED:
            assert np.array_equal(r.positions, m.positions) and s["result_message"], where
        changes.append(s["change_percent"])
        flats.append(s["flat_share_after"])
        h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
        ratios.append(sampled_hausdorff(r.positions, m.triangles, m.clean, m.triangles) / h0)
    change, flat, ratio = BOUNDS[family]
    if change is not None:
        assert np.median(changes) <= change, (family, changes)
    if flat is not None:
        assert min(flats) >= flat, (family, flats)
    if ratio is not None:
        assert max(ratios) <= ratio, (family, ratios)

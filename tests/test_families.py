"""Seeded random developables of every family of issue 11 (devkit/families.py)
through the engine's defaults, on seeds no one tuned on (100-102 for every
family and triangulation; the tuning seeds are 0-9).

Every run, whatever the family: no face turned over, no edge folded (its
angle grown by more than 90 degrees), mean |defect| and the flat share no
worse than the input's, the input returned as is when the
result says unchanged. Then the issue's bounds where the engine meets them
(docs/families.md has the whole table and says where it does not):
  - grids (one diagonal or alternating), every family but curved folds:
    each run's mean |defect| down at least 98 % (their median at least
    99 %), at least 95 % of the interior vertices flat (|defect| < 1e-3 rad);
  - and, on grids, the Hausdorff distance to the noise-free twin at most
    1.5 times the input's (the noise removed, not the shape changed), every
    family but curved folds (random-curve tangent developables too since
    least motion's projected candidate, docs/method.md);
  - curved folds: at least 95 % flat and the mean down at least 90 %;
  - irregular triangulations (jittered Delaunay), every family: the mean
    down at least 95 %; and for cone patches, tangent developables of
    helices and twisted cubics, and planes, the same distance bound.
The Hausdorff ratio of the other families is above the issue's 1.5 on some
seeds (curved folds: 1.52 on an alternating grid, and single seeds of
cylinder patches and bands, cone bands and bent sheets on irregular
triangulations, more on the irregular wavy ones). On irregular triangulations that is what the triangles force: the
noise-free twin run through the engine moves about as far, and every
family's irregular runs are held to 1.5 times the larger of the noise and
that move;
each family's median is held to today's with room, so that a change that
moves the shape more fails here.
"""
import os

import numpy as np
import pytest

from devkit import families
from devkit.binding import native
from devkit.distance import TriangleGrid, sampled_hausdorff, samples
from devkit.measures import developability_figures, sharpened_edges

SEEDS = range(100, 103)
GRIDS = ("grid", "alternating")
SHAPE_KEPT = [f for f in families.FAMILIES if f != "curved_fold"]
SHAPE_KEPT_IRREGULAR = ("cone_patch", "tangent_helix", "tangent_cubic", "plane")
# family -> the largest median Hausdorff ratio accepted: today's median
# (docs/families.md) times 1.5, at least 1.5.
MEDIAN_RATIO = {
    "cylinder_patch": 1.5,
    "cylinder_band": 1.5,
    "cone_patch": 1.5,
    "cone_band": 1.5,
    "tangent_helix": 1.5,
    "tangent_cubic": 1.5,
    "tangent_random": 1.6,
    "generalized_cylinder": 1.5,
    "generalized_cone": 1.5,
    "bent_sheet": 1.5,
    "curved_fold": 1.7,
    "plane": 1.5,
}


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


def run_family(family, triangulation):
    """The figures of every seed: (dE %, flat share, Hausdorff ratio to the twin,
    where; on irregular triangulations also the twin's own ratio: the twin run
    through the engine, its distance to itself after over the input's)."""
    figures = []
    for seed in SEEDS:
        m = families.random_case(family, seed, triangulations=[triangulation])
        r = native.run(m.positions, m.triangles)
        s = r.stats
        where = "%s/%s seed %d (%d faces, noise %.3f AE)" % (family, triangulation, seed, len(m.triangles), m.noise)
        turned = (
            np.einsum("ij,ij->i", face_normals(m.positions, m.triangles), face_normals(r.positions, m.triangles)) < 0
        )
        assert not turned.any() and s["faces_turned_over"] == 0, where
        # Nor folds an edge (the crease guard on one patch, pipeline.cpp):
        # tangent developables' thin faces came back lying on their neighbours.
        creased = sharpened_edges(m.positions, r.positions, m.triangles, growth_degrees=90.0 + 1e-6)
        assert len(creased) == 0, (where, len(creased))
        assert s["mean_defect_after"] <= s["mean_defect_before"], where
        assert s["flat_share_after"] >= s["flat_share_before"], where
        if s["result"] == native.RESULT_UNCHANGED:
            assert np.array_equal(r.positions, m.positions) and s["result_message"], where
        h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
        ratio = sampled_hausdorff(r.positions, m.triangles, m.clean, m.triangles) / h0
        figure = (s["change_percent"], s["flat_share_after"], ratio, where)
        if triangulation == "irregular":
            twin = native.run(m.clean, m.triangles).positions
            figure += (sampled_hausdorff(twin, m.triangles, m.clean, m.triangles) / h0,)
        figures.append(figure)
    return figures


CASES = [
    (f, t) for f in families.FAMILIES for t in families.TRIANGULATIONS if not (f == "curved_fold" and t == "irregular")
]


@pytest.fixture(scope="module")
def results():
    """Every family and triangulation, run once for all the tests below."""
    return {case: run_family(*case) for case in CASES}


def test_no_run_folds_or_gets_worse(results):
    assert len(results) == len(CASES)  # run_family asserted each run


@pytest.mark.parametrize("family", [f for f in families.FAMILIES if f != "curved_fold"])
def test_grids_become_developable(results, family):
    runs = [r for t in GRIDS for r in results[(family, t)]]
    for change, flat, _, where in runs:
        assert change <= -98.0, where
        assert flat >= 0.95, where
    assert np.median([r[0] for r in runs]) <= -99.0


@pytest.mark.parametrize("family", SHAPE_KEPT)
def test_grids_keep_the_shape_within_the_noise(results, family):
    for _, _, ratio, where in [r for t in GRIDS for r in results[(family, t)]]:
        assert ratio <= 1.5, where


def test_curved_folds_become_developable(results):
    for t in ("grid", "alternating", "slivers"):
        for change, flat, _, where, *_ in results[("curved_fold", t)]:
            assert flat >= 0.95 and change <= -90.0, where


@pytest.mark.parametrize("family", [f for f in families.FAMILIES if f != "curved_fold"])
def test_irregular_triangulations_become_developable(results, family):
    for change, _, _, where, _ in results[(family, "irregular")]:
        assert change <= -95.0, where


@pytest.mark.parametrize("family", SHAPE_KEPT_IRREGULAR)
def test_irregular_triangulations_keep_the_shape_within_the_noise(results, family):
    for _, _, ratio, where, _ in results[(family, "irregular")]:
        assert ratio <= 1.5, where


@pytest.mark.parametrize("family", [f for f in families.FAMILIES if f != "curved_fold"])
def test_irregular_triangulations_move_no_more_than_their_triangles_force(results, family):
    """An irregular triangulation of a developable surface is not developable
    itself (its twin keeps 1-100 % of the noisy input's mean |defect|): the
    twin too has to move to become developable, as far as 4.8 times the noise
    on seed 102 of tangent_random. Every family's run ends within 1.5 times the
    larger of the noise and the twin's own move (docs/families.md)."""
    for _, _, ratio, where, twin in results[(family, "irregular")]:
        assert ratio <= 1.5 * max(1.0, twin), (where, ratio, twin)


@pytest.mark.parametrize("family", families.FAMILIES)
def test_the_shape_moves_no_more_than_today(results, family):
    ratios = [r[2] for (f, _), runs in results.items() if f == family for r in runs]
    assert np.median(ratios) <= MEDIAN_RATIO[family], (family, sorted(ratios))


def test_a_result_that_changed_the_shape_is_no_reference_for_roughness():
    """Least motion's roughness guard (docs/method.md): a wavy bent sheet whose
    deformation moved it far more than the noise (its waves flattened, its
    normals smoother than the sheet's own) does not keep the candidates that
    moved it about as much as the noise out for being rougher than that. A
    tuning seed: with the deformation's roughness as the only reference it
    ended 9.9 times the noise from its twin."""
    m = families.random_case("bent_sheet", 9, triangulations=["slivers"])
    r = native.run(m.positions, m.triangles)
    s = r.stats
    assert s["result_origin"] in native.LEAST_MOTION_ORIGINS, s
    assert s["flat_share_after"] >= 0.99 and s["change_percent"] <= -99.0, s
    h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
    assert sampled_hausdorff(r.positions, m.triangles, m.clean, m.triangles) <= 1.5 * h0


TURNED_AWAY = pytest.mark.xfail(
    strict=True,
    reason="the finish would move a vertex 1.55 times the choice's farthest (the polish of the raw input, "
    "which moved few vertices): turned away, 75 % flat and ruled (docs/method.md, Known limits)",
)


@pytest.mark.parametrize(
    "family,seed",
    [
        pytest.param("cylinder_patch", 100, marks=TURNED_AWAY),
        ("cylinder_patch", 101),
        ("cylinder_band", 100),
        ("cylinder_band", 101),
        ("cone_patch", 100),
        ("cone_patch", 101),
        ("bent_sheet", 100),
        ("bent_sheet", 101),
    ],
)
def test_scan_noise_comes_back_flat_and_ruled_nearer_the_twin(library, family, seed):
    """Issue 35: a sheet scanned with noise at 10-20 % of its edge length, which the polish
    leaves flat but crumpled (flat vertices whose faces are not bent about one line), comes
    back flat and ruled by the ruled finish (docs/method.md, "The ruled finish"), nearer its
    noise-free twin than the scan, surface distance and Hausdorff. One-diagonal grids, held-out
    seeds (the finish was tuned on seed 1); docs/families.md, "Scan noise", has every family."""
    m = families.random_case(family, seed, faces=(1000, 3000), noise=(0.1, 0.2), triangulations=["grid"])
    r = native.run(m.positions, m.triangles)
    figures = developability_figures(r.positions, m.triangles)
    assert figures["flat_and_ruled"] >= 0.97 and figures["crumpled"] <= 0.01, (figures, r.stats["result_origin"])
    assert r.stats["faces_turned_over"] == 0
    assert sampled_hausdorff(r.positions, m.triangles, m.clean, m.triangles) < sampled_hausdorff(
        m.positions, m.triangles, m.clean, m.triangles
    )
    grid = TriangleGrid(m.clean, m.triangles)

    def rms(positions):
        return np.sqrt(np.mean(grid.distances(samples(positions, m.triangles)) ** 2))

    assert rms(r.positions) < 0.8 * rms(m.positions)

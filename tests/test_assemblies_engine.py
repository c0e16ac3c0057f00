"""The command-line tool on noisy sheet-metal assemblies (devkit/assemblies.py) and on curved
folds (devkit/families.py), on seeds held out of the tuning of the crease pieces (0-19, issue
35): the engine finds an assembly's natural pieces in most runs from its creases, turns no face
over and keeps the shape near the noise-free twin; a curved fold, one developable sheet whose
fold carries no curvature, stays one piece and comes back 100 % flat: its fold's defects are the
noise's (pipeline/plan.h, crease_pieces_compete), so the plan's other alternatives run too, and
their one-patch result, developable within the noise (one_sheet_within_noise), wins under the one
order (split at the fold, the crease pieces left the fold's vertices curved, 93-97 % flat).

Every part and triangulation is drawn from the seed (random_case), 1000-2500 faces, noise 0.5-5 %
of the edge length; the tool runs with its defaults (devkit/tool.py)."""
import numpy as np
import pytest

from devkit import assemblies, families
from devkit.distance import sampled_hausdorff
from devkit.families import face_normals
from devkit.tool import run_tool

SEEDS = range(100, 104)  # held out: the crease pieces were tuned on 0-19
PARTS = ("elbow4", "elbow6", "tee", "ybranch", "cup", "reducer")
FACES = (1000, 2500)


def run(tool, tmp_path, positions, triangles, where):
    result = run_tool(tool, tmp_path, positions, triangles)
    assert not isinstance(result, str), (where, result)
    out, stats, _ = result
    turned = np.einsum("ij,ij->i", face_normals(positions, triangles), face_normals(out, triangles)) < 0
    assert not turned.any() and stats["faces_turned_over"] == 0, where
    return out, stats


@pytest.fixture(scope="module")
def held_out_runs(tool_path, tmp_path_factory):
    """part -> [(where, found the natural pieces, H/H0)] of the tool on SEEDS."""
    tmp_path = tmp_path_factory.mktemp("assemblies")
    runs = {}
    for part in PARTS:
        for seed in SEEDS:
            m = assemblies.random_case(part, seed, faces=FACES)
            where = f"{part} seed {seed} ({m.triangulation}, {len(m.triangles)} faces, noise {m.noise:.3f} AE)"
            out, stats = run(tool_path, tmp_path, m.positions, m.triangles, where)
            h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
            ratio = sampled_hausdorff(out, m.triangles, m.clean, m.triangles) / h0
            runs.setdefault(part, []).append((where, stats["patches"] == m.natural_pieces, ratio))
    return runs


@pytest.mark.parametrize("part", PARTS)
def test_assemblies_come_back_in_their_natural_pieces_near_their_twin(held_out_runs, part):
    runs = held_out_runs[part]
    for where, _, ratio in runs:
        # The run on crease pieces moves a vertex by at most twice the noise (pipeline/plan.h,
        # kCreaseMoveNoise); where the pieces are not found, the segmented run may move more
        # (bench/assemblies.py on seeds 100-119: up to 8 times the input's distance).
        assert ratio <= 3.0, (where, ratio)
    found = [natural for _, natural, _ in runs]
    assert sum(found) >= len(found) - 1, (part, found)


def test_assemblies_come_back_nearer_their_twin_than_the_scan(held_out_runs):
    # On pieces too, least motion's projected and smoothed starts (the input smoothed piece by
    # piece) keep the vertices whose angle sums hardly depend on their height on the surface, where
    # the polishes push them out: over these 24 runs the mean log H/H0 is -0.042 with them, -0.014
    # with the projected start alone, +0.028 with neither (bench/assemblies.py, 640 runs: 611 ->
    # 622 -> 625 within 1.5 times the noise; docs/method.md, "Crease pieces").
    ratios = [ratio for runs in held_out_runs.values() for _, _, ratio in runs]
    assert np.mean(np.log(ratios)) < 0.0, ratios


# Y-branches at 4-5 % noise, where the crease lines miss one of the three seams and two of the
# pieces come joined, fitting no cone: the plane that parts them (crease_pieces.h, step 5) gives
# the three back (seeds 600-611: 11 -> 12 of 12 in their pieces, largest H/H0 3.15 -> 1.06).
LOUD_SEEDS = range(600, 606)


def test_loud_noise_y_branches_come_back_in_their_three_pieces_near_their_twin(tool_path, tmp_path):
    for seed in LOUD_SEEDS:
        m = assemblies.random_case("ybranch", seed, faces=FACES, noise=(0.04, 0.05))
        where = "ybranch seed %d (%s, %d faces, noise %.3f AE)" % (seed, m.triangulation, len(m.triangles), m.noise)
        out, stats = run(tool_path, tmp_path, m.positions, m.triangles, where)
        assert stats["patches"] == m.natural_pieces, (where, stats["patches"])
        h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
        ratio = sampled_hausdorff(out, m.triangles, m.clean, m.triangles) / h0
        assert ratio <= 1.5, (where, ratio)


# The one-piece sheets whose crease pieces (a curved fold's two sides, a generalized cone's and a
# random-curve tangent developable's lines of high curvature) were taken before they competed:
# 93-97 % flat instead of 100 % (bench/regression.py against the plan without crease pieces).
SHEETS = [("curved_fold", t, s) for t in ("grid", "alternating") for s in (100, 101, 102)] + [
    ("generalized_cone", "alternating", 100),
    ("tangent_random", "slivers", 102),
]


@pytest.mark.parametrize("family,triangulation,seed", SHEETS)
def test_one_piece_sheets_stay_one_sheet_and_come_back_flat(tool_path, tmp_path, family, triangulation, seed):
    m = families.random_case(family, seed, triangulations=[triangulation])
    where = "%s/%s seed %d (%d faces, noise %.3f AE)" % (family, triangulation, seed, len(m.triangles), m.noise)
    _, stats = run(tool_path, tmp_path, m.positions, m.triangles, where)
    assert stats["patches"] == 1, where
    assert stats["flat_share_after"] == 1.0, (where, stats["flat_share_after"])

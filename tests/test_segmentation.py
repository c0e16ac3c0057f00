"""Segmentation into quasi-developable patches, and whole meshes made
piecewise developable."""
import numpy as np
import pytest

from devkit import families, meshes
from devkit.binding import native
from devkit.distance import bbox_diagonal, sampled_hausdorff
from devkit.measures import developability_figures, flat_share, seam_vertices, sharpened_edges
from devkit.obj import read_obj


def split_matches(patch_ids, piece):
    """True when the patches are exactly the given pieces (up to renaming)."""
    pairs = set(zip(piece.tolist(), patch_ids.tolist()))
    return len(pairs) == len(set(piece.tolist())) == len(set(patch_ids.tolist()))


@pytest.mark.parametrize("angle", [90.0, 150.0])
def test_folded_sheet_splits_along_the_crease(library, angle):
    positions, triangles = meshes.folded_sheet(angle_degrees=angle)
    flat, _ = meshes.plane()
    piece = (flat[triangles].mean(axis=1)[:, 0] > 1.0).astype(int)
    result = native.run(positions, triangles, params=dict(segmentation=1))
    assert result.stats["patches"] == 2
    assert split_matches(result.patch_ids, piece)


def test_cylinder_joined_to_cone_splits_along_the_seam(library):
    positions, triangles, piece = meshes.cylinder_cone()
    result = native.run(positions, triangles, params=dict(segmentation=1))
    assert result.stats["patches"] == 2
    assert split_matches(result.patch_ids, piece)
    assert {patch for _, patch, _ in result.curves} == {0, 1}


def test_segmentation_is_deterministic(library, meshes_dir):
    positions, triangles = read_obj(meshes_dir / "wingnut.obj")
    a = native.run(positions, triangles, params=dict(segmentation=1, max_iterations=1))
    b = native.run(positions, triangles, params=dict(segmentation=1, max_iterations=1))
    assert np.array_equal(a.patch_ids, b.patch_ids)


def test_segmentation_off_gives_one_patch(library, meshes_dir):
    positions, triangles = read_obj(meshes_dir / "wingnut.obj")
    result = native.run(positions, triangles, params=dict(segmentation=0, max_iterations=1))
    assert result.stats["patches"] == 1 and not result.patch_ids.any()


@pytest.mark.parametrize(
    "family,triangulation,seed",
    [
        ("tangent_random", "alternating", 0),  # the one-curve fit calls their Gauss images blobs
        ("generalized_cone", "slivers", 0),
    ],
)
def test_automatic_segmentation_gives_way_to_one_patch_that_is_more_developable(library, family, triangulation, seed):
    """A noisy developable whose Gauss image the one-curve fit fails on gets
    a misfit that asks for segmentation; split, it ends less developable than
    as one patch, and the automatic choice returns the one-patch run
    (pipeline.cpp, second opinion). Tuning seeds of devkit/families.py."""
    m = families.random_case(family, seed, triangulations=[triangulation])
    fractions = []
    auto = native.run(m.positions, m.triangles, progress=lambda f, _: fractions.append(f) or True)
    assert fractions == sorted(fractions) and fractions[-1] == 1.0  # two runs, one progress bar
    split = native.run(m.positions, m.triangles, params=dict(segmentation=1))
    whole = native.run(m.positions, m.triangles, params=dict(segmentation=0))
    assert split.stats["patches"] > 1
    assert auto.stats["patches"] == 1 and np.array_equal(auto.positions, whole.positions)
    assert auto.stats["flat_share_after"] > split.stats["flat_share_after"]
    assert auto.stats["mean_defect_after"] < split.stats["mean_defect_after"]
    assert auto.stats["change_percent"] <= -99 and auto.stats["flat_share_after"] >= 0.95


def test_the_one_patch_run_may_raise_the_largest_defect_a_little(library):
    """The second opinion's one-patch run is returned when it is flatter on
    both figures even if one vertex ends a little above the input's largest
    |defect| (at most 5 %, as the nearly flat polish may), and the message
    says so. A twisted cubic's tangent developable on slivers, held-out seed
    206: split, -87 % and 74 % flat; as one patch -94 % and 93 % flat with the
    largest |defect| 2 % above the input's."""
    m = families.random_case("tangent_cubic", 206, triangulations=["slivers"])
    auto = native.run(m.positions, m.triangles)
    split = native.run(m.positions, m.triangles, params=dict(segmentation=1))
    assert split.stats["patches"] > 1
    assert auto.stats["patches"] == 1
    bar = max(split.stats["max_defect_after"], auto.stats["max_defect_before"])
    assert bar < auto.stats["max_defect_after"] <= 1.05 * bar
    assert auto.stats["flat_share_after"] > split.stats["flat_share_after"]
    assert auto.stats["mean_defect_after"] < split.stats["mean_defect_after"]
    assert "largest |defect| grew" in auto.stats["result_message"]


ELBOW_SEEDS = range(8)


@pytest.fixture(scope="module")
def pipe_elbow_runs(library):
    """The defaults' stats on random pipe elbows (devkit/meshes.py), by seed."""
    return {seed: native.run(*meshes.pipe_elbow(np.random.default_rng(seed))).stats for seed in ELBOW_SEEDS}


@pytest.mark.parametrize("seed", ELBOW_SEEDS)
def test_an_open_pipe_elbow_comes_back_improved(pipe_elbow_runs, seed):
    """A random pipe elbow: its total curvature can only gather, on seams or,
    as one patch, where the rulings bend. Automatic segmentation's second
    opinion returns whichever run the result check let through; before, a
    one-patch run whose largest |defect| grew by 4-14 % lost to a segmented
    run that returned the input (4 of these 8 elbows came back unchanged)."""
    s = pipe_elbow_runs[seed]
    assert s["result"] == native.RESULT_IMPROVED, s["result_message"]
    assert s["faces_turned_over"] == 0
    assert s["flat_share_after"] > s["flat_share_before"]
    assert s["mean_defect_after"] < s["mean_defect_before"]
    if s["max_defect_after"] > s["max_defect_before"]:
        assert "largest |defect| grew" in s["result_message"]


def test_most_open_pipe_elbows_come_back_much_flatter(pipe_elbow_runs):
    """Which of the two runs an elbow gets depends on the last bits of its
    input: the segmented run's mean |defect| ends within 2 % of the input's,
    the admission's bound (seed 5: 21 patches and refused, or, its
    coordinates scaled by 1 + 4e-12, 20 patches and 9 -> 74 % flat; the
    one-patch polish 9 -> 13 %). Over scalings by 1 + k 1e-12 (k = 0-5) every
    scaling had at least 7 of the 8 elbows 10 points flatter or more
    (docs/segmentation.md, "Pipe elbows")."""
    gains = [s["flat_share_after"] - s["flat_share_before"] for s in pipe_elbow_runs.values()]
    assert sum(g >= 0.1 for g in gains) >= 6, gains


@pytest.mark.parametrize("seed", range(300, 308))
def test_a_lobster_back_elbow_is_found_developable_piecewise(library, seed):
    """Cylinder pieces joined by mitres: segmentation's cone fits cut across
    the mitres (at their sides the cylinders are tangent); the cuts along the
    curvature (developable_pieces.h) find one patch per cylinder, so the
    engine says the mesh is developable piecewise and returns it as it is.
    Tuned on seeds 0-39, 100-139 and 200-229; these are held out."""
    pieces = int(np.random.default_rng(seed).integers(2, 7))  # the generator's first draw
    positions, triangles = meshes.lobster_elbow(np.random.default_rng(seed), turns_degrees=(10.0, 60.0))
    result = native.run(positions, triangles)
    s = result.stats
    assert s["result"] == native.RESULT_UNCHANGED and np.array_equal(result.positions, positions)
    assert s["unchanged_reason"] == native.UNCHANGED_DEVELOPABLE_PIECEWISE, s["result_message"]
    assert s["patches"] == pieces and len(np.unique(result.patch_ids)) == pieces


def test_an_open_whole_object_is_planned_as_a_closed_one(library, meshes_dir):
    """hand_lowres is open at the wrist, but its curvature sums to 6.2 rad: a
    whole object (selection.h, is_object), never run as one patch, planned as a
    closed mesh is (its segmented run beside the thinned pieces, the order
    reading the flat-and-ruled share first): automatic and forced
    segmentation give the same result, its thinned pieces (42.7 % flat and
    ruled, 0.6 % crumpled; the segmented run was 50.8 % flat, 28.5 % flat and
    ruled)."""
    positions, triangles = read_obj(meshes_dir / "hand_lowres.obj")
    auto = native.run(positions, triangles)
    split = native.run(positions, triangles, params=dict(segmentation=1))
    assert auto.stats["patches"] > 1 and auto.stats["patches"] == split.stats["patches"]
    assert np.array_equal(auto.positions, split.positions)
    assert auto.stats["result_origin"] == 8  # DEV_ORIGIN_THINNED_PIECES
    assert auto.stats["ruled_share_after"] >= 0.38


# wingnut was here too until 2026-12-06: 77 % of its vertices flat, its boss and wing tips doubly
# curved, it came back unchanged only because its thinned pieces raised the mean |defect| over every
# vertex by 35 %; held inside its pieces it comes back as them (test_objects_pieces.py).
@pytest.mark.parametrize("name", ["boat"])
def test_piecewise_developable_meshes_keep_their_shape(library, meshes_dir, name):
    positions, triangles = read_obj(meshes_dir / (name + ".obj"))
    result = native.run(positions, triangles)
    s = result.stats
    interior = result.interior
    flat_before = np.mean(np.abs(result.defect_before[interior]) < 1e-3)
    flat_after = np.mean(np.abs(result.defect_after[interior]) < 1e-3)
    assert flat_after >= flat_before - 0.01
    assert s["mean_defect_after"] <= s["mean_defect_before"]
    distance = sampled_hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.005 * bbox_diagonal(positions)
    if s["result"] == native.RESULT_UNCHANGED:
        # The polish of boat's input ran 11 steps and was not kept: the
        # panel showed "Angle polish: 11 steps" under "Nothing changed".
        assert s["polish_iterations"] == 0


# Issue 11: these results were reached by turning faces over (or raising the
# mean |defect|); the fold-free step reaches less (human_woman at 60 patches
# and 1.4 AE: 38 % flat instead of 55 %; the torus's mean |defect| rises with
# every flatter iterate, so it comes back unchanged).
FOLDS_XFAIL = pytest.mark.xfail(
    strict=True, reason="issue 11: reached only by folding; the " "fold-free step does not reach it yet"
)


def patch_inside(triangles, patch_ids, interior):
    """Interior vertices whose faces all belong to one patch (not on a seam)."""
    return interior & ~seam_vertices(interior.size, triangles, patch_ids)


def test_human_woman_is_made_piecewise_developable(library, meshes_dir):
    """The issue's goal on the closest to the paper's wetsuit: on a closed
    surface the total curvature is fixed (Gauss-Bonnet), so a good result
    gathers it on the seams and the share of flat vertices counts. With 60
    patches and a 1.4 AE tolerance (docs/segmentation.md), at least half of
    the interior vertices end with |defect| < 1e-3 rad (about 60 %), within
    1 % of the bounding-box diagonal, with no face turned over and no edge
    inside a patch sharpened by more than the crease guard's 20 degrees
    (before the guard: 66 %, with the face crumpled)."""
    positions, triangles = read_obj(meshes_dir / "human_woman.obj")
    result = native.run(positions, triangles, params=dict(target_patches=60, tolerance=1.4))
    interior = result.interior
    assert result.stats["patches"] == 60
    assert flat_share(result.defect_before, interior) < 0.05
    assert flat_share(result.defect_after, interior) >= 0.5
    assert result.stats["faces_turned_over"] == 0
    assert len(sharpened_edges(positions, result.positions, triangles, result.patch_ids, 21.0)) == 0
    distance = sampled_hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.01 * bbox_diagonal(positions)


def test_whole_objects_with_the_defaults_bend_without_crumpling(library, meshes_dir):
    """human_woman with every default: ruled pieces, not a crumpled mask. No
    edge inside a patch sharpened by more than the crease guard's 20 degrees
    (without the guard 7.9 % of the edges were, the fingers pressed into
    blades); at least 45 % of the interior vertices flat and ruled (47.1 %
    since pieces still curved inside are split, 48.3 % before, 44.6 % before
    the ruled polish gave up sooner, docs/segmentation.md;
    the flat-by-zigzag result the order took before ranking closed meshes by
    that share: 64.8 % flat, 33.6 % flat and ruled, 31 % crumpled), at most 3 %
    crumpled (issue 35's bound), within 1 % of the diagonal, no face turned
    over."""
    positions, triangles = read_obj(meshes_dir / "human_woman.obj")
    result = native.run(positions, triangles)
    assert result.stats["patches"] > 1
    assert len(sharpened_edges(positions, result.positions, triangles, result.patch_ids, 21.0)) == 0
    after = developability_figures(result.positions, triangles)
    assert after["flat_and_ruled"] >= 0.45, after
    assert after["crumpled"] <= 0.03, after
    assert result.stats["faces_turned_over"] == 0
    # The move limit is 1 % of the diagonal exactly, and the vertex at it sets the distance.
    distance = sampled_hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.01 * bbox_diagonal(positions) * (1 + 1e-9)


@pytest.mark.parametrize("seams", [native.SEAMS_FREE, native.SEAMS_PINNED], ids=["free", "pinned"])
def test_segmented_result_is_flatter_inside_the_patches(library, meshes_dir, seams):
    """Default settings: automatic segmentation, and the kept iterate is the
    one with the lowest median |defect| inside the patches, never above the
    input's; free seams (the default) flatten far more than pinned ones."""
    positions, triangles = read_obj(meshes_dir / "human_woman.obj")
    result = native.run(positions, triangles, params=dict(seams=seams))
    assert result.stats["patches"] > 1
    inside = patch_inside(triangles, result.patch_ids, result.interior)
    before = np.median(np.abs(result.defect_before[inside]))
    after = np.median(np.abs(result.defect_after[inside]))
    assert after <= before
    if seams == native.SEAMS_FREE:
        assert after < 0.2 * before
        assert flat_share(result.defect_after, result.interior) >= 0.3
    limit = result.stats["average_edge_length"] * 10.0  # the default tolerance
    assert np.linalg.norm(result.positions - positions, axis=1).max() <= limit * (1 + 1e-9)


@FOLDS_XFAIL
def test_target_smoothing_flattens_doubly_curved_patches(library, meshes_dir):
    """Projected targets of a doubly curved patch jump along its ideal curve
    and crumple it; the automatic one round of smoothing on a segmented mesh
    (docs/method.md) flattens the torus's patches instead (measured: 11 % of
    the vertices flat without it, 35 % with it, 8 % before)."""
    positions, triangles = read_obj(meshes_dir / "torus.obj")
    plain = native.run(positions, triangles, params=dict(target_smoothing=0))
    smoothed = native.run(positions, triangles)
    assert plain.stats["patches"] > 1
    flat_plain = flat_share(plain.defect_after, plain.interior)
    flat_smoothed = flat_share(smoothed.defect_after, smoothed.interior)
    assert flat_smoothed >= max(2.0 * flat_plain, 0.3)
    distance = sampled_hausdorff(positions, triangles, smoothed.positions, triangles)
    assert distance <= 0.01 * bbox_diagonal(positions)

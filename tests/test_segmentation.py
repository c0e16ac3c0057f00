"""Segmentation into quasi-developable patches, and whole meshes made
piecewise developable."""
import numpy as np
import pytest

import geometry
import meshgen


def split_matches(patch_ids, piece):
    """True when the patches are exactly the given pieces (up to renaming)."""
    pairs = set(zip(piece.tolist(), patch_ids.tolist()))
    return len(pairs) == len(set(piece.tolist())) == len(set(patch_ids.tolist()))


@pytest.mark.parametrize("angle", [90.0, 150.0])
def test_folded_sheet_splits_along_the_crease(engine, angle):
    positions, triangles = meshgen.folded_sheet(angle_degrees=angle)
    flat, _ = meshgen.plane()
    piece = (flat[triangles].mean(axis=1)[:, 0] > 1.0).astype(int)
    result = engine.run(positions, triangles, segmentation=1)
    assert result.stats["patches"] == 2
    assert split_matches(result.patch_ids, piece)


def test_cylinder_joined_to_cone_splits_along_the_seam(engine):
    positions, triangles, piece = meshgen.cylinder_cone()
    result = engine.run(positions, triangles, segmentation=1)
    assert result.stats["patches"] == 2
    assert split_matches(result.patch_ids, piece)
    assert {c["patch"] for c in result.curves} == {0, 1}


def test_segmentation_is_deterministic(engine, meshes_dir):
    positions, triangles = meshgen.read_obj(meshes_dir / "wingnut.obj")
    a = engine.run(positions, triangles, segmentation=1, max_iterations=1)
    b = engine.run(positions, triangles, segmentation=1, max_iterations=1)
    assert np.array_equal(a.patch_ids, b.patch_ids)


def test_segmentation_off_gives_one_patch(engine, meshes_dir):
    positions, triangles = meshgen.read_obj(meshes_dir / "wingnut.obj")
    result = engine.run(positions, triangles, segmentation=0, max_iterations=1)
    assert result.stats["patches"] == 1 and not result.patch_ids.any()


@pytest.mark.parametrize("name", ["boat", "wingnut"])
def test_piecewise_developable_meshes_keep_their_shape(engine, meshes_dir, name):
    positions, triangles = meshgen.read_obj(meshes_dir / (name + ".obj"))
    result = engine.run(positions, triangles)
    s = result.stats
    interior = result.interior
    flat_before = np.mean(np.abs(result.defect_before[interior]) < 1e-3)
    flat_after = np.mean(np.abs(result.defect_after[interior]) < 1e-3)
    assert flat_after >= flat_before - 0.01
    assert s["mean_defect_after"] <= s["mean_defect_before"]
    distance = geometry.hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.005 * geometry.bbox_diagonal(positions)


@pytest.mark.parametrize("seams", ["free", "pinned"])
def test_human_woman_is_segmented_and_never_made_worse(engine, meshes_dir, seams):
    """The closest to the paper's wetsuit. On a closed surface the total
    curvature is fixed (Gauss-Bonnet), so the share of flat vertices counts.
    The engine does not yet reach the goal of half the vertices flat (see
    docs/segmentation.md); what it guarantees is checked here: automatic
    segmentation, the tolerance, and a result never worse than the input."""
    positions, triangles = meshgen.read_obj(meshes_dir / "human_woman.obj")
    result = engine.run(positions, triangles, seams=seams)
    interior = result.interior
    assert result.stats["patches"] > 1
    flat_before = np.mean(np.abs(result.defect_before[interior]) < 1e-3)
    flat_after = np.mean(np.abs(result.defect_after[interior]) < 1e-3)
    assert flat_before < 0.05 and flat_after >= flat_before
    assert result.stats["mean_defect_after"] <= result.stats["mean_defect_before"]
    distance = geometry.hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.01 * geometry.bbox_diagonal(positions)

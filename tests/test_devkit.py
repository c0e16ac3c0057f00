"""The development kit's own promises (devkit/): OBJ files read back bit for
bit, exact point-to-triangle distances, and the grid-accelerated sampled
Hausdorff distance equal to a brute-force search over every triangle."""
import numpy as np
import pytest

from devkit import meshes
from devkit.distance import point_triangle_distance, samples, sampled_hausdorff
from devkit.obj import read_obj, write_obj


def test_obj_round_trip_is_bit_exact(tmp_path):
    positions, triangles = meshes.noisy_cylinder_patch(seed=3)
    positions[5] = [np.inf, -np.inf, 1e-300]
    write_obj(tmp_path / "m.obj", positions, triangles)
    back_p, back_t = read_obj(tmp_path / "m.obj")
    assert np.array_equal(back_p.view(np.uint64), positions.view(np.uint64))
    assert np.array_equal(back_t, triangles) and back_t.dtype == np.int32


def test_obj_polygons_are_split_into_fans(tmp_path):
    (tmp_path / "q.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1/1 2/2/2 3/3/3 4/4/4\n")
    _, triangles = read_obj(tmp_path / "q.obj")
    assert triangles.tolist() == [[0, 1, 2], [0, 2, 3]]


A, B, C = np.array([0.0, 0, 0]), np.array([2.0, 0, 0]), np.array([0.0, 2, 0])


@pytest.mark.parametrize(
    "point,distance",
    [
        ((0.5, 0.5, 3.0), 3.0),  # above the face
        ((-1.0, -1.0, 0.0), np.sqrt(2)),  # beyond vertex a
        ((3.0, -1.0, 1.0), np.sqrt(3)),  # beyond vertex b
        ((1.0, -2.0, 0.0), 2.0),  # beside edge ab
        ((-0.5, 1.0, 0.0), 0.5),  # beside edge ac
        ((2.0, 2.0, 0.0), np.sqrt(2)),  # beside edge bc
    ],
)
def test_point_triangle_distance_in_every_region(point, distance):
    d = point_triangle_distance(np.array([point]), A, B, C)
    assert d[0] == pytest.approx(distance, rel=1e-14)


def brute_force_one_sided(points, positions, triangles):
    tri = positions[triangles]
    best = np.full(len(points), np.inf)
    for t in tri:
        best = np.minimum(best, point_triangle_distance(points, t[0], t[1], t[2]))
    return best.max()


@pytest.mark.parametrize("other", ["same connectivity", "other connectivity"])
def test_sampled_hausdorff_equals_brute_force(other):
    pos, tri = meshes.cone(rows=6, cols=24, r0=1.36, r1=0.68, height=0.72, bulge=0.066)
    if other == "same connectivity":
        pos_b, tri_b = meshes.add_noise(pos, 0.02, seed=5), tri
    else:
        pos_b, tri_b = meshes.cone(rows=5, cols=30, r0=1.3, r1=0.7, height=0.75)
    expected = max(
        brute_force_one_sided(samples(pos, tri), pos_b, tri_b), brute_force_one_sided(samples(pos_b, tri_b), pos, tri)
    )
    assert sampled_hausdorff(pos, tri, pos_b, tri_b) == pytest.approx(expected, rel=1e-12)

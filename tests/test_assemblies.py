"""The promises of devkit/assemblies.py (seeded sheet-metal assemblies with their noise-free
twins and natural pieces) and of the developability measures of devkit/measures.py
(ruled_spread, developability_figures, dihedral_angles) on cases known in closed form.
numpy only: no build needed."""
import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from devkit import assemblies, families, meshes
from devkit.measures import angle_defects, developability_figures, dihedral_angles, ruled_spread

SEEDS = (0, 1, 2)
CASES = [(p, t) for p in assemblies.PARTS for t in assemblies.TRIANGULATIONS]
# Boundary loops of each part: pipe ends, the cup's rim; the sheet: its edge and one per hole.
OPEN_ENDS = {"transition": 2, "reducer": 2, "elbow4": 2, "elbow6": 2, "tee": 3, "ybranch": 3, "cup": 1}


def edges_of(triangles):
    """(unique undirected edges, how many faces each), and the directed edges' counts."""
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    edges, count = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    return edges, count, np.unique(directed, axis=0, return_counts=True)[1]


def components(n, pairs):
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def face_pairs(triangles):
    """(face, face) of every edge between two faces."""
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    key = np.sort(directed, axis=1)
    face = np.tile(np.arange(len(triangles)), 3)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], face[order]
    same = np.nonzero(np.all(key[1:] == key[:-1], axis=1))[0]
    return key[same], np.c_[face[same], face[same + 1]]


def inside_pieces(mesh):
    """Vertices whose faces all belong to one piece (off the seams)."""
    n = len(mesh.clean)
    low = np.full(n, np.iinfo(np.int32).max)
    high = np.full(n, -1)
    for corner in range(3):
        np.minimum.at(low, mesh.triangles[:, corner], mesh.pieces)
        np.maximum.at(high, mesh.triangles[:, corner], mesh.pieces)
    return low == high


@pytest.fixture(scope="module")
def generated():
    """Every triangulation of every part for three seeds, 800-2400 faces, noise 2 %."""
    return {(p, t, s): assemblies.make(p, t, faces=800 + 800 * s, noise=0.02, seed=s) for p, t in CASES for s in SEEDS}


# -- the generator -------------------------------------------------------------------------


@pytest.mark.parametrize("part", assemblies.PARTS)
def test_the_same_arguments_give_the_same_mesh_bit_for_bit(part):
    a = assemblies.random_case(part, 5)
    b = assemblies.random_case(part, 5)
    for name in ("positions", "clean", "triangles", "pieces", "creases"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.positions.tobytes() == b.positions.tobytes()
    other = assemblies.random_case(part, 6)
    assert len(other.clean) != len(a.clean) or not np.array_equal(other.clean, a.clean)


@pytest.mark.parametrize("part,triangulation", CASES)
def test_every_triangulation_is_one_welded_manifold_oriented_mesh(generated, part, triangulation):
    for seed in SEEDS:
        m = generated[(part, triangulation, seed)]
        where = "%s/%s seed %d" % (part, triangulation, seed)
        t, n = m.triangles, len(m.clean)
        assert t.dtype == np.int32 and m.pieces.dtype == np.int32 and m.creases.dtype == np.int32
        assert 0.75 * (800 + 800 * seed) <= len(t) <= 1.25 * (800 + 800 * seed), (where, len(t))
        assert np.array_equal(np.unique(t), np.arange(n)), where  # no loose vertex
        assert np.all((t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])), where
        edges, count, directed = edges_of(t)
        assert count.max() <= 2, where  # manifold edges
        assert directed.max() == 1, where  # one orientation
        # Welded: no two vertices in one place.
        diagonal = np.linalg.norm(m.clean.max(axis=0) - m.clean.min(axis=0))
        assert not cKDTree(m.clean).query_pairs(1e-9 * diagonal), where
        corner = m.clean[t]
        area = np.linalg.norm(np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0]), axis=1)
        assert area.min() > 1e-3 * area.mean(), where
        # Open where the real part is, and nowhere else: its boundary loops; one surface
        # without handles (Euler characteristic 2 - loops).
        rim = edges[count == 1]
        loops = len(np.unique(components(n, rim)[np.unique(rim)]))
        assert loops == OPEN_ENDS.get(part, 1 + m.info.get("holes_meshed", 0)), where
        assert n - len(edges) + len(t) == 2 - loops, where
        if part == "holed_sheet":
            assert 1 <= m.info["holes_meshed"] <= 3, where


@pytest.mark.parametrize("part,triangulation", CASES)
def test_the_twin_is_exactly_developable_inside_every_piece(generated, part, triangulation):
    for seed in SEEDS:
        m = generated[(part, triangulation, seed)]
        where = "%s/%s seed %d" % (part, triangulation, seed)
        defects, interior = angle_defects(m.clean, m.triangles)
        inside = interior & inside_pieces(m)
        assert inside.sum() > 0.2 * len(m.clean), where
        assert np.abs(defects[inside]).max() < 1e-9, (where, np.abs(defects[inside]).max())
        # ... and ruled there (each vertex between the planar strips along its ruling).
        figures = developability_figures(m.clean, m.triangles, interior=inside)
        assert figures["flat_and_ruled"] == 1.0, (where, figures)
        # The noise: every coordinate moved, by at most noise x AE.
        move = np.abs(m.positions - m.clean)
        assert 0.5 * 0.02 * m.info["ae"] < move.max() <= 0.02 * m.info["ae"] * (1 + 1e-12), where
        assert np.mean(move > 0) > 0.99, where
        noisy, _ = angle_defects(m.positions, m.triangles)
        assert np.abs(noisy[inside]).mean() > 1e-4, where


@pytest.mark.parametrize("part,triangulation", CASES)
def test_pieces_are_the_natural_ones_and_creases_the_edges_between_them(generated, part, triangulation):
    for seed in SEEDS:
        m = generated[(part, triangulation, seed)]
        where = "%s/%s seed %d" % (part, triangulation, seed)
        assert m.natural_pieces == assemblies.NATURAL_PIECES[part]
        assert np.array_equal(np.unique(m.pieces), np.arange(m.natural_pieces)), where
        edge, faces = face_pairs(m.triangles)
        between = m.pieces[faces[:, 0]] != m.pieces[faces[:, 1]]
        # Each piece one connected set of faces (across its own edges).
        within = faces[~between]
        label = components(len(m.triangles), within)
        for piece in range(m.natural_pieces):
            assert len(np.unique(label[m.pieces == piece])) == 1, (where, piece)
        expected = {tuple(e) for e in edge[between]}
        assert len(m.creases) == len(expected) and {tuple(e) for e in m.creases} == expected, where
        assert np.all(m.creases[:, 0] < m.creases[:, 1]), where
        if m.natural_pieces > 1:
            assert len(m.creases) >= 12, where


def test_the_creases_are_creases():
    """The seams fold by the parts' angles: the cup's bottom meets its side at the facets' slope;
    a mitre turns the normals by the turn per mitre where the bend's plane cuts it (column 0,
    grid) and by nothing where the pipe's sides run through it; the square-to-round's
    triangles meet their cones tangentially (only the facets' angle), on planar strips."""
    cup = assemblies.make("cup", "grid", 2000, 0.0, 4)
    rb, rt = cup.info["radii"]
    # A facet of the side spans two of its N columns: a chord pi / N off each, so its run
    # outwards is (rt - rb) cos(pi / N).
    slope = np.arctan2(cup.info["height"], (rt - rb) * np.cos(np.pi / len(cup.creases)))
    assert np.allclose(dihedral_angles(cup.clean, cup.triangles, cup.creases), slope, rtol=1e-9)
    elbow = assemblies.make("elbow6", "grid", 2000, 0.0, 4)
    bends = dihedral_angles(elbow.clean, elbow.triangles, elbow.creases)
    assert np.isclose(bends.max(), elbow.info["turn"], rtol=1e-9) and bends.min() < 0.1 * elbow.info["turn"]
    transition = assemblies.make("transition", "irregular", 2000, 0.0, 4)
    bends = dihedral_angles(transition.clean, transition.triangles, transition.creases)
    assert bends.max() < 0.2 and np.median(bends) < 0.1
    # So the whole transition is one developable sheet, flat and ruled on its seams too; the
    # cup's seam is not flat.
    assert developability_figures(transition.clean, transition.triangles)["flat_and_ruled"] == 1.0
    defects, _ = angle_defects(cup.clean, cup.triangles)
    assert np.abs(defects[cup.creases.ravel()]).min() > 1e-3


def test_make_refuses_what_it_cannot_build():
    with pytest.raises(ValueError):
        assemblies.make("teapot")
    with pytest.raises(ValueError):
        assemblies.make("tee", "voronoi")
    with pytest.raises(ValueError):
        assemblies.make("tee", "grid", faces=100)


def test_random_case_draws_within_its_ranges():
    seen = set()
    for seed in range(8):
        m = assemblies.random_case("reducer", seed, faces=(1000, 2000), noise=(0.01, 0.02))
        assert 0.01 <= m.noise <= 0.02 and 0.75 * 1000 <= len(m.triangles) <= 1.25 * 2000
        seen.add(m.triangulation)
        seen.add(m.info["eccentric"])
    assert {True, False} <= seen and len(seen) >= 4
    only = assemblies.random_case("cup", 1, triangulations=["slivers"])
    assert only.triangulation == "slivers"


def test_scan_sheets_are_families_with_scan_noise():
    a = assemblies.scan_sheet("cone_patch", "irregular", 1500, 0.3, 2)
    b = families.make("cone_patch", "irregular", 1500, 0.3, 2)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.triangles, b.triangles)
    for seed in range(6):
        m = assemblies.random_scan_sheet("curved_fold", seed)
        assert 0.1 <= m.noise <= 0.5 and m.triangulation != "irregular"
        assert np.array_equal(m.positions, assemblies.random_scan_sheet("curved_fold", seed).positions)
        move = np.abs(m.positions - m.clean).max()
        assert 0.5 * m.noise * m.info["ae"] < move <= m.noise * m.info["ae"] * (1 + 1e-12)


# -- the measures on closed-form cases -------------------------------------------------------


def miura(rows=9, cols=11, step=1.0, height=0.5, shift=0.4, depth=1.0):
    """A Miura-ori, the translational surface of two zigzags, (i step, 0, height (i mod 2)) and
    (shift (j mod 2), j depth, 0): planar parallelograms whose four angles at every vertex are
    a, pi - a, pi - a, a (angle defect exactly 0), their normals (+-height depth,
    +-height shift, step depth) on no great circle."""
    i, j = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    p = np.stack([i * step + shift * (j % 2), j * depth, height * (i % 2)], -1).reshape(-1, 3)
    return p.astype(np.float64), meshes.grid_triangles(rows, cols)


def test_a_cylinder_and_a_cone_are_flat_and_ruled():
    for positions, triangles in (meshes.cylinder(rows=10, cols=40), meshes.cone(rows=8, cols=48)):
        spread = ruled_spread(positions, triangles)
        _, interior = angle_defects(positions, triangles)
        assert np.all(spread[interior] < 1e-6)
        assert np.all(np.isnan(spread[~interior]))  # boundary: NaN
        figures = developability_figures(positions, triangles)
        assert figures == {
            "vertices": int(interior.sum()),
            "flat": 1.0,
            "ruled": 1.0,
            "flat_and_ruled": 1.0,
            "crumpled": 0.0,
        }


def test_a_cones_apex_spreads_by_its_normals_circle():
    """At the pole of a sphere cap the fan's normals lie on a circle of polar angle g around the
    axis, equally weighted: M = W diag(sin^2 g / 2, sin^2 g / 2, cos^2 g), so the spread is
    arcsin(sin g / sqrt 2)."""
    positions, triangles = meshes.sphere_cap(40, rings=10, sectors=36)
    p = positions[triangles[0]]
    normal = np.cross(p[1] - p[0], p[2] - p[0])
    g = np.arccos(abs(normal[2]) / np.linalg.norm(normal))
    assert np.isclose(ruled_spread(positions, triangles)[0], np.arcsin(np.sin(g) / np.sqrt(2)), rtol=1e-9)


def test_a_miura_ori_is_flat_but_not_ruled():
    # Proportions where the smallest eigenvalue is the x-z block's, which the weights set (with
    # equal weights b would vanish and the spread be 1.9 times as large).
    step, height, shift, depth = 1.0, 0.2, 2.0, 1.0
    positions, triangles = miura(step=step, height=height, shift=shift, depth=depth)
    defects, interior = angle_defects(positions, triangles)
    assert np.abs(defects[interior]).max() < 1e-12
    # M = (1/|n|^2) [[2 pi h^2 d^2, 0, b], [0, 2 pi h^2 s^2, 0], [b, 0, 2 pi l^2 d^2]] with
    # b = 2 (pi - 2 a) h l d^2 (a: the parallelogram's angle; weights a, pi - a, pi - a, a).
    a = np.arccos(step * shift / (np.hypot(step, height) * np.hypot(shift, depth)))
    norm2 = (height * depth) ** 2 + (height * shift) ** 2 + (step * depth) ** 2
    xx, zz = 2 * np.pi * (height * depth) ** 2, 2 * np.pi * (step * depth) ** 2
    xz = 2 * (np.pi - 2 * a) * height * step * depth**2
    smallest = min(2 * np.pi * (height * shift) ** 2, (xx + zz) / 2 - np.hypot((xx - zz) / 2, xz)) / norm2
    expected = np.arcsin(np.sqrt(smallest / (2 * np.pi)))
    assert expected > 0.1
    assert np.allclose(ruled_spread(positions, triangles)[interior], expected, rtol=1e-9)
    figures = developability_figures(positions, triangles)
    assert figures["flat"] == 1.0 and figures["ruled"] == 0.0 and figures["crumpled"] == 1.0


def test_a_pleated_sheet_is_flat_and_ruled():
    """Rows pushed alternately up and down: every vertex sits on a straight fold, its star's
    normals are two points, on one great circle: developable, ruled."""
    i, j = np.meshgrid(np.arange(9), np.arange(11), indexing="ij")
    positions = np.stack([i * 1.0, j * 1.0, 0.4 * (i % 2)], -1).reshape(-1, 3).astype(np.float64)
    triangles = meshes.grid_triangles(9, 11)
    figures = developability_figures(positions, triangles)
    assert figures["flat"] == 1.0 and figures["flat_and_ruled"] == 1.0 and figures["crumpled"] == 0.0


def test_a_noisy_sheet_is_neither_flat_nor_ruled():
    positions, triangles = meshes.plane(rows=20, cols=24)
    noisy = meshes.add_noise(positions, 0.05, seed=3)  # half a tenth of the edge length
    spread = ruled_spread(noisy, triangles)
    _, interior = angle_defects(noisy, triangles)
    assert np.mean(spread[interior] > 0.02) > 0.95
    figures = developability_figures(noisy, triangles)
    assert figures["flat"] < 0.05 and figures["flat_and_ruled"] < 0.05 and figures["crumpled"] < 0.05
    # Counting only some vertices: the mask is intersected with the interior ones.
    mask = np.zeros(len(positions), dtype=bool)
    mask[:30] = True
    assert developability_figures(noisy, triangles, interior=mask)["vertices"] == int((mask & interior).sum())


def test_vertices_with_fewer_than_three_faces_spread_zero():
    """Exactly 0, though rounding leaves up to 1e-8 rad in the eigenvalue: 200 random pillows
    (a triangle both ways round: every edge between two faces, no boundary), an open pair of
    triangles (boundary: NaN) and a vertex no face uses."""
    pillows = np.random.default_rng(0).normal(size=(600, 3))
    triangles = np.arange(600).reshape(-1, 3)
    positions = np.vstack([pillows, [[3, 0, 0], [4, 0, 0], [3, 1, 0], [4, 1, 1.0], [5, 5, 5]]])
    triangles = np.vstack([triangles, triangles[:, ::-1], [[600, 601, 602], [601, 603, 602]]]).astype(np.int32)
    spread = ruled_spread(positions, triangles)
    assert np.all(spread[:600] == 0.0) and np.all(np.isnan(spread[600:604])) and spread[604] == 0.0


def test_dihedral_angles_of_a_folded_sheet():
    positions, triangles = meshes.folded_sheet(rows=6, cols=7, angle_degrees=120.0)
    edges, count, _ = edges_of(triangles)
    inner = edges[count == 2]
    on_fold = np.all(np.isclose(positions[inner][:, :, 0], 1.0), axis=1)
    angles = dihedral_angles(positions, triangles, inner)
    assert np.allclose(angles[on_fold], np.radians(60.0)) and np.allclose(angles[~on_fold], 0.0, atol=1e-7)
    with pytest.raises(ValueError):
        dihedral_angles(positions, triangles, edges[count == 1][:1])

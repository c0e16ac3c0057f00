"""One-sided (non-orientable) and inconsistently wound meshes through the C ABI (issue 37, item 4).

The engine turns faces over so that neighbours agree (native/core/orientation.h), runs on that and
hands every per-face output back in the caller's winding: an inconsistently wound mesh gives its
consistently wound twin's result bit for bit, and a Möbius strip runs, and unfolds in one piece cut
once across."""
import numpy as np
import pytest

from devkit import meshes
from devkit.binding import native

# -- meshes ---------------------------------------------------------------------------------------


def moebius(across=6, around=120, radius=1.0, width=0.3, noise=0.0, irregular=False, seed=1):
    """A Möbius strip: `around` columns of `across` + 1 vertices round a circle of radius `radius`, the
    ruling of width `width` turning half a turn over the round (x = (R + s cos(t/2)) cos t, ...,
    s sin(t/2)); the last column joins the first upside down. irregular: the vertices moved along the
    surface by up to 0.3 of a cell and each cell's diagonal picked at random; noise: a uniform move of
    every vertex by up to this fraction of the mean edge length. Seeded."""
    rng = np.random.default_rng(seed)
    rows = across + 1
    j, i = np.meshgrid(np.arange(around, dtype=float), np.arange(rows, dtype=float), indexing="ij")
    if irregular:
        j = j + rng.uniform(-0.3, 0.3, j.shape)
        i = np.where((i > 0) & (i < across), i + rng.uniform(-0.3, 0.3, i.shape), i)
    t = 2 * np.pi * j / around
    s = width * (i / across - 0.5)
    r = radius + s * np.cos(t / 2)
    pos = np.stack([r * np.cos(t), r * np.sin(t), s * np.sin(t / 2)], -1).reshape(-1, 3)
    jj, ii = (x.ravel() for x in np.meshgrid(np.arange(around), np.arange(across), indexing="ij"))
    last = jj == around - 1
    a = jj * rows + ii
    c = a + 1
    b = np.where(last, across - ii, (jj + 1) * rows + ii)
    d = np.where(last, across - ii - 1, (jj + 1) * rows + ii + 1)
    split = (rng.random(len(a)) < 0.5 if irregular else (ii + jj) % 2 == 0)[:, None]
    first = np.where(split, np.stack([a, b, d], 1), np.stack([a, b, c], 1))
    second = np.where(split, np.stack([a, d, c], 1), np.stack([b, d, c], 1))
    tri = np.stack([first, second], 1).reshape(-1, 3).astype(np.int32)
    if noise:
        amplitude = noise * mean_edge_length(pos, tri)
        pos = pos + rng.uniform(-amplitude, amplitude, pos.shape)
    return pos, tri


def reflect(points, centre, angle):
    """Points (k, 2) reflected across the line through `centre` at `angle`."""
    d = np.array([np.cos(angle), np.sin(angle)])
    q = points - centre
    return centre + 2 * np.outer(q @ d, d) - q


def folded_moebius(across=4, per_panel=3, width=0.2, step=2.0, first=1.0):
    """A paper strip [0, 3 step] x [0, width] folded flat along three fold lines through (first + k step,
    width / 2) at +60, -60 and +60 degrees to it: the triangular Möbius band, whose ends meet upside down
    (the three reflections map (u, v) to (u - 3 step, width - v)). Planar panels meeting at creases:
    exactly developable. Columns: the square ends, the fold lines and per_panel - 1 lines between each two
    (their ends on the rims evenly spaced); the last column is the first upside down. Returns positions,
    triangles and the paper's length."""
    angles = np.radians([60.0, -60.0, 60.0])
    centres = first + step * np.arange(3)
    length = 3 * step
    half = width / 2
    keys = [(0.0, 0.0)] + [(c - half / np.tan(a), c + half / np.tan(a)) for c, a in zip(centres, angles)]
    keys.append((length, length))
    v = width * np.arange(across + 1) / across
    columns = []
    for k in range(4):
        for j in range(per_panel):
            x0, x1 = (keys[k][e] + j / per_panel * (keys[k + 1][e] - keys[k][e]) for e in (0, 1))
            p = np.stack([x0 + (x1 - x0) * v / width, v], 1)
            for fold in reversed(range(k)):  # the folds before the column, last first
                p = reflect(p, np.array([centres[fold], half]), angles[fold])
            columns.append(np.column_stack([p, np.zeros(len(v))]))
    pos = np.concatenate(columns)
    rows, n = across + 1, len(columns)
    jj, ii = (x.ravel() for x in np.meshgrid(np.arange(n), np.arange(across), indexing="ij"))
    last = jj == n - 1
    a = jj * rows + ii
    c = a + 1
    b = np.where(last, across - ii, (jj + 1) * rows + ii)
    d = np.where(last, across - ii - 1, (jj + 1) * rows + ii + 1)
    tri = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]).astype(np.int32)
    return pos, tri, length


def mean_edge_length(pos, tri):
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    return np.linalg.norm(pos[e[:, 0]] - pos[e[:, 1]], axis=1).mean()


def flipped(tri, faces):
    """The triangles with `faces` (a mask) turned over as the engine turns them: (a, b, c) -> (a, c, b)."""
    out = tri.copy()
    out[faces] = out[faces][:, [0, 2, 1]]
    return out


def normals(pos, tri):
    n = np.cross(pos[tri[:, 1]] - pos[tri[:, 0]], pos[tri[:, 2]] - pos[tri[:, 0]])
    return n / np.linalg.norm(n, axis=1)[:, None]


def same_direction_edges(tri):
    """Edges (a, b) that two faces both run a -> b."""
    directed = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    unique, count = np.unique(directed, axis=0, return_counts=True)
    return unique[count > 1]


def signed_uv_areas(uv):
    uv = uv.reshape(-1, 3, 2)
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def assert_corners_follow_the_caller(pos, tri, uv, tolerance):
    """Corner k of face f in the pattern is the caller's corner k: each flat edge as long as its 3D edge."""
    uv = uv.reshape(-1, 3, 2)
    for k in range(3):
        flat = np.linalg.norm(uv[:, (k + 1) % 3] - uv[:, k], axis=1)
        real = np.linalg.norm(pos[tri[:, (k + 1) % 3]] - pos[tri[:, k]], axis=1)
        assert np.abs(flat / real - 1).max() < tolerance


MOEBIUS = {
    # name: keyword arguments of moebius(); noise 1 to 5 % of the edge length
    "grid, 1 % noise": dict(noise=0.01, seed=1),
    "grid, 5 % noise": dict(noise=0.05, seed=2),
    "irregular, 3 % noise": dict(noise=0.03, irregular=True, seed=3),
    "irregular, 5 % noise, fine": dict(noise=0.05, irregular=True, seed=4, around=200, across=10),
}

# -- what the run says it turned ------------------------------------------------------------------


def test_the_run_says_what_it_turned_as_the_input_check_does(library):
    # The add-on tells the user what the engine turned from the run's result alone (ABI 10); before,
    # it ran the input check and the turning a second time to read it (~1 s at 1M faces).
    pos, tri = meshes.noisy_cylinder_patch()
    strip = moebius(noise=0.03, seed=6)
    cases = {
        "wound consistently": (pos, tri, ""),
        "one face turned": (pos, flipped(tri, np.arange(len(tri)) == 7), "1 of 690 triangles is wound the other way"),
        "a third turned": (pos, flipped(tri, np.arange(len(tri)) % 3 == 0), "230 of 690 triangles are wound"),
        "Möbius strip": strip + ("the surface is one-sided (like a Möbius strip): ",),
    }
    for name, (p, t, words) in cases.items():
        status, message = native.validate(p, t)
        note = native.run(p, t, params={"max_iterations": 2}).stats["orientation_note"]
        assert status == native.STATUS_OK and message == ("ok: " + note if note else "ok"), name
        assert note.startswith(words) and bool(note) == bool(words), (name, note)
    assert "a cut of 6 edges" in note and note.endswith("which the flat pattern opens")  # the strip, last


# -- inconsistently wound: the twin's result ------------------------------------------------------


@pytest.mark.parametrize("share", [0.3, 0.7])
def test_inconsistent_winding_gives_the_twins_result(library, share):
    pos, tri = meshes.noisy_cylinder_patch()
    rng = np.random.default_rng(5)
    turn = np.zeros(len(tri), bool)
    turn[rng.choice(len(tri), int(share * len(tri)), replace=False)] = True
    given = flipped(tri, turn)
    assert len(same_direction_edges(given)) > 0 and native.validate(pos, given)[0] == 0
    # Under half turned: the engine turns them back. Over half: it turns the others, and runs the
    # twin wound the other way round.
    twin = tri if share < 0.5 else flipped(tri, np.ones(len(tri), bool))
    engine_turned = turn if share < 0.5 else ~turn
    mine, theirs = native.run(pos, given), native.run(pos, twin)
    assert np.array_equal(mine.positions, theirs.positions)
    for key in ("result", "iterations", "mean_defect_after", "faces_turned_over", "flat_share_after", "patches"):
        assert mine.stats[key] == theirs.stats[key]
    assert np.array_equal(mine.patch_ids, theirs.patch_ids)
    # Target normals in the caller's winding: negated where the engine turned the face.
    sign = np.where(engine_turned, -1.0, 1.0)[:, None]
    assert np.array_equal(mine.target_normals, sign * theirs.target_normals)
    n = normals(mine.positions, given)
    assert np.median((n * mine.target_normals).sum(1)) > 0.99
    # The unfolding: the twin's, corners in the caller's order.
    a, b = (native.unfold(pos, t, params={"scale": 0}) for t in (given, twin))
    assert np.array_equal(a.piece_ids, b.piece_ids) and np.array_equal(a.face_strain, b.face_strain)
    swap = np.where(engine_turned[:, None], [0, 2, 1], [0, 1, 2])
    for mine_uv, twin_uv in ((a.corner_uvs, b.corner_uvs), (a.sheet_uvs, b.sheet_uvs)):
        assert np.array_equal(mine_uv, np.take_along_axis(twin_uv, swap[:, :, None], 1))
    assert_corners_follow_the_caller(pos, given, a.corner_uvs, 1e-2)
    # The pattern shows the side the engine's normals point to: the faces it turned run clockwise.
    assert np.array_equal(signed_uv_areas(a.corner_uvs) < 0, engine_turned)
    assert [s["vertices"].tolist() for s in a.seams] == [s["vertices"].tolist() for s in b.seams]


# -- one-sided: a Möbius strip ---------------------------------------------------------------------


def test_the_generators_are_one_sided():
    for kwargs in MOEBIUS.values():
        pos, tri = moebius(**kwargs)
        assert len(same_direction_edges(tri)) == kwargs.get("across", 6)
    pos, tri, length = folded_moebius()
    assert len(same_direction_edges(tri)) == 4
    # Exactly developable: every interior vertex's angles sum to 2 pi; the ends meet.
    angle = np.zeros(len(pos))
    for k in range(3):
        u, v = pos[tri[:, (k + 1) % 3]] - pos[tri[:, k]], pos[tri[:, (k + 2) % 3]] - pos[tri[:, k]]
        angle += np.bincount(tri[:, k], np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), (u * v).sum(1)), len(pos))
    interior = np.ones(len(pos), bool)
    interior[np.arange(len(pos)) % 5 == 0] = interior[np.arange(len(pos)) % 5 == 4] = False
    assert np.abs(angle[interior] - 2 * np.pi).max() < 1e-12
    assert length == 6.0


@pytest.mark.parametrize("name", sorted(MOEBIUS))
def test_a_noisy_moebius_strip_runs_and_unfolds_in_one_piece(library, name):
    pos, tri = moebius(**MOEBIUS[name])
    status, message = native.validate(pos, tri)
    assert status == 0, message
    result = native.run(pos, tri)
    st = result.stats
    assert st["result"] == native.RESULT_IMPROVED, st["result_message"]
    # No face turned over: each face's normal against its own before, in the caller's winding.
    assert st["faces_turned_over"] == 0
    assert ((normals(pos, tri) * normals(result.positions, tri)).sum(1) > 0).all()
    # Flat, or flat and ruled where the ruled finish traded a few flat vertices for ruled ones
    # (selection.h, ruled_finish_kept): the 5 % grid 99.5 % flat, 98.7 % flat and ruled.
    assert st["flat_share_after"] > st["flat_share_before"] and st["flat_share_after"] > 0.97
    assert st["result_origin"] == native.ORIGIN_RULED_FINISH or st["flat_share_after"] > 0.99
    assert np.linalg.norm(result.positions - pos, axis=1).max() <= st["move_limit"] * (1 + 1e-12)
    # Target normals in the caller's winding: beside each face's own normal, none opposite.
    cosines = (normals(result.positions, tri) * result.target_normals).sum(1)
    assert cosines.min() > 0 and np.median(cosines) > 0.99
    # Unfolded: one piece, cut once across the strip (a seam of the piece with itself about the width
    # long, both sides the same length), corners in the caller's order.
    pattern = native.unfold(result.positions, tri, result.patch_ids, params={"scale": 0})
    assert pattern.stats["pieces"] == 1, pattern.stats
    cuts = [s for s in pattern.seams if s["piece_a"] == s["piece_b"] == 0 and s["cut"]]
    assert len(cuts) == 1 and pattern.stats["seams"] == 1
    width = 0.3
    assert width * 0.95 < cuts[0]["length_3d"] < width * 1.1  # the shortest way across
    assert abs(cuts[0]["length_a"] / cuts[0]["length_3d"] - 1) < 1e-3
    assert abs(cuts[0]["length_b"] / cuts[0]["length_3d"] - 1) < 1e-3
    assert pattern.stats["cut_edges"] == cuts[0]["edges"]
    # A ruled finish keeps a few vertices just above the flat threshold: within the pattern's seam
    # tolerance (0.25 %), still one piece (the 5 % grid: 0.16 %).
    strain = 2.5e-3 if st["result_origin"] == native.ORIGIN_RULED_FINISH else 1e-3
    assert pattern.stats["max_strain"] < strain
    assert_corners_follow_the_caller(result.positions, tri, pattern.corner_uvs, strain)
    vertices = cuts[0]["vertices"]
    assert vertices.max() < len(pos) and np.array_equal(vertices[1:, 0], vertices[:-1, 1])


def test_an_exact_folded_moebius_band_is_already_developable_and_unfolds_to_its_paper(library):
    pos, tri, length = folded_moebius()
    result = native.run(pos, tri)
    assert result.stats["stop_reason"] == 0, result.stats["result_message"]
    assert np.array_equal(result.positions, pos)
    pattern = native.unfold(pos, tri, params={"scale": 0})
    st = pattern.stats
    assert st["pieces"] == 1 and st["seams"] == 1 and st["splits"] == 0, st
    (seam,) = pattern.seams
    assert seam["cut"] and seam["piece_a"] == seam["piece_b"] == 0 and seam["edges"] == st["cut_edges"] == 4
    assert seam["length_3d"] == pytest.approx(0.2, rel=1e-12)  # straight across the paper
    assert st["max_strain"] < 1e-9
    (piece,) = pattern.pieces
    # The paper strip: its area and outline.
    assert piece["area_flat"] == pytest.approx(0.2 * length, rel=1e-9)
    assert piece["outline_length"] == pytest.approx(2 * length + 2 * 0.2, rel=1e-9)
    assert_corners_follow_the_caller(pos, tri, pattern.corner_uvs, 1e-9)


def test_a_moebius_strip_wound_at_random_gives_the_same_result(library):
    # The faces' windings do not matter: any winding of the same strip runs the same mesh.
    pos, tri = moebius(noise=0.03, seed=6)
    rng = np.random.default_rng(6)
    shuffled = flipped(tri, rng.random(len(tri)) < 0.3)
    assert len(same_direction_edges(shuffled)) > 100
    a, b = native.run(pos, tri), native.run(pos, shuffled)
    assert np.array_equal(a.positions, b.positions)
    pattern = native.unfold(b.positions, shuffled, b.patch_ids, params={"scale": 0})
    assert pattern.stats["pieces"] == 1 and pattern.stats["seams"] == 1
    assert_corners_follow_the_caller(b.positions, shuffled, pattern.corner_uvs, 1e-3)

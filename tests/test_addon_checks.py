"""The add-on's own checks and verdicts (addon/checks.py: numpy, no bpy),
on seeded generated meshes, without Blender: what the engine is handed, where
a refused mesh is bad, the figures and when a result is a warning."""
import importlib.util
import pathlib
import re

import numpy as np
import pytest

spec = importlib.util.spec_from_file_location(
    "addon_checks", pathlib.Path(__file__).resolve().parents[1] / "addon" / "checks.py"
)
checks = importlib.util.module_from_spec(spec)
spec.loader.exec_module(checks)


def grid(n=6, m=5, seed=0, noise=0.0):
    """A height-field sheet of quads split into triangles, and its polygon of each triangle."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(m, dtype=float), indexing="ij")
    p = np.stack([x, y, noise * rng.normal(size=x.shape)], axis=-1).reshape(-1, 3)
    idx = np.arange(n * m).reshape(n, m)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    poly = np.concatenate([np.arange(len(quads))] * 2)
    return p, quads, tris, poly


def vertex_sets(polygons):
    return lambda i: frozenset(polygons[i])


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_triangle_lying_on_a_quad_is_dropped_and_identical_faces_are_kept(seed):
    p, quads, tris, poly = grid(seed=seed)
    rng = np.random.default_rng(seed)
    q = int(rng.integers(len(quads)))
    polygons = [tuple(f) for f in quads] + [tuple(quads[q][[0, 1, 2]])]  # a triangle on quad q
    t2 = np.vstack([tris, quads[q][[0, 1, 2]]])
    p2 = np.append(poly, len(quads))
    out, out_poly, dropped = checks.drop_shared_triangles(t2, p2, vertex_sets(polygons))
    assert dropped == 1 and len(out) == len(tris)
    assert len(out_poly) == len(out)
    # the same quad twice (identical faces, which validate() removes): left for the engine
    polygons = [tuple(f) for f in quads] + [tuple(quads[q])]
    t3 = np.vstack([tris, quads[q][[0, 1, 2]], quads[q][[0, 2, 3]]])
    p3 = np.append(poly, [len(quads)] * 2)
    out, _, dropped = checks.drop_shared_triangles(t3, p3, vertex_sets(polygons))
    assert dropped == 0 and len(out) == len(t3)
    assert checks.duplicate_polygons(t3, p3)[0] == (len(quads), q)


def test_bad_edges_find_every_fin_and_every_flipped_neighbour():
    p, quads, tris, poly = grid()
    fins = [(7, 8), (13, 14)]
    extra = [(a, b, len(p) + i) for i, (a, b) in enumerate(fins)]
    many, flipped = checks.bad_edges(np.vstack([tris, extra]))
    assert sorted(map(tuple, many)) == fins and len(flipped) == 0
    t = tris.copy()
    t[3] = t[3][::-1]
    many, flipped = checks.bad_edges(t)
    assert len(many) == 0 and len(flipped) == 3  # the flipped triangle's three edges


def test_degenerate_triangles_are_those_the_engine_refuses():
    p, _, tris, _ = grid()
    p = np.vstack([p, [[10, 10, 0], [11, 10, 0], [12, 10, 0]]])
    t = np.vstack([tris, [len(p) - 3, len(p) - 2, len(p) - 1], [0, 0, 1]])
    bad = checks.degenerate_triangles(p, t)
    assert list(np.nonzero(bad)[0]) == [len(tris), len(tris) + 1]


def test_figures_of_a_result():
    p, _, tris, _ = grid(noise=0.1, seed=4)
    after = p.copy()
    after[:, 2] = 0.0  # flattened
    interior = np.zeros(len(p), dtype=bool)
    interior[[7, 8, 12, 13]] = True
    d_before = np.full(len(p), 0.01)
    d_after = np.zeros(len(p))
    f = checks.figures(p, after, tris, interior, d_before, d_after)
    size = np.linalg.norm(p.max(0) - p.min(0))
    assert f["flat_before"] == 0.0 and f["flat_after"] == 1.0
    assert f["move_percent"] == pytest.approx(100 * np.abs(p[:, 2]).max() / size)
    assert f["faces_turned"] == 0
    assert not f["closed"]  # a grid has a boundary
    mirrored = p.copy()
    mirrored[:, 2] *= -1
    mirrored[:, 0] *= -1  # every face turned over
    assert checks.figures(p, mirrored, tris, interior, d_before, d_after)["faces_turned"] == len(tris)


STATS = {
    "mean_defect_before": 0.01,
    "mean_defect_after": 0.002,
    "change_percent": -80.0,
    "max_defect_before": 0.05,
    "max_defect_after": 0.01,
    "time_total_ms": 12.0,
    "stop_reason": 3,
}
FIG = {"flat_before": 0.1, "flat_after": 0.6, "move_percent": 1.5, "faces_turned": 0, "max_move": 0.02, "size": 1.0}


def test_an_improvement_is_info():
    level, verdict, message = checks.verdict("sheet", STATS, FIG)
    assert (level, verdict) == ("INFO", "IMPROVED")
    assert "flat 10 % \u2192 60 %" in message and "1.5 % of its size" in message


@pytest.mark.parametrize(
    "change, fig, words",
    [
        ({"mean_defect_after": 0.0104, "change_percent": 4.4}, {}, "curvature grew (+4.4 %)"),
        ({}, {"flat_after": 0.05}, "fewer vertices are flat"),
        ({}, {"faces_turned": 3}, "3 faces turned over"),
        # the engine's own warning: its mean fell, but its curvature gathered
        ({"max_defect_before": 3.73, "max_defect_after": 8.4}, {}, "largest curvature grew (3.73 → 8.4 rad)"),
    ],
)
def test_a_worse_figure_is_a_warning_with_what_to_try(change, fig, words):
    level, verdict, message = checks.verdict("torus", dict(STATS, **change), dict(FIG, **fig))
    assert (level, verdict) == ("WARNING", "WORSE")
    assert words in message and "Try" in message and "at 0" in message


@pytest.mark.parametrize(
    "closed, why", [(True, "a closed surface keeps its total curvature"), (False, "gave up gathered on fewer others")]
)
def test_gathered_curvature_is_explained_for_closed_and_open_meshes(closed, why):
    stats = dict(STATS, max_defect_before=0.005, max_defect_after=0.006)
    level, verdict, message = checks.verdict("elbow", stats, dict(FIG, closed=closed))
    assert verdict == "WORSE" and why in message


def unchanged_reasons():
    """DEV_UNCHANGED_* of native/api/developable.h: {name: value}."""
    header = (pathlib.Path(__file__).resolve().parents[1] / "native" / "api" / "developable.h").read_text()
    return {name: int(value) for name, value in re.findall(r"DEV_UNCHANGED_(\w+) = (\d+)", header)}


def test_the_reasons_with_nothing_to_do_are_the_engines():
    reasons = unchanged_reasons()
    assert len(reasons) == 7
    assert set(checks.NOTHING_TO_DO) == {
        reasons["ALREADY_DEVELOPABLE"],
        reasons["DEVELOPABLE_PIECEWISE"],
        reasons["ALREADY_FLAT"],
    }


@pytest.mark.parametrize(
    "reason, words",
    [
        ("ALREADY_DEVELOPABLE", "it is already developable."),
        ("DEVELOPABLE_PIECEWISE", "already developable piecewise"),
        ("ALREADY_FLAT", "every vertex is already flat"),
    ],
)
def test_an_already_developable_mesh_is_an_info_without_advice(reason, words):
    # The engine's message is not read: its wording may change.
    stats = dict(
        STATS,
        result=1,
        unchanged_reason=unchanged_reasons()[reason],
        result_message="",
        mean_defect_after=0.01,
        change_percent=0.0,
    )
    level, verdict, message = checks.verdict("pipe", stats, dict(FIG, max_move=0.0))
    assert (level, verdict) == ("INFO", "DEVELOPABLE")
    assert "nothing to do" in message and words in message and "Try" not in message


@pytest.mark.parametrize("reason", ["NO_VISIBLE_GAIN", "NO_BETTER_ITERATE", "REJECTED"])
def test_nothing_changed_is_a_warning_with_the_engines_reason(reason):
    stats = dict(
        STATS,
        result=1,
        unchanged_reason=unchanged_reasons()[reason],
        result_message="Returned the input unchanged: no iterate lowered its curvature.",
        mean_defect_after=0.01,
        change_percent=0.0,
    )
    level, verdict, message = checks.verdict("torus", stats, dict(FIG, max_move=0.0))
    assert (level, verdict) == ("WARNING", "UNCHANGED")
    assert message.startswith("torus: nothing changed. Try")
    # The engine's reason once, where the panel puts it on a line of its own.
    assert message.endswith(checks.ENGINE_WORDS + "Returned the input unchanged: no iterate lowered its curvature.")

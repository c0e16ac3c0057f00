"""The add-on's bpy-free core (addon/core: checks, verdict, colours, text), on
seeded generated meshes and synthetic engine reports, without Blender: what
the engine is handed, where a refused mesh is bad, one-sided and unwelded
meshes, flat faces, the curvature colours, the verdict and its advice, and
figures as the panel writes them."""
import importlib
import pathlib
import re
import sys

import numpy as np
import pytest

from addon.core import checks, colours, presets, text, verdict

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "blender_scripts"))
shapes = importlib.import_module("shapes")  # numpy only: the meshes the Blender scenarios use

HEADER = (pathlib.Path(__file__).resolve().parents[1] / "native" / "api" / "developable.h").read_text()


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


# -- what the engine is handed, what is wrong with a refused mesh --------------------


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


def test_non_manifold_edges_are_the_fins_and_a_flipped_face_is_none():
    p, quads, tris, poly = grid()
    fins = [(7, 8), (13, 14)]
    extra = [(a, b, len(p) + i) for i, (a, b) in enumerate(fins)]
    assert sorted(map(tuple, checks.non_manifold_edges(np.vstack([tris, extra])))) == fins
    t = tris.copy()
    t[3] = t[3][::-1]  # the engine turns it (core/orientation.h): nothing to refuse
    assert len(checks.non_manifold_edges(t)) == 0


def test_degenerate_triangles_are_those_the_engine_refuses():
    p, _, tris, _ = grid()
    p = np.vstack([p, [[10, 10, 0], [11, 10, 0], [12, 10, 0]]])
    t = np.vstack([tris, [len(p) - 3, len(p) - 2, len(p) - 1], [0, 0, 1]])
    bad = checks.degenerate_triangles(p, t)
    assert list(np.nonzero(bad)[0]) == [len(tris), len(tris) + 1]


def test_engine_triangle_numbers_become_blender_faces():
    p, quads, tris, poly = grid()
    _, words = checks.describe_problem(
        "sheet", "unfold sheet", 7, "INVALID_ARGUMENT", "triangle 30 lies flat over triangle 2", p, tris, poly
    )
    assert "face %d lies flat over face %d" % (poly[30], poly[2]) in words
    assert "triangle" not in words
    selection, _ = checks.describe_problem("sheet", "unfold sheet", 7, "INVALID_ARGUMENT", "triangle 30", p, tris, poly)
    assert list(selection[2]) == [poly[30]]


# -- welding, flat faces ----------------------------------------------------------


def test_unwelded_seams_are_found_and_welded_meshes_are_not():
    v, faces = shapes.unwelded_sheet(nu=12, nv=8, seam=6)
    tris, _ = shapes.triangulate(faces)
    found = checks.unwelded_vertices(v, checks.boundary_vertices(tris, len(v)))
    assert len(found) == 16  # the seam's 8 vertices on each side
    assert np.allclose(np.sort(v[found][:, 0]), v[found][0, 0])
    welded, wfaces = shapes.plate()
    t, _ = shapes.triangulate(wfaces)
    assert len(checks.unwelded_vertices(welded, checks.boundary_vertices(t, len(welded)))) == 0
    # a polygon soup: every vertex lies on another (bar the plate's corners)
    sv, sfaces = shapes.soup(welded, wfaces)
    st, _ = shapes.triangulate(sfaces)
    assert len(checks.unwelded_vertices(sv, checks.boundary_vertices(st, len(sv)))) == len(sv) - 4


def test_a_pair_straddling_a_grid_cell_is_found():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0]], float)
    tris = np.array([[0, 1, 2], [1, 3, 2], [4, 5, 3]])
    size = checks.diagonal(v)
    cell = checks.WELD_DISTANCE * size
    v = np.vstack([v, [1 + 0.4 * cell, 0.5 * cell + 1e-3 * cell, 0]])  # next to vertex 1, across a cell border
    v[1] = [1 - 0.4 * cell, 0.5 * cell - 1e-3 * cell, 0]
    t = np.vstack([tris, [[4, 6, 5]]])
    found = checks.unwelded_vertices(v, checks.boundary_vertices(t, len(v)))
    assert set(found) >= {1, 6}


@pytest.mark.parametrize(
    "shape, pieces",
    [(shapes.box(), 6), (shapes.prism(12), 14), (shapes.prism(5), 7)],
)
def test_a_box_and_a_prism_are_flat_faced(shape, pieces):
    v, faces = shape
    tris, _ = shapes.triangulate(faces)
    assert checks.flat_faced(v, tris, 1e-3) == pieces


def test_a_sheet_is_one_open_piece():
    _, _, tris, _ = grid()
    assert checks.sheet_like(tris)  # a disc
    band, faces = shapes.duct()
    assert checks.sheet_like(shapes.triangulate(faces)[0])  # a band (a tube open at both ends)
    box, faces = shapes.box()
    assert not checks.sheet_like(shapes.triangulate(faces)[0])  # closed
    two = np.vstack([tris, tris + tris.max() + 1])
    assert not checks.sheet_like(two)  # two parts
    v, faces = shapes.plate(6, 6)
    t, _ = shapes.triangulate([f for i, f in enumerate(faces) if i not in (6, 8, 16, 18)])
    assert checks.sheet_like(t)  # a plate with four windows is a sheet too


def test_triangles_and_noise_are_not_flat_faced():
    p, _, tris, _ = grid(noise=0.05, seed=3)
    assert checks.flat_faced(p, tris, 1e-3) == 0  # every triangle bends against its neighbours
    v, faces = shapes.box()
    tris, _ = shapes.triangulate(faces)
    v = v + np.random.default_rng(4).normal(scale=0.01, size=v.shape)  # a box made crooked
    assert checks.flat_faced(v, tris, 1e-3) == 0


# -- colours -----------------------------------------------------------------------


def test_a_developable_mesh_is_white_not_noise_red_and_blue():
    rng = np.random.default_rng(5)
    interior = np.ones(200, bool)
    noise = rng.normal(scale=2e-16, size=200)  # rounding noise on a flat plate
    scale = colours.colour_scale(noise, noise, interior, 1e-3)
    assert scale == 1e-3
    rgba = colours.defect_colours(noise, interior, scale)
    assert np.abs(rgba[:, :3] - 1.0).max() < 1e-9
    curved = rng.normal(scale=0.05, size=200)
    assert colours.colour_scale(curved, noise, interior, 1e-3) > 1e-3  # a curved input keeps its scale


# -- the verdict ---------------------------------------------------------------------


def stats(**change):
    """A synthetic dev_stats dict: an improved open sheet, nothing worse."""
    s = {
        "patches": 1,
        "result": 0,
        "unchanged_reason": 0,
        "worse_figures": 0,
        "result_message": "",
        "mean_defect_before": 0.01,
        "mean_defect_after": 0.002,
        "change_percent": -80.0,
        "max_defect_before": 0.05,
        "max_defect_after": 0.01,
        "flat_share_before": 0.1,
        "flat_share_after": 0.6,
        "ruled_share_before": 0.1,
        "ruled_share_after": 0.58,
        "crumpled_share_before": 0.0,
        "crumpled_share_after": 0.02,
        "faces_turned_over": 0,
        "max_vertex_move": 0.015,
        "move_limit": 0.02,
        "flat_threshold": 1e-3,
        "time_total_ms": 12.0,
    }
    s.update(change)
    return s


def header_enum(prefix):
    return {name: int(value) for name, value in re.findall(r"DEV_%s_(\w+) = (\d+)" % prefix, HEADER)}


def test_the_verdicts_numbers_are_the_engines():
    reasons, worse = header_enum("UNCHANGED"), header_enum("WORSE")
    assert (verdict.ALREADY_DEVELOPABLE, verdict.DEVELOPABLE_PIECEWISE, verdict.ALREADY_FLAT) == (
        reasons["ALREADY_DEVELOPABLE"],
        reasons["DEVELOPABLE_PIECEWISE"],
        reasons["ALREADY_FLAT"],
    )
    assert (verdict.NO_VISIBLE_GAIN, verdict.NO_BETTER_ITERATE, verdict.REJECTED) == (
        reasons["NO_VISIBLE_GAIN"],
        reasons["NO_BETTER_ITERATE"],
        reasons["REJECTED"],
    )
    assert worse == {
        "MEAN_DEFECT": verdict.WORSE_MEAN_DEFECT,
        "MAX_DEFECT": verdict.WORSE_MAX_DEFECT,
        "FLAT_SHARE": verdict.WORSE_FLAT_SHARE,
        "RULED_SHARE": verdict.WORSE_RULED_SHARE,
        "TURNED_FACES": verdict.WORSE_TURNED_FACES,
    }


def test_an_improvement_is_info_in_the_users_terms():
    v = verdict.verdict("sheet", stats(), verdict.Facts(size=1.0))
    assert (v.level, v.kind, v.key_value) == ("INFO", "IMPROVED", 1.0)
    assert "flat 10 % \u2192 60 %" in v.text and "1.5 % of its size" in v.text


@pytest.mark.parametrize(
    "flags, words",
    [
        (verdict.WORSE_FLAT_SHARE, "fewer vertices are flat"),
        (verdict.WORSE_RULED_SHARE, "fewer are flat and ruled"),
        (verdict.WORSE_TURNED_FACES, "3 faces turned over"),
    ],
)
def test_the_engines_worse_figures_are_a_warning_with_the_key_at_0(flags, words):
    s = stats(worse_figures=flags, faces_turned_over=3 if flags == verdict.WORSE_TURNED_FACES else 0)
    v = verdict.verdict("torus", s, verdict.Facts())
    assert (v.level, v.kind, v.key_value) == ("WARNING", "WORSE", 0.0)
    assert words in v.text and "Try" in v.text and "at 0" in v.text


def test_the_add_on_does_not_recompute_the_engines_judgement():
    """A grown mean the engine did not flag is no warning: the engine decides."""
    v = verdict.verdict("sheet", stats(mean_defect_after=0.02, change_percent=100.0), verdict.Facts())
    assert v.kind == "IMPROVED"


@pytest.mark.parametrize("closed, why", [(True, "a closed surface keeps its total curvature"), (False, "fewer others")])
def test_curvature_gathered_on_seams_is_a_usable_result(closed, why):
    s = stats(worse_figures=verdict.WORSE_MAX_DEFECT, max_defect_after=0.2)
    v = verdict.verdict("sphere", s, verdict.Facts(closed=closed, segmentation="ON", job="OBJECT"))
    assert (v.level, v.kind, v.key_value) == ("WARNING", "GATHERED", 1.0)
    assert why in v.text and "0.05 \u2192 0.2 rad" in v.text


def test_a_crumpled_result_is_a_warning_that_offers_what_helps():
    s = stats(flat_share_after=1.0, ruled_share_after=0.8, crumpled_share_after=0.2)
    v = verdict.verdict("duct", s, verdict.Facts(job="GENERAL"))
    assert (v.level, v.kind) == ("WARNING", "CRUMPLED")
    assert "Angle polish: Off" in v.text and "100 %" in v.text and "80 %" in v.text
    # a sheet the run cut into pieces: the one-piece job too
    v = verdict.verdict("duct", dict(s, patches=4), verdict.Facts(job="GENERAL"))
    assert "Clean up a scanned sheet" in v.text
    # never the job that ran, nor a setting already set
    v = verdict.verdict("duct", dict(s, patches=4), verdict.Facts(job="SHEET", segmentation="OFF", polish="OFF"))
    assert "Clean up a scanned sheet" not in v.text and "Angle polish" not in v.text
    assert "Shape may move" in v.text
    # a few crumpled vertices among many flat ones is a plain improvement
    s = stats(flat_share_after=1.0, ruled_share_after=0.96, crumpled_share_after=0.04)
    assert verdict.verdict("band", s, verdict.Facts()).kind == "IMPROVED"


@pytest.mark.parametrize("reason", ["ALREADY_DEVELOPABLE", "DEVELOPABLE_PIECEWISE", "ALREADY_FLAT"])
def test_nothing_to_do_is_info_without_advice(reason):
    s = stats(result=1, unchanged_reason=header_enum("UNCHANGED")[reason], max_vertex_move=0.0)
    v = verdict.verdict("pipe", s, verdict.Facts())
    assert (v.level, v.kind) == ("INFO", "DEVELOPABLE")
    assert "nothing to do" in v.text and "Try" not in v.text


def test_a_box_is_already_developable_piecewise():
    s = stats(result=1, unchanged_reason=verdict.NO_BETTER_ITERATE, result_message="Returned the input unchanged.")
    v = verdict.verdict("Cube", s, verdict.Facts(closed=True, flat_faces=6, job="OBJECT", segmentation="ON"))
    assert (v.level, v.kind) == ("INFO", "DEVELOPABLE")
    assert "already developable piecewise: its 6 faces are flat" in v.text
    assert v.engine == ""  # the engine's advice for triangles does not apply


@pytest.mark.parametrize("job", [key for key, _, _ in presets.PRESET_ITEMS])
@pytest.mark.parametrize("closed", [True, False])
def test_advice_after_nothing_changed_never_names_the_job_that_ran(job, closed):
    values = presets.settings_of(job) or presets.GENERAL
    facts = verdict.Facts(
        closed=closed,
        sheet=not closed,
        job=job,
        segmentation=values["segmentation"],
        keep_boundary=values["pin_boundary"],
    )
    for reason in (verdict.NO_VISIBLE_GAIN, verdict.NO_BETTER_ITERATE, verdict.REJECTED):
        v = verdict.verdict("thing", stats(result=1, unchanged_reason=reason), facts)
        assert v.kind == "UNCHANGED" and "Try" in v.text, v.text
        if job != "CUSTOM":
            assert "'%s'" % presets.LABELS[job] not in v.text, v.text
        if closed and values["segmentation"] == "ON":
            assert "Whole object into pieces" not in v.text and "more pieces" in v.text


# -- figures as the panel writes them ---------------------------------------------------


@pytest.mark.parametrize(
    "value, words",
    [(0.9992, "99.9 %"), (1.0, "100 %"), (0.0004, "< 0.1 %"), (0.004, "0.4 %"), (0.0, "0 %"), (0.5049, "50 %")],
)
def test_shares_never_round_to_what_they_are_not(value, words):
    assert text.share(value) == words


@pytest.mark.parametrize(
    "value, words", [(2.38e-07, "< 0.01 %"), (0.0238, "0.02 %"), (2.38, "2.4 %"), (23.8, "24 %"), (0.0, "0 %")]
)
def test_percentages_have_sensible_digits(value, words):
    assert text.percent(value) == words
    assert "e" not in text.percent(value) and "e" not in text.signed_percent(value)


def test_wrapping_keeps_words_whole_and_lines_within_the_width():
    sentence = "Large mesh: the run takes about 21 s to 2 min on two cores"
    lines = text.wrap(sentence, 20)
    assert " ".join(lines) == sentence and max(map(len, lines)) <= 20

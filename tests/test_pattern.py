"""Flat patterns through the C ABI (dev_unfold, bound by addon/core/native.py):
exact developables unfold isometrically, strain is reported honestly, the
layout keeps pieces apart, the seams match, the SVG is at true scale."""
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from devkit import meshes
from devkit.obj import read_obj
from devkit import families
from pattern_support import (
    edge_strain,
    face_areas,
    holed_plate,
    label_boxes,
    load_native,
    nearly_developable,
    overlapping_triangles,
    read_png,
    signed_areas,
    square_to_round,
    strain_bound,
)

SEAM_COLOUR = "#c0392b"


@pytest.fixture(scope="module")
def native(library_path):
    return load_native(library_path)


def exact_shapes():
    shapes = {
        "plane": meshes.plane(),
        "cylinder band": meshes.cylinder(),
        "open cylinder": meshes.cylinder(angle=2.5),
        "cone band": meshes.cone(),
    }
    for seed in (11, 12, 13):
        shapes["curved fold %d" % seed] = meshes.curved_fold(seed)
    return shapes


def dihedral_range_degrees(positions, triangles):
    """Largest bend between two faces sharing an edge, degrees (0 = flat)."""
    n = np.cross(
        positions[triangles[:, 1]] - positions[triangles[:, 0]], positions[triangles[:, 2]] - positions[triangles[:, 0]]
    )
    n /= np.linalg.norm(n, axis=1)[:, None]
    faces_of = {}
    for f, t in enumerate(triangles):
        for k in range(3):
            faces_of.setdefault(tuple(sorted((t[k], t[(k + 1) % 3]))), []).append(f)
    pairs = np.array([v for v in faces_of.values() if len(v) == 2])
    cos = np.clip((n[pairs[:, 0]] * n[pairs[:, 1]]).sum(1), -1, 1)
    return np.degrees(np.arccos(cos)).max()


def test_curved_fold_is_folded_and_flat():
    # The generator's promise: intrinsically flat, yet really folded.
    for seed in (11, 12, 13):
        pos, tri = meshes.curved_fold(seed)
        angle = np.zeros(len(pos))
        for k in range(3):
            u = pos[tri[:, (k + 1) % 3]] - pos[tri[:, k]]
            v = pos[tri[:, (k + 2) % 3]] - pos[tri[:, k]]
            angle += np.bincount(
                tri[:, k], np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), (u * v).sum(1)), len(pos)
            )
        interior = np.abs(angle - 2 * np.pi) < 1.0  # boundary vertices sum to about pi or less
        assert interior.sum() > 100
        assert np.abs(angle[interior] - 2 * np.pi).max() < 1e-12
        assert dihedral_range_degrees(pos, tri) > 20.0


@pytest.mark.parametrize("name", list(exact_shapes()))
def test_exact_developables_unfold_isometrically(native, name):
    pos, tri = exact_shapes()[name]
    pattern = native.unfold(pos, tri, params={"scale": 0})
    st = pattern.stats
    assert st["pieces"] == 1 and st["splits"] == 0
    assert st["max_strain"] < 1e-6
    piece = pattern.pieces[0]
    area = face_areas(pos, tri).sum()
    assert abs(piece["area_flat"] / area - 1) < 1e-6
    assert abs(piece["area_3d"] / area - 1) < 1e-12
    # Independent of the engine's own figures: edge lengths and orientation.
    assert edge_strain(pos, tri, pattern.corner_uvs).max() < 1e-6
    assert (signed_areas(pattern.corner_uvs) > 0).all()
    closed = name in ("cylinder band", "cone band")
    assert (st["cut_edges"] > 0) == closed
    if closed:  # one cut across the band, matched on both sides
        assert st["seams"] == 1 and pattern.seams[0]["cut"] == 1
        seam = pattern.seams[0]
        assert abs(seam["length_a"] - seam["length_3d"]) < 1e-9 * seam["length_3d"]
        assert abs(seam["length_b"] - seam["length_3d"]) < 1e-9 * seam["length_3d"]


def test_patches_become_pieces_with_a_matched_border(native):
    pos, tri, part = meshes.cylinder_cone()
    pattern = native.unfold(pos, tri, part, params={"scale": 0})
    assert sorted(p["patch"] for p in pattern.pieces) == [0, 1]
    assert pattern.stats["max_strain"] < 1e-6
    borders = [s for s in pattern.seams if not s["cut"]]
    assert len(borders) == 1 and borders[0]["edges"] == 40  # the ring between cylinder and cone
    assert abs(borders[0]["length_a"] / borders[0]["length_b"] - 1) < 1e-9


@pytest.mark.parametrize("seed", [21, 22, 23])
def test_noisy_developable_after_the_engine(native, seed):
    pos, tri = meshes.noisy_cylinder_patch(seed=seed)
    result = native.run(pos, tri)
    pattern = native.unfold(result.positions, tri, result.patch_ids, params={"layout": 0})
    assert pattern.stats["mean_strain"] < 1e-3
    assert (signed_areas(pattern.corner_uvs) > 0).all()


def test_sphere_caps_report_growing_strain(native):
    # Unsplit (no seam tolerance): one piece whose strain grows with the cap.
    strains, areas = [], []
    for angle in (15, 30, 60, 90, 120):
        pos, tri = meshes.sphere_cap(angle)
        pattern = native.unfold(pos, tri, params={"layout": 0, "seam_tolerance": 0})
        assert pattern.stats["pieces"] == 1
        assert (signed_areas(pattern.corner_uvs) > 0).all()
        strains.append(pattern.stats["max_strain"])
        areas.append(abs(pattern.pieces[0]["area_change"]))
        # The figure is the truth about the flat map.
        assert np.isclose(edge_strain(pos, tri, pattern.corner_uvs).max(), strains[-1], rtol=1e-9)
    assert all(b > a for a, b in zip(strains, strains[1:])), strains
    assert all(b > a for a, b in zip(areas, areas[1:])), areas
    assert strains[0] > 1e-3 and strains[-1] > 0.3
    # With the default seam tolerance the cap is split instead, more for larger caps.
    counts = [native.unfold(*meshes.sphere_cap(a), params={"layout": 0}).stats["pieces"] for a in (15, 60, 120)]
    assert counts[0] < counts[1] < counts[2]


def piece_bboxes(pattern):
    boxes = []
    for p in range(len(pattern.pieces)):
        c = pattern.sheet_uvs[pattern.piece_ids == p].reshape(-1, 2)
        boxes.append((pattern.pieces[p]["sheet"], c.min(0), c.max(0)))
    return boxes


def seam_labels_in_svgs(files):
    labels = []
    for path in files:
        for text in ET.parse(path).getroot().iter("{http://www.w3.org/2000/svg}text"):
            if text.get("fill") == SEAM_COLOUR:
                labels.append(text.text)
    return labels


@pytest.fixture(scope="module")
def woman_result(native, meshes_dir):
    pos, tri = read_obj(meshes_dir / "human_woman.obj")
    return native.run(pos, tri), tri  # the engine with its defaults


@pytest.fixture(scope="module")
def woman_pattern(native, woman_result, tmp_path_factory):
    result, tri = woman_result
    out = tmp_path_factory.mktemp("woman") / "woman.svg"
    pattern = native.unfold(result.positions, tri, result.patch_ids, params={"scale": 0}, svg_path=str(out))
    return result.positions, tri, pattern


def test_human_woman_pieces_lie_flat(woman_pattern):
    pos, tri, pattern = woman_pattern
    assert len(pattern.pieces) > 1
    assert (signed_areas(pattern.corner_uvs) > 0).all()
    assert (signed_areas(pattern.sheet_uvs) < 0).all()  # y down on the sheet: same turn, not mirrored
    for p in range(len(pattern.pieces)):
        faces = np.flatnonzero(pattern.piece_ids == p)
        assert overlapping_triangles(pattern.corner_uvs, faces) == [], "piece %d overlaps itself" % p
    strain = edge_strain(pos, tri, pattern.corner_uvs)
    assert np.isclose(strain.max(), pattern.stats["max_strain"], rtol=1e-9)


def test_human_woman_layout_keeps_pieces_apart(woman_pattern):
    _, _, pattern = woman_pattern
    margin, width, height = 10.0, 210.0, 297.0
    boxes = piece_bboxes(pattern)
    for sheet, lo, hi in boxes:
        assert lo.min() >= margin - 1e-9 and hi[0] <= width - margin + 1e-9 and hi[1] <= height - margin
    # Boxes on one sheet apart, hence the polygons inside them too.
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            if boxes[i][0] != boxes[j][0]:
                continue
            apart = (boxes[i][2] < boxes[j][1]).any() or (boxes[j][2] < boxes[i][1]).any()
            assert apart, "pieces %d and %d overlap on sheet %d" % (i, j, boxes[i][0])
    # The piece sizes are the true sizes at the scale used.
    scale_mm = pattern.stats["scale"] * 1000.0
    piece = max(range(len(pattern.pieces)), key=lambda p: pattern.pieces[p]["area_3d"])
    flat = pattern.corner_uvs[pattern.piece_ids == piece].reshape(-1, 2)
    sheet = pattern.sheet_uvs[pattern.piece_ids == piece].reshape(-1, 2)
    d_flat = np.linalg.norm(flat[:, None] - flat[None], axis=2).max()
    d_sheet = np.linalg.norm(sheet[:, None] - sheet[None], axis=2).max()
    assert abs(d_sheet / (d_flat * scale_mm) - 1) < 1e-9


def test_human_woman_seams_match(woman_pattern):
    pos, tri, pattern = woman_pattern
    assert pattern.seams
    for seam in pattern.seams:
        assert abs(seam["length_a"] - seam["length_b"]) <= 0.005 * seam["length_3d"], seam
        edges = seam["vertices"]
        assert np.isclose(np.linalg.norm(pos[edges[:, 0]] - pos[edges[:, 1]], axis=1).sum(), seam["length_3d"])
    # A seam's label is on its sides where there is room beside its notch
    # (never over another label: test_labels_do_not_overlap), at most twice.
    labels = seam_labels_in_svgs(pattern.files)
    counts = {}
    for text in labels:
        counts[text] = counts.get(text, 0) + 1
    assert set(counts) <= {s["label"] for s in pattern.seams} and max(counts.values()) <= 2
    assert len(labels) >= 0.8 * 2 * len(pattern.seams)


def test_face_groups_stay_together(native):
    # A noisy sheet must be split; triangles of one quad (a group) never part.
    pos, tri = meshes.plane(rows=14, cols=14, size=2.0)
    pos = meshes.add_noise(pos, 0.08, seed=31)
    quads = np.arange(len(tri)) // 2  # grid_triangles emits the two triangles of a quad in a row
    free = native.unfold(pos, tri, params={"scale": 0})
    grouped = native.unfold(pos, tri, params={"scale": 0}, face_groups=quads)
    assert free.stats["pieces"] > 1 and grouped.stats["pieces"] > 1
    ids = grouped.piece_ids
    assert (ids[0::2] == ids[1::2]).all()
    assert (signed_areas(grouped.corner_uvs) > 0).all()
    # No seam runs along a quad's diagonal.
    diagonal = {tuple(sorted(set(tri[2 * q]) & set(tri[2 * q + 1]))) for q in range(len(tri) // 2)}
    for seam in grouped.seams:
        for a, b in seam["vertices"]:
            assert tuple(sorted((a, b))) not in diagonal


def test_seams_follow_pieces(native):
    # Two pieces of one cut band and two patches: each seam's sides are where it says.
    pos, tri, part = meshes.cylinder_cone()
    pattern = native.unfold(pos, tri, part, params={"layout": 0})
    piece = pattern.piece_ids
    for seam in pattern.seams:
        for a, b in seam["vertices"]:
            left = [f for f in range(len(tri)) if any(tri[f][k] == a and tri[f][(k + 1) % 3] == b for k in range(3))]
            right = [f for f in range(len(tri)) if any(tri[f][k] == b and tri[f][(k + 1) % 3] == a for k in range(3))]
            assert piece[left[0]] == seam["piece_a"] and piece[right[0]] == seam["piece_b"]


RSVG = shutil.which("rsvg-convert")


def rasterise(svg, png, dpi):
    subprocess.run([RSVG, "-d", str(dpi), "-p", str(dpi), "-o", str(png), str(svg)], check=True)
    return read_png(png)


@pytest.mark.skipif(RSVG is None, reason="rsvg-convert (librsvg2-bin) is not installed")
def test_scale_is_true_on_the_rasterised_sheet(native, tmp_path):
    # A 10 cm x 5 cm plane in metres, 1:1 on A4, rasterised at 254 dpi (10 px per mm).
    pos, tri = meshes.plane(rows=6, cols=11, size=0.1)
    pos[:, 1] *= 0.05 / pos[:, 1].max()
    svg = tmp_path / "plane.svg"
    pattern = native.unfold(pos, tri, params={"scale": 1.0, "unit_name": "m"}, svg_path=str(svg))
    assert pattern.files == [str(svg)]
    root = ET.parse(svg).getroot()
    assert root.get("width") == "210mm" and root.get("height") == "297mm"
    image = rasterise(svg, tmp_path / "plane.png", 254)
    assert image.shape[:2] == (2970, 2100)
    rgb = image[..., :3].astype(int)
    fill = np.abs(rgb - [0xDB, 0xE8, 0xF6]).sum(axis=2) < 12  # the piece's fill colour
    ys, xs = np.nonzero(fill)
    width_px = xs.max() - xs.min() + 1
    height_px = ys.max() - ys.min() + 1
    # The 0.2 mm outline is drawn on the edge: the fill inside it is 0.1 mm short on each side.
    assert abs(width_px - 1000) <= 4 and abs(height_px - 500) <= 4, (width_px, height_px)
    # The same piece in centimetres (the model unit as an option) at 1:2.
    svg_cm = tmp_path / "plane_cm.svg"
    native.unfold(pos * 100, tri, params={"scale": 0.5, "unit_name": "cm"}, svg_path=str(svg_cm))
    rgb = rasterise(svg_cm, tmp_path / "plane_cm.png", 254)[..., :3].astype(int)
    ys, xs = np.nonzero(np.abs(rgb - [0xDB, 0xE8, 0xF6]).sum(axis=2) < 12)
    assert abs(xs.max() - xs.min() + 1 - 500) <= 4 and abs(ys.max() - ys.min() + 1 - 250) <= 4


SVG = "{http://www.w3.org/2000/svg}"


def svg_paths(path, group):
    """piece label -> (k, 2) corners of the path of that piece in the SVG group."""
    out = {}
    for g in ET.parse(path).getroot().iter(SVG + "g"):
        if g.get("id") != group:
            continue
        for node in g.iter(SVG + "path"):
            numbers = [float(x) for x in node.get("d").replace("M", " ").replace("L", " ").replace("Z", " ").split()]
            out[node.get("id").split("-", 1)[1]] = np.array(numbers).reshape(-1, 2)
    return out


def inside_polygon(points, polygon):
    """Even-odd test of each point against the closed polygon."""
    x, y = points[:, 0][:, None], points[:, 1][:, None]
    ax, ay = polygon[:, 0][None], polygon[:, 1][None]
    bx, by = np.roll(polygon[:, 0], -1)[None], np.roll(polygon[:, 1], -1)[None]
    crosses = ((ay > y) != (by > y)) & (x < (bx - ax) * (y - ay) / np.where(by != ay, by - ay, 1) + ax)
    return crosses.sum(axis=1) % 2 == 1


def distance_to_polyline(points, polygon):
    a, b = polygon[None], np.roll(polygon, -1, axis=0)[None]
    e = b - a
    t = np.clip(((points[:, None] - a) * e).sum(2) / (e * e).sum(2), 0, 1)
    return np.linalg.norm(a + t[..., None] * e - points[:, None], axis=2).min(axis=1)


def test_seam_allowance_surrounds_every_piece(native, woman_result, woman_pattern, tmp_path):
    # human_woman's ~950 pieces, many with hollows and slots: every cut line
    # holds its piece's seam line at least the allowance away, and the cut
    # lines keep the layout's spacing.
    (engine, tri), (_, _, pattern) = woman_result, woman_pattern
    allowance, spacing = 3.0, 4.0
    out = tmp_path / "woman.svg"
    result = native.unfold(
        engine.positions, tri, engine.patch_ids, params={"scale": 0, "seam_allowance_mm": allowance}, svg_path=str(out)
    )
    assert result.stats["cut_lines_from_hull"] == 0
    assert result.stats["pieces"] == pattern.stats["pieces"]
    boxes = []
    for path in result.files:
        cut, seam = svg_paths(path, "cut-lines"), svg_paths(path, "seam-lines")
        assert cut.keys() == seam.keys() and cut
        for label, line in cut.items():
            outline = seam[label]
            assert inside_polygon(outline, line).all(), label
            assert distance_to_polyline(outline, line).min() >= allowance - 0.011, label
            boxes.append((path, line.min(0), line.max(0)))
    assert len(boxes) == result.stats["pieces"]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            if boxes[i][0] == boxes[j][0]:
                gap = np.maximum(boxes[j][1] - boxes[i][2], boxes[i][1] - boxes[j][2]).max()
                assert gap >= spacing - 1e-6, (i, j)


def polygon_area(polygon):
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * (x * np.roll(y, -1) - np.roll(x, -1) * y).sum()


def self_crossings(polygon, tolerance=1e-3):
    """Pairs of non-adjacent edges of the closed polygon that cross properly: each edge's ends more
    than `tolerance` (mm; the SVG rounds to 1e-4) on either side of the other's line."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    e = b - a

    def side(p, q, r):
        cross = (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
        distance = cross / np.maximum(np.linalg.norm(q - p, axis=-1), 1e-300)
        return np.where(np.abs(distance) > tolerance, np.sign(distance), 0)

    A, B = a[:, None], b[:, None]
    C, D = a[None], b[None]
    cross = (side(A, B, C) * side(A, B, D) < 0) & (side(C, D, A) * side(C, D, B) < 0)
    n = len(polygon)
    i, j = np.nonzero(np.triu(cross, 2))
    return [(x, y) for x, y in zip(i, j) if not (x == 0 and y == n - 1)] if len(e) else []


def test_glue_tabs_on_every_piece_that_has_room(native, woman_result, tmp_path):
    # human_woman's pattern with 3 mm tabs: each cut line a simple polygon
    # holding its piece, every seam tabbed or counted as dropped. Seams
    # without room on side a try side b: 256 of 2284 were left without a tab
    # on side a alone, 77 with side b. Of the thinned pieces' pattern (424
    # pieces, 1224 seams, scale 1:2) 52 had room on neither side (4.2 %);
    # with its pieces still curved inside split (400 pieces, 1171 seams, more
    # of them short) 83 (7.1 %).
    engine, tri = woman_result
    out = tmp_path / "woman.svg"
    result = native.unfold(
        engine.positions, tri, engine.patch_ids, params={"scale": 0, "glue_tabs_mm": 3.0}, svg_path=str(out)
    )
    st = result.stats
    assert st["glue_tabs"] >= 0.95 * st["seams"] and st["glue_tabs"] + st["glue_tabs_dropped"] >= st["seams"]
    assert st["glue_tabs_dropped"] <= 0.08 * st["seams"]
    folds = 0
    for path in result.files:
        cut, pieces = svg_paths(path, "cut-lines"), svg_paths(path, "tabbed-pieces")
        assert cut.keys() == pieces.keys() and cut
        for label, line in cut.items():
            assert self_crossings(line) == [], label
            assert (np.linalg.norm(line - np.roll(line, -1, axis=0), axis=1) > 0).all(), label  # no segment of length 0
            corners = pieces[label]  # on the cut line (untabbed) or inside it (a tab's fold)
            on = distance_to_polyline(corners, line) < 1e-6
            assert (on | inside_polygon(corners, line)).all(), label
            assert abs(polygon_area(line)) >= abs(polygon_area(corners)) - 1e-9, label
        folds += sum(
            1
            for g in ET.parse(path).getroot().iter(SVG + "g")
            if g.get("id") == "fold-lines"
            for _ in g.iter(SVG + "path")
        )
    assert folds == st["glue_tabs"]
    with pytest.raises(native.EngineError) as err:
        native.unfold(
            engine.positions, tri, engine.patch_ids, params={"scale": 0, "glue_tabs_mm": 3.0, "seam_allowance_mm": 3.0}
        )
    assert "not both" in err.value.message


@pytest.mark.skipif(RSVG is None, reason="rsvg-convert (librsvg2-bin) is not installed")
def test_seam_allowance_on_the_rasterised_sheet(native, tmp_path):
    # The 10 cm x 5 cm plane with a 10 mm allowance: cut 120 x 70 mm with
    # round corners around the 100 x 50 mm piece, at 10 px per mm.
    pos, tri = meshes.plane(rows=6, cols=11, size=0.1)
    pos[:, 1] *= 0.05 / pos[:, 1].max()
    svg = tmp_path / "plane.svg"
    native.unfold(pos, tri, params={"scale": 1.0, "seam_allowance_mm": 10.0}, svg_path=str(svg))
    rgb = rasterise(svg, tmp_path / "plane.png", 254)[..., :3].astype(int)
    piece = np.abs(rgb - [0xDB, 0xE8, 0xF6]).sum(axis=2) < 12
    band = np.abs(rgb - [0xEE, 0xF4, 0xFB]).sum(axis=2) < 12
    ys, xs = np.nonzero(piece)
    assert abs(xs.max() - xs.min() + 1 - 1000) <= 4 and abs(ys.max() - ys.min() + 1 - 500) <= 4
    ys, xs = np.nonzero(band)
    assert abs(xs.max() - xs.min() + 1 - 1200) <= 4 and abs(ys.max() - ys.min() + 1 - 700) <= 4
    # Round corners: the corner of the cut line's box is outside, 3 mm in along the diagonal inside.
    x0, y0 = xs.min(), ys.min()
    assert not band[y0 + 5, x0 + 5] and band[y0 + 30, x0 + 30]
    assert len(svg_paths(svg, "seam-lines")) == 1


@pytest.mark.skipif(RSVG is None, reason="rsvg-convert (librsvg2-bin) is not installed")
def test_rasterised_sheets_are_not_blank(woman_pattern, tmp_path):
    _, _, pattern = woman_pattern
    assert len(pattern.files) == pattern.stats["sheets"] >= 1
    for i, svg in enumerate(pattern.files):
        image = rasterise(svg, tmp_path / ("sheet%d.png" % i), 50)
        # rsvg-convert rounds the pixel size up.
        assert image.shape[:2] == (int(np.ceil(297 / 25.4 * 50)), int(np.ceil(210 / 25.4 * 50)))
        ink = (image[..., :3].astype(int).sum(axis=2) < 3 * 250).mean()
        assert ink > 0.01, "sheet %s is blank" % svg


def test_bad_input_gets_a_status(native, tmp_path):
    pos, tri = meshes.plane()
    with pytest.raises(native.EngineError) as err:
        native.unfold(pos, tri, np.full(len(tri), -1))
    assert err.value.status_name == "INVALID_ARGUMENT" and "negative" in err.value.message
    with pytest.raises(native.EngineError) as err:
        native.unfold(pos, np.vstack([tri, tri[:1]]))
    assert err.value.status_name == "DUPLICATE_TRIANGLE"
    with pytest.raises(native.EngineError) as err:  # a 2 m x 1.6 m plane at 1:1 on A4
        native.unfold(pos, tri)
    assert err.value.status_name == "INVALID_ARGUMENT" and "1:10" in err.value.message
    for bad in (
        {"sheet_width_mm": 0},
        {"scale": -1},
        {"margin_mm": 200},
        {"seam_tolerance": -1},
        {"seam_allowance_mm": -1},
        {"seam_allowance_mm": float("nan")},
        {"glue_tabs_mm": -2},
    ):
        with pytest.raises(native.EngineError) as err:
            native.unfold(pos, tri, params=dict(bad, scale=bad.get("scale", 0)))
        assert err.value.status_name == "INVALID_ARGUMENT"
    with pytest.raises(native.EngineError) as err:
        native.unfold(pos, tri, params={"scale": 0}, svg_path=str(tmp_path / "missing" / "x.svg"))
    assert err.value.status_name == "INVALID_ARGUMENT" and "cannot write" in err.value.message


# The SVG writes coordinates to 1e-4 mm and turns to 1e-4 degrees: boxes read back from it
# may cross by a few 1e-5 mm where the engine placed them touching (human_woman's pattern, two
# labels by 3e-5 mm). A thousandth of a millimetre is far below what a printer draws.
SVG_ROUNDING_MM = 1e-3


def overlapping_pairs(boxes):
    """Pairs of (x0, y0, x1, y1) boxes whose insides overlap by more than the SVG's rounding
    (touching is apart), on a grid."""
    cells, pairs = {}, set()
    for i, (x0, y0, x1, y1) in enumerate(boxes):
        for cx in range(int(np.floor(x0 / 5)), int(np.floor(x1 / 5)) + 1):
            for cy in range(int(np.floor(y0 / 5)), int(np.floor(y1 / 5)) + 1):
                for j in cells.setdefault((cx, cy), []):
                    a = boxes[j]
                    tol = SVG_ROUNDING_MM
                    if x0 < a[2] - tol and a[0] < x1 - tol and y0 < a[3] - tol and a[1] < y1 - tol:
                        pairs.add((j, i))
                cells[(cx, cy)].append(i)
    return pairs


def test_labels_do_not_overlap(woman_pattern):
    # human_woman's pieces after the engine, their labels and both sides'
    # seam labels: no two boxes (0.8 em per glyph, 1.2 em high) overlap.
    _, _, pattern = woman_pattern
    for path in pattern.files:
        boxes = label_boxes(path)
        assert len(boxes) > 10
        assert overlapping_pairs(boxes) == set(), path


def test_label_overlap_check_can_fail():
    assert overlapping_pairs([(0, 0, 2, 1), (1.5, 0.5, 3, 2), (3, 0, 4, 1)]) == {(0, 1)}


def flat_patches(positions, triangles, patch_ids):
    """Whether every inner vertex of every patch is flat (|defect| < 1e-3)."""
    for patch in np.unique(patch_ids):
        defect, inner = families.angle_defects(positions, triangles[patch_ids == patch])
        if (np.abs(defect[inner]) >= 1e-3).any():
            return False
    return True


# Held-out seeds: the rules were measured on human_woman, spot, sphere caps and
# a bent sheet of seed 1, not on these. (A tangent developable of a helix is
# left out: its development can wind around and overlap itself, and is split
# then, as it must be.)
FAMILY_CASES = [
    ("cylinder_patch", 301),
    ("cone_patch", 302),
    ("generalized_cone", 303),
    ("generalized_cylinder", 304),
    ("bent_sheet", 305),
    ("curved_fold", 306),
    ("plane", 307),
    ("cone_band", 308),
]


@pytest.mark.parametrize("family,seed", FAMILY_CASES)
def test_noisy_developables_unfold_into_their_patches(native, family, seed):
    # A noisy developable of any triangulation after the engine: each patch
    # that is (nearly) developable is one piece, its strain within the stated
    # bound (strain_bound: the rule of docs/pattern.md measured here from the
    # mesh).
    mesh = families.random_case(family, seed, faces=(800, 3000))
    result = native.run(mesh.positions, mesh.triangles)
    tri = mesh.triangles
    pattern = native.unfold(result.positions, tri, result.patch_ids, params={"layout": 0})
    strain = edge_strain(result.positions, tri, pattern.corner_uvs).max(axis=1)
    for patch in np.unique(result.patch_ids):
        faces = result.patch_ids == patch
        if not nearly_developable(result.positions, tri[faces]):
            continue  # the tolerance decides
        assert len(np.unique(pattern.piece_ids[faces])) == 1, (family, seed, mesh.triangulation, patch)
        assert strain[faces].max() <= strain_bound(result.positions, tri[faces]) + 1e-12
    assert flat_patches(result.positions, tri, result.patch_ids) or family == "cone_band"
    assert (signed_areas(pattern.corner_uvs) > 0).all()


def test_bent_sheet_is_one_piece(native):
    # A bent sheet of 20k faces, noise 2 %, after the engine: one piece.
    mesh = families.make("bent_sheet", "irregular", faces=20000, noise=0.02, seed=311)
    result = native.run(mesh.positions, mesh.triangles)
    pattern = native.unfold(result.positions, mesh.triangles, result.patch_ids, params={"layout": 0})
    assert flat_patches(result.positions, mesh.triangles, result.patch_ids)
    assert pattern.stats["pieces"] == result.stats["patches"] == 1
    assert pattern.stats["max_strain"] <= strain_bound(result.positions, mesh.triangles)


@pytest.mark.parametrize("seed", [4, 5, 6, 7])
def test_noisy_duct_is_one_piece(native, seed):
    # A lofted square-to-round transition with 2 % noise, after the engine: one
    # piece (cut once across) when its vertices that are not flat (the engine
    # leaves a few at 1-3e-3 rad on some seeds) need no more strain than the
    # tolerance together, within the bound; as it is (not developable) it
    # needs tens of pieces.
    pos, tri = square_to_round(seed=seed)
    result = native.run(pos, tri)
    pattern = native.unfold(result.positions, tri, result.patch_ids, params={"layout": 0})
    assert nearly_developable(result.positions, tri)
    bound = strain_bound(result.positions, tri)
    assert pattern.stats["pieces"] == 1 and pattern.stats["cut_edges"] > 0
    assert pattern.stats["max_strain"] <= bound
    assert native.unfold(pos, tri, params={"layout": 0}).stats["pieces"] > 5


@pytest.mark.parametrize("seed", [11, 12, 13])
@pytest.mark.parametrize("bent", [False, True])
def test_plate_with_holes_is_one_piece_without_slits(native, tmp_path, seed, bent):
    pos, tri, holes = holed_plate(seed=seed, bent=bent)
    svg = tmp_path / "plate.svg"
    pattern = native.unfold(pos, tri, params={"scale": 0}, svg_path=str(svg))
    st = pattern.stats
    assert st["pieces"] == 1 and st["cut_edges"] == 0 and st["seams"] == 0
    assert st["max_strain"] <= (1e-9 if not bent else 0.0025)
    # The cut line: the outline and one loop per hole.
    cut = svg_path_data(svg, "cut-lines")
    assert len(cut) == 1 and list(cut.values())[0].count("M") == 1 + holes
    assert (signed_areas(pattern.corner_uvs) > 0).all()
    assert overlapping_triangles(pattern.corner_uvs, np.arange(len(tri))) == []


def svg_path_data(path, group):
    """piece label -> the d attribute of its path in the SVG group."""
    out = {}
    for g in ET.parse(path).getroot().iter(SVG + "g"):
        if g.get("id") == group:
            for node in g.iter(SVG + "path"):
                out[node.get("id").split("-", 1)[1]] = node.get("d")
    return out

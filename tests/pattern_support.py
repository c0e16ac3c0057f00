"""Helpers for the flat-pattern tests (tests/test_pattern*.py): the binding
on the build's library, a PNG reader for rsvg-convert's output and
geometric checks of an unfolding."""
import pathlib
import re
import struct
import xml.etree.ElementTree as ET
import zlib

import numpy as np

from devkit.binding import native


def load_native(library_path):
    """addon/core/native.py (devkit/binding.py) with the build under test loaded."""
    native.load(path=library_path)
    return native


def read_png(path):
    """(height, width, channels) uint8 of an 8-bit, non-interlaced PNG (what
    rsvg-convert writes). Rows filtered None, Up or Sub are undone with numpy
    (Sub is a running sum modulo 256 per channel); Average and Paeth depend on
    the pixel to the left as already decoded, so those rows go byte by byte in
    plain Python (Python ints: far quicker than indexing numpy arrays)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and interlace == 0, "unsupported PNG"
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
    raw = zlib.decompress(idat)
    stride = width * channels
    rows = np.frombuffer(raw, dtype=np.uint8).reshape(height, stride + 1)
    out = np.zeros((height, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.uint8)
    for y in range(height):
        kind, line = rows[y, 0], rows[y, 1:]
        if kind == 0:
            cur = line
        elif kind == 1:
            cur = np.cumsum(line.reshape(width, channels), axis=0, dtype=np.uint8).reshape(-1)
        elif kind == 2:
            cur = line + prev  # uint8: modulo 256
        elif kind in (3, 4):
            cur = _unfilter_row(kind, line.tolist(), prev.tolist(), channels)
        else:
            raise AssertionError("bad PNG filter type %d" % kind)
        out[y] = cur
        prev = out[y]
    return out.reshape(height, width, channels)


def _unfilter_row(kind, line, prev, channels):
    """One row of filter type 3 (Average) or 4 (Paeth), on lists of ints."""
    cur = [0] * len(line)
    for x, value in enumerate(line):
        left = cur[x - channels] if x >= channels else 0
        up = prev[x]
        if kind == 3:
            cur[x] = (value + ((left + up) >> 1)) & 255
        else:
            up_left = prev[x - channels] if x >= channels else 0
            p = left + up - up_left
            pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
            pred = left if pa <= pb and pa <= pc else (up if pb <= pc else up_left)
            cur[x] = (value + pred) & 255
    return np.array(cur, dtype=np.uint8)


def signed_areas(corners):
    """Signed area of each flat triangle, corners (t, 3, 2)."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def overlapping_triangles(corners, faces):
    """Faces of one flat piece whose centroid lies strictly inside another face
    of the piece (an overlap), by brute force."""
    tri = corners[faces]
    centre = tri.mean(axis=1)
    bad = []
    for i, p in enumerate(centre):
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]

        def side(u, v):
            return (v[:, 0] - u[:, 0]) * (p[1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (p[0] - u[:, 0])

        scale = np.abs(signed_areas(tri)) * 1e-9
        inside = (side(a, b) > scale) & (side(b, c) > scale) & (side(c, a) > scale)
        inside[i] = False
        if inside.any():
            bad.append(faces[i])
    return bad


def edge_strain(positions, triangles, corners):
    """|l_flat / l_3d - 1| of every face edge, (t, 3)."""
    out = np.empty((len(triangles), 3))
    for k in range(3):
        l3 = np.linalg.norm(positions[triangles[:, k]] - positions[triangles[:, (k + 1) % 3]], axis=1)
        l2 = np.linalg.norm(corners[:, k] - corners[:, (k + 1) % 3], axis=1)
        out[:, k] = np.abs(l2 / l3 - 1)
    return out


def face_areas(positions, triangles):
    p = positions[triangles]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


def square_to_round(rows=24, cols=96, noise=0.02, seed=1, side=1.0, radius=0.45, height=0.8):
    """A lofted square-to-round duct transition (open at both ends): each
    point of the square's perimeter joined by a straight line to the point of
    the circle at the same angle around, as a sheet-metal loft; a grid of
    rows x cols vertices closed around, its vertices moved by a uniform
    random amount in +-noise times the mean edge length (seeded)."""
    angle = 2 * np.pi * np.arange(cols) / cols
    direction = np.c_[np.cos(angle), np.sin(angle)]
    square = direction / np.abs(direction).max(axis=1, keepdims=True) * side / 2
    circle = direction * radius
    v = np.linspace(0.0, 1.0, rows + 1)[:, None, None]
    ring = (1 - v) * square[None] + v * circle[None]
    pos = np.concatenate([ring, np.broadcast_to(v * height, ring.shape[:2] + (1,))], axis=2).reshape(-1, 3)
    tri = []
    for r in range(rows):
        for c in range(cols):
            a, b = r * cols + c, r * cols + (c + 1) % cols
            tri += [(a, b, b + cols), (a, b + cols, a + cols)]
    tri = np.array(tri, dtype=np.int32)
    edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
    ae = np.linalg.norm(pos[edges[:, 0]] - pos[edges[:, 1]], axis=1).mean()
    pos = pos + np.random.default_rng(seed).uniform(-1, 1, pos.shape) * noise * ae
    return pos, tri


def holed_plate(seed=1, bent=False, points=1500):
    """An exact developable plate with 1-3 round holes, any triangulation: a
    Delaunay triangulation of random points (seeded) in a 2 x 1.2 rectangle,
    each hole's circle sampled by vertices, the triangles inside the holes
    removed; bent: rolled around a cylinder of radius 1 (x becomes arc
    length), which keeps every length."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(seed)
    w, h = 2.0, 1.2
    holes = []
    while len(holes) < rng.integers(1, 4):
        c, r = rng.uniform([0.3, 0.3], [w - 0.3, h - 0.3]), rng.uniform(0.08, 0.22)
        if (
            all(np.linalg.norm(c - c2) > r + r2 + 0.1 for c2, r2 in holes)
            and (c - r > 0.05).all()
            and (c + r < [w - 0.05, h - 0.05]).all()
        ):
            holes.append((c, r))
    spacing = np.sqrt(w * h / points)
    pts = [rng.uniform([0, 0], [w, h], (points, 2))]
    for t in np.linspace(0, 1, int(w / spacing), endpoint=False):
        pts.append([[t * w, 0], [w - t * w, h]])
    for t in np.linspace(0, 1, int(h / spacing), endpoint=False):
        pts.append([[0, h - t * h], [w, t * h]])
    for c, r in holes:
        k = max(12, int(2 * np.pi * r / spacing))
        a = 2 * np.pi * np.arange(k) / k
        pts.append(c + r * np.c_[np.cos(a), np.sin(a)])
    p = np.concatenate([np.asarray(q, dtype=float).reshape(-1, 2) for q in pts])
    keep = np.ones(len(p), dtype=bool)
    for c, r in holes:  # no free point inside a hole or too near its circle
        d = np.linalg.norm(p - c, axis=1)
        keep &= ~((d < r + 0.5 * spacing) & (np.abs(d - r) > 1e-12))
    p = p[keep]
    tri = Delaunay(p).simplices
    centre = p[tri].mean(axis=1)
    inside = np.zeros(len(tri), dtype=bool)
    for c, r in holes:
        inside |= np.linalg.norm(centre - c, axis=1) < r
    tri = tri[~inside]
    a = p[tri]
    area = np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0])
    tri = np.where((area < 0)[:, None], tri[:, [0, 2, 1]], tri)[np.abs(area) > 1e-9].astype(np.int32)
    used = np.unique(tri)
    remap = -np.ones(len(p), dtype=np.int64)
    remap[used] = np.arange(len(used))
    p, tri = p[used], remap[tri].astype(np.int32)
    if bent:
        pos = np.c_[np.sin(p[:, 0]), p[:, 1], 1 - np.cos(p[:, 0])]
    else:
        pos = np.c_[p, np.zeros(len(p))]
    return pos, tri, len(holes)


GLYPH_WIDTH = 0.8  # em per glyph, as native/pattern/pattern_labels.h counts it


def label_boxes(svg_path):
    """(x0, y0, x1, y1) of every text label of the SVG, mm: centred on its
    point (the baseline is 0.35 em below it), GLYPH_WIDTH em per glyph, 1.2 em
    high, the box around it turned by its rotate()."""
    boxes = []
    for node in ET.parse(svg_path).getroot().iter("{http://www.w3.org/2000/svg}text"):
        if node.get("font-size") is None:
            continue  # the scale bar's captions
        size = float(node.get("font-size"))
        x, y = float(node.get("x")), float(node.get("y")) - 0.35 * size
        angle = 0.0
        m = re.match(r"rotate\(([-0-9.e]+)", node.get("transform") or "")
        if m:
            angle = np.radians(float(m.group(1)))
        half_w, half_h = 0.5 * GLYPH_WIDTH * size * len(node.text), 0.6 * size
        c, s = abs(np.cos(angle)), abs(np.sin(angle))
        hx, hy = c * half_w + s * half_h, s * half_w + c * half_h
        boxes.append((x - hx, y - hy, x + hx, y + hy))
    return boxes


def nearly_developable(positions, triangles, tolerance=0.0025):
    """Whether the inner vertices that are not flat (|defect| >= 1e-3) of a
    piece of these faces need no more strain than the tolerance together
    (their sum of |defect| / (2 pi)): every vertex flat, or nearly."""
    from devkit import families

    defect, inner = families.angle_defects(positions, triangles)
    d = np.abs(defect[inner])
    return d[d >= 1e-3].sum() / (2 * np.pi) <= tolerance


def strain_bound(positions, triangles, tolerance=0.0025):
    """The strain a piece of these faces may keep (docs/pattern.md, the rule):
    when it is nearly developable, the larger of the tolerance and the sum of
    |defect| over its inner vertices / (2 pi); else the tolerance."""
    from devkit import families

    if not nearly_developable(positions, triangles, tolerance):
        return tolerance
    defect, inner = families.angle_defects(positions, triangles)
    return max(tolerance, np.abs(defect[inner]).sum() / (2 * np.pi))

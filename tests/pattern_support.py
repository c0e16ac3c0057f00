"""Helpers for the flat-pattern tests (tests/test_pattern*.py): the binding
on the build's library, a PNG reader for rsvg-convert's output and
geometric checks of an unfolding."""
import pathlib
import struct
import zlib

import numpy as np

from devkit.binding import native


def load_native(library_path):
    """addon/native.py (devkit/binding.py) with the build under test loaded."""
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

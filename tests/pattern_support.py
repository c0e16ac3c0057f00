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
    rsvg-convert writes)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
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
    out = np.zeros((height, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        if kind == 0:
            cur = line
        elif kind == 2:
            cur = (line + prev) & 255
        else:  # 1 sub, 3 average, 4 Paeth depend on the left pixel: row by row
            cur = np.zeros(stride, dtype=np.int32)
            for x in range(stride):
                left = cur[x - channels] if x >= channels else 0
                up = prev[x]
                if kind == 1:
                    cur[x] = (line[x] + left) & 255
                elif kind == 3:
                    cur[x] = (line[x] + (left + up) // 2) & 255
                else:
                    up_left = prev[x - channels] if x >= channels else 0
                    p = left + up - up_left
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
                    pred = left if pa <= pb and pa <= pc else (up if pb <= pc else up_left)
                    cur[x] = (line[x] + pred) & 255
        out[y] = cur
        prev = cur
    return out.reshape(height, width, channels).astype(np.uint8)


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

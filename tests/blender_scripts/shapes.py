"""Meshes a Blender user makes, in numpy (no bpy), for the add-on tests: in
Blender through make_object() of the scenario scripts and without Blender in
tests/test_addon_checks.py. Each returns (vertices (n, 3) float64, faces: a
list of vertex index tuples, any number of corners)."""
import numpy as np


def _grid_faces(rows, cols, wrap=False):
    count = cols if wrap else cols - 1
    return [
        (i * cols + j, i * cols + (j + 1) % cols, (i + 1) * cols + (j + 1) % cols, (i + 1) * cols + j)
        for i in range(rows - 1)
        for j in range(count)
    ]


def plate(nu=12, nv=8, size=(1.0, 0.6)):
    x, y = np.meshgrid(np.linspace(0, size[0], nu), np.linspace(0, size[1], nv), indexing="ij")
    v = np.stack([x, y, np.zeros_like(x)], axis=-1).reshape(-1, 3)
    return v, _grid_faces(nu, nv)


def fin(nu=12, nv=8):
    """A plate with a fin: a triangle standing on an inner edge, which three faces
    then share (a non-manifold edge, refused)."""
    v, faces = plate(nu, nv)
    a, b = nv + 2, nv + 3  # an inner edge along the plate's second row
    v = np.vstack([v, (v[a] + v[b]) / 2 + [0, 0, 0.2]])
    return v, faces + [(a, b, len(v) - 1)]


def moebius(around=48, across=6, radius=1.0, width=0.4):
    """A Moebius strip of quads: a paper strip given half a twist, one-sided.
    The last column of quads joins the first with the strip turned over."""
    u = np.linspace(0, 2 * np.pi, around, endpoint=False)
    s = np.linspace(-width / 2, width / 2, across)
    U, S = np.meshgrid(u, s, indexing="ij")
    v = np.stack(
        [
            (radius + S * np.cos(U / 2)) * np.cos(U),
            (radius + S * np.cos(U / 2)) * np.sin(U),
            S * np.sin(U / 2),
        ],
        axis=-1,
    ).reshape(-1, 3)
    idx = np.arange(around * across).reshape(around, across)
    faces = []
    for i in range(around):
        for j in range(across - 1):
            if i + 1 < around:
                a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
            else:  # the twist: across the seam, side j meets side across-1-j
                a, b, c, d = idx[i, j], idx[0, across - 1 - j], idx[0, across - 2 - j], idx[i, j + 1]
            faces.append((int(a), int(b), int(c), int(d)))
    return v, faces


def duct(around=64, rings=16, side=0.3, radius=0.1, height=0.3, noise=0.0, seed=1):
    """A square-to-round transition lofted by straight lines (sheet metal):
    the square end (side x side) at z = 0, the round end at z = height."""
    t = np.linspace(0, 2 * np.pi, around, endpoint=False) + np.pi / around
    c, s = np.cos(t), np.sin(t)
    k = (side / 2) / np.maximum(np.abs(c), np.abs(s))
    square = np.stack([k * c, k * s, np.zeros(around)], 1)
    circle = np.stack([radius * c, radius * s, np.full(around, height)], 1)
    w = np.linspace(0, 1, rings)[:, None, None]
    v = ((1 - w) * square[None] + w * circle[None]).reshape(-1, 3)
    v = v + np.random.default_rng(seed).normal(scale=noise, size=v.shape)
    return v, _grid_faces(rings, around, wrap=True)


def box(size=2.0):
    """Blender's default cube: 8 vertices, 6 quads."""
    h = size / 2
    v = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)], dtype=float)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, faces


def prism(sides=12, radius=1.0, height=2.0):
    """A cylinder as Blender's Add > Cylinder makes it: quads around, n-gon caps."""
    t = np.linspace(0, 2 * np.pi, sides, endpoint=False)
    ring = np.stack([radius * np.cos(t), radius * np.sin(t)], 1)
    v = np.vstack(
        [np.column_stack([ring, np.full(sides, -height / 2)]), np.column_stack([ring, np.full(sides, height / 2)])]
    )
    faces = [(i, (i + 1) % sides, sides + (i + 1) % sides, sides + i) for i in range(sides)]
    faces.append(tuple(range(sides - 1, -1, -1)))
    faces.append(tuple(range(sides, 2 * sides)))
    return v, faces


def ngon(sides=12, radius=1.0):
    """A flat n-gon alone (Add > Circle, Fill Type N-Gon)."""
    t = np.linspace(0, 2 * np.pi, sides, endpoint=False)
    return np.stack([radius * np.cos(t), radius * np.sin(t), np.zeros(sides)], 1), [tuple(range(sides))]


def unwelded_sheet(nu=12, nv=8, seam=6, bend=0.3):
    """A bent sheet whose column of vertices at `seam` is doubled: two halves
    that touch along a seam that was never welded."""
    v, faces = plate(nu, nv)
    v = v.copy()
    v[:, 2] = bend * np.sin(np.pi * v[:, 0])
    copies = {seam * nv + j: len(v) + j for j in range(nv)}
    v = np.vstack([v, v[[seam * nv + j for j in range(nv)]]])
    right = [tuple(copies.get(i, i) for i in f) if min(i // nv for i in f) >= seam else f for f in faces]
    return v, right


def soup(v, faces):
    """Every face on its own vertices (a polygon soup, as some exporters write)."""
    out_v, out_f = [], []
    for f in faces:
        out_f.append(tuple(range(len(out_v), len(out_v) + len(f))))
        out_v.extend(np.asarray(v)[list(f)])
    return np.array(out_v), out_f


def triangulate(faces):
    """Fan triangles of the faces, and each triangle's face."""
    tris, owner = [], []
    for k, f in enumerate(faces):
        for i in range(1, len(f) - 1):
            tris.append((f[0], f[i], f[i + 1]))
            owner.append(k)
    return np.array(tris, dtype=np.int64), np.array(owner, dtype=np.int64)

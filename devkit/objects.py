"""Seeded random whole objects: closed meshes of the kinds users bring that are not
developable anywhere in particular (issue 11's "whole objects", beyond the eleven of
../shared/meshes), for tests and benchmarks that must hold on shapes nobody tuned for.

Kinds (KINDS):
  blob         an icosphere pushed in and out by a few random smooth waves over the
               directions, scaled differently along three random axes (a pebble, a potato,
               a head)
  rounded_box  a superellipsoid |x|^p + |y|^p + |z|^p = 1 (p 3-10) on a UV sphere's grid,
               random side lengths: nearly flat sides joined by rounded edges, poles at
               two sides' centres (a CAD part, a soap bar)
  torus        a ring whose tube radius and centre-line radius wave around it (a bagel, a
               handle, a tyre), on a grid with either diagonal
  limb         a tube of varying radius along a random smooth space curve, closed by
               rounded caps whose poles are triangle fans (a finger, an arm, a sausage)

Each is drawn with a face count (log-uniform over `faces`) and optional noise (each
coordinate moves by a uniform amount in +-noise AE, AE the mean edge length, as
devkit/families.py does). Everything derives from the seed: the same arguments give the
same mesh bit for bit. Every mesh is closed, manifold and consistently oriented outward.
"""
from dataclasses import dataclass, field

import numpy as np

KINDS = ("blob", "rounded_box", "torus", "limb")


@dataclass
class ObjectMesh:
    kind: str
    seed: int
    noise: float  # amplitude in AE
    positions: np.ndarray  # (n, 3), noisy if noise > 0
    clean: np.ndarray  # (n, 3) without the noise
    triangles: np.ndarray  # (m, 3) int32, outward
    info: dict = field(default_factory=dict)


def _icosphere(level):
    t = (1 + 5**0.5) / 2
    v = [
        (-1, t, 0),
        (1, t, 0),
        (-1, -t, 0),
        (1, -t, 0),
        (0, -1, t),
        (0, 1, t),
        (0, -1, -t),
        (0, 1, -t),
        (t, 0, -1),
        (t, 0, 1),
        (-t, 0, -1),
        (-t, 0, 1),
    ]
    f = [
        (0, 11, 5),
        (0, 5, 1),
        (0, 1, 7),
        (0, 7, 10),
        (0, 10, 11),
        (1, 5, 9),
        (5, 11, 4),
        (11, 10, 2),
        (10, 7, 6),
        (7, 1, 8),
        (3, 9, 4),
        (3, 4, 2),
        (3, 2, 6),
        (3, 6, 8),
        (3, 8, 9),
        (4, 9, 5),
        (2, 4, 11),
        (6, 2, 10),
        (8, 6, 7),
        (9, 8, 1),
    ]
    points = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(level):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                p = points[a] + points[b]
                points.append(p / np.linalg.norm(p))
                middle[key] = len(points) - 1
            return middle[key]

        faces = [
            g
            for a, b, c in faces
            for g in (
                (a, mid(a, b), mid(c, a)),
                (b, mid(b, c), mid(a, b)),
                (c, mid(c, a), mid(b, c)),
                (mid(a, b), mid(b, c), mid(c, a)),
            )
        ]
    return np.array(points), np.array(faces, dtype=np.int32)


def _grid_closed_u(rows, cols, alternating, poles):
    """Triangles of a (rows + 1) x cols vertex grid closed around u (columns wrap);
    with `poles`, two more vertices (index rows1*cols, +1) fan the first and last rows."""
    tris = []
    for i in range(rows):
        for j in range(cols):
            a, b = i * cols + j, i * cols + (j + 1) % cols
            c, d = a + cols, b + cols
            if alternating and (i + j) % 2:
                tris += [(a, b, d), (a, d, c)]
            else:
                tris += [(a, b, c), (b, d, c)]
    if poles:
        south, north = (rows + 1) * cols, (rows + 1) * cols + 1
        top = rows * cols
        for j in range(cols):
            tris.append((south, (j + 1) % cols, j))
            tris.append((north, top + j, top + (j + 1) % cols))
    return np.array(tris, dtype=np.int32)


def _random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _blob(rng, faces):
    level = int(np.clip(round(np.log(faces / 20) / np.log(4)), 2, 6))
    d, tris = _icosphere(level)
    radius = np.ones(len(d))
    for _ in range(int(rng.integers(2, 6))):
        w = rng.normal(size=3)
        w *= rng.uniform(1.0, 3.5) / np.linalg.norm(w)
        radius += rng.uniform(0.05, 0.25) * np.sin(d @ w + rng.uniform(0, 2 * np.pi))
    radius = np.maximum(radius, 0.4)
    scale = rng.uniform(0.6, 1.4, size=3)
    return ((d * radius[:, None]) * scale) @ _random_rotation(rng).T, tris


def _rounded_box(rng, faces, alternating):
    cols = max(8, int(round(np.sqrt(faces))))
    rows = max(4, int(round(faces / (2 * cols))) - 1)
    p = rng.uniform(3.0, 10.0)
    theta = np.linspace(0, np.pi, rows + 3)[1:-1]  # without the poles
    phi = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    T, P = np.meshgrid(theta, phi, indexing="ij")

    def spow(x):
        return np.sign(x) * np.abs(x) ** (2.0 / p)

    x, y, z = spow(np.sin(T) * np.cos(P)), spow(np.sin(T) * np.sin(P)), spow(np.cos(T))
    pts = np.stack([x, y, -z], axis=-1).reshape(-1, 3)  # rows go south -> north
    pts = np.vstack([pts, [[0, 0, -1.0], [0, 0, 1.0]]])
    pts *= rng.uniform(0.5, 1.5, size=3)
    return pts @ _random_rotation(rng).T, _grid_closed_u(rows, cols, alternating, poles=True)


def _torus(rng, faces, alternating):
    ratio = rng.uniform(0.15, 0.45)  # tube over ring radius
    cols = max(12, int(round(np.sqrt(faces / (2 * ratio)))))
    rows = max(6, int(round(faces / (2 * cols))))
    u = np.linspace(0, 2 * np.pi, cols, endpoint=False)  # around the ring
    v = np.linspace(0, 2 * np.pi, rows, endpoint=False)  # around the tube
    k = rng.integers(1, 4, size=2)
    a = rng.uniform(0.0, 0.3, size=2)
    ph = rng.uniform(0, 2 * np.pi, size=2)
    ring = 1.0 + a[0] * ratio * np.sin(k[0] * u + ph[0])
    tube = ratio * (1.0 + a[1] * np.sin(k[1] * u + ph[1]))
    V, U = np.meshgrid(v, u, indexing="ij")
    R, r = np.broadcast_to(ring, U.shape), np.broadcast_to(tube, U.shape)
    pts = np.stack([(R + r * np.cos(V)) * np.cos(U), (R + r * np.cos(V)) * np.sin(U), r * np.sin(V)], -1)
    pts = pts.reshape(-1, 3) * [1.0, rng.uniform(0.7, 1.0), 1.0]
    tris = _grid_closed_u(rows - 1, cols, alternating, poles=False)
    # close the tube around v: the last row to the first
    last = []
    for j in range(cols):
        a_, b_ = (rows - 1) * cols + j, (rows - 1) * cols + (j + 1) % cols
        c_, d_ = j, (j + 1) % cols
        last += [(a_, b_, c_), (b_, d_, c_)]
    tris = np.vstack([tris, np.array(last, dtype=np.int32)])
    return pts @ _random_rotation(rng).T, tris


def _limb(rng, faces, alternating):
    control = np.cumsum(rng.normal(size=(5, 3)) * [1.0, 0.5, 0.5] + [1.0, 0, 0], axis=0)
    t = np.linspace(0, 1, 400)
    # A smooth curve near the control points: their least-squares cubic.
    basis = np.vander(np.linspace(0, 1, len(control)), 4)
    coeff = np.linalg.lstsq(basis, control, rcond=None)[0]
    curve = np.vander(t, 4) @ coeff
    length = np.linalg.norm(np.diff(curve, axis=0), axis=1).sum()
    mean_radius = length * rng.uniform(0.06, 0.15)
    cols = max(8, int(round(np.sqrt(faces * np.pi * mean_radius / length))))
    rows = max(6, int(round(faces / (2 * cols))) - 1)
    cap = mean_radius / length  # cap length in curve parameter
    s = np.linspace(-cap, 1 + cap, rows + 3)[1:-1]
    along = np.clip(s, 0, 1)
    # Tangent and a parallel-transported frame along the dense curve.
    tangent = np.gradient(curve, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.cross(tangent[0], [0.0, 0.0, 1.0] if abs(tangent[0][2]) < 0.9 else [1.0, 0, 0])
    normals = []
    for tg in tangent:
        normal = normal - (normal @ tg) * tg
        normal /= np.linalg.norm(normal)
        normals.append(normal)
    normals = np.array(normals)
    binormals = np.cross(tangent, normals)
    idx = np.clip((along * (len(t) - 1)).round().astype(int), 0, len(t) - 1)
    wave = 1.0 + 0.25 * np.sin(2 * np.pi * rng.integers(1, 3) * along + rng.uniform(0, 2 * np.pi))
    # Rounded caps: the radius falls as a quarter circle beyond either end.
    beyond = np.maximum(np.maximum(-s, s - 1), 0) / cap
    radius = mean_radius * wave * np.sqrt(np.clip(1 - beyond**2, 0, 1))
    offset = np.sign(s - 0.5) * np.minimum(beyond, 1) * mean_radius * wave
    phi = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    centre = curve[idx] + tangent[idx] * offset[:, None]
    ring = (
        np.cos(phi)[None, :, None] * normals[idx][:, None, :] + np.sin(phi)[None, :, None] * binormals[idx][:, None, :]
    )
    pts = (centre[:, None, :] + radius[:, None, None] * ring).reshape(-1, 3)
    ends = [curve[0] - tangent[0] * mean_radius * wave[0], curve[-1] + tangent[-1] * mean_radius * wave[-1]]
    pts = np.vstack([pts, ends])
    return pts, _grid_closed_u(rows, cols, alternating, poles=True)


def _oriented_outward(positions, triangles):
    """Flips every triangle if the signed volume is negative."""
    p = positions[triangles]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum()
    return triangles if volume > 0 else triangles[:, ::-1].copy()


def make(kind, faces=4000, noise=0.0, seed=0, alternating=False):
    """One object of `kind` with about `faces` triangles and `noise` (fraction of AE)."""
    if kind not in KINDS:
        raise ValueError("unknown kind %r (objects.KINDS)" % kind)
    rng = np.random.default_rng([seed, KINDS.index(kind), 4241])
    if kind == "blob":
        clean, triangles = _blob(rng, faces)
    elif kind == "rounded_box":
        clean, triangles = _rounded_box(rng, faces, alternating)
    elif kind == "torus":
        clean, triangles = _torus(rng, faces, alternating)
    else:
        clean, triangles = _limb(rng, faces, alternating)
    clean = clean.astype(np.float64)
    triangles = _oriented_outward(clean, triangles)
    edges = np.unique(
        np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1), axis=0
    )
    ae = np.linalg.norm(clean[edges[:, 0]] - clean[edges[:, 1]], axis=1).mean()
    positions = clean + rng.uniform(-1.0, 1.0, clean.shape) * noise * ae
    return ObjectMesh(kind, seed, noise, positions, clean, triangles, {"ae": ae, "alternating": alternating})


def random_case(kind, seed, faces=(1000, 20000), noise=(0.0, 0.02)):
    """make() with the face count (log-uniform), the noise (uniform; zero on every other
    seed, as most whole objects are modelled rather than scanned) and the diagonal style
    drawn from `seed` too."""
    rng = np.random.default_rng([seed, 104729, KINDS.index(kind)])
    count = int(np.exp(rng.uniform(np.log(faces[0]), np.log(faces[1]))))
    amplitude = float(rng.uniform(*noise)) if seed % 2 else 0.0
    return make(kind, count, amplitude, seed, alternating=bool(rng.integers(2)))


def open_case(kind, seed, keep=(0.55, 0.85)):
    """random_case cut open by a plane: an object with a boundary that still wraps around
    something (a hand at the wrist, a cap, a box without its lid). The plane's normal and the
    share of the object's height kept (uniform in `keep`) are drawn from `seed`; the faces whose
    centroid lies on the far side go, and the largest edge-connected rest is returned,
    reindexed. Returns an ObjectMesh (its info holds the plane)."""
    m = random_case(kind, seed)
    rng = np.random.default_rng([seed, 7919, KINDS.index(kind)])
    direction = rng.standard_normal(3)
    direction /= np.linalg.norm(direction)
    heights = m.clean @ direction
    cut = float(np.quantile(heights, rng.uniform(*keep)))
    kept = m.triangles[heights[m.triangles].mean(axis=1) <= cut]
    kept = kept[_largest_component(kept)]
    used = np.unique(kept)
    remap = np.full(len(m.positions), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    info = dict(m.info, direction=direction, cut=cut)
    return ObjectMesh(kind, seed, m.noise, m.positions[used], m.clean[used], remap[kept].astype(np.int32), info)


def _largest_component(triangles):
    """Mask of the faces of the largest edge-connected component (union-find over shared edges)."""
    n = len(triangles)
    parent = np.arange(n)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    faces = np.tile(np.arange(n), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, faces = edges[order], faces[order]
    same = np.all(edges[1:] == edges[:-1], axis=1)
    for a, b in zip(faces[:-1][same], faces[1:][same]):
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
    roots = np.array([find(f) for f in range(n)])
    return roots == np.bincount(roots).argmax()

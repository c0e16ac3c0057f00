"""Seeded random developable surfaces of every family of issue 11, each with
its noise-free twin.

    mesh = families.make("tangent_helix", seed=3)
    mesh.positions   noisy vertices (n, 3)
    mesh.clean       the noise-free twin, same connectivity (an exact
                     developable surface sampled at the vertices)
    mesh.triangles   (m, 3) int32

Families (FAMILIES): cylinder and cone patches and closed bands, tangent
developables of a helix, a twisted cubic and a random smooth space curve,
generalized cylinders and cones over wavy directrices, bent sheets (a plane
rolled with varying curvature), curved folds (a wavy generalized cylinder
with one side reflected through a tilted plane: both sides stay developable,
the crease is a row of the grid) and planes.

Triangulations (TRIANGULATIONS): "grid" (every quad cut along the same
diagonal), "alternating" (diagonals alternate, the style of
devkit.meshes), "irregular" (a Delaunay triangulation of jittered points in
the parameter domain), "slivers" (a grid of cells six times longer than
wide, cut along one diagonal: corners under 10 degrees). Curved folds take
only the grid triangulations (the crease must be a row of edges).

Noise: each coordinate moves by a uniform random amount in +-noise AE (AE:
the twin's mean edge length). Everything derives from the seed: the same
arguments give the same mesh bit for bit.
"""
from dataclasses import dataclass, field

import numpy as np

FAMILIES = (
    "cylinder_patch",
    "cylinder_band",
    "cone_patch",
    "cone_band",
    "tangent_helix",
    "tangent_cubic",
    "tangent_random",
    "generalized_cylinder",
    "generalized_cone",
    "bent_sheet",
    "curved_fold",
    "plane",
)
TRIANGULATIONS = ("grid", "alternating", "irregular", "slivers")
CLOSED_FAMILIES = ("cylinder_band", "cone_band")  # closed around u


@dataclass
class FamilyMesh:
    family: str
    triangulation: str
    seed: int
    noise: float  # amplitude in AE
    positions: np.ndarray  # noisy (n, 3)
    clean: np.ndarray  # noise-free twin (n, 3)
    triangles: np.ndarray  # (m, 3) int32
    info: dict = field(default_factory=dict)


# -- surfaces on the parameter square (u, v) in [0, 1]^2 ----------------------------------


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _wavy(rng, count=3, amplitude=0.15):
    """A smooth random 1D function on [0, 1]: a few sines of random phase."""
    k = rng.integers(1, 4, size=count)
    a = rng.uniform(-amplitude, amplitude, size=count) / k
    phase = rng.uniform(0, 2 * np.pi, size=count)
    return lambda u: sum(a[i] * np.sin(2 * np.pi * k[i] * u + phase[i]) for i in range(count))


def _surface(family, rng):
    """(function (u, v) -> points, aspect = length along u / along v, closed in u)."""
    if family in ("cylinder_patch", "cylinder_band"):
        closed = family == "cylinder_band"
        radius = rng.uniform(0.5, 2.0)
        span = 2 * np.pi if closed else rng.uniform(0.5, 1.0) * np.pi
        height = rng.uniform(0.8, 2.5)

        def f(u, v):
            t = span * u
            return np.stack([radius * np.cos(t), radius * np.sin(t), height * v], -1)

        return f, radius * span / height, closed
    if family in ("cone_patch", "cone_band"):
        closed = family == "cone_band"
        r0, r1 = rng.uniform(1.0, 2.0), rng.uniform(0.3, 0.9)
        span = 2 * np.pi if closed else rng.uniform(0.5, 1.0) * np.pi
        height = rng.uniform(0.8, 2.0)

        def f(u, v):
            t = span * u
            r = r0 + (r1 - r0) * v
            return np.stack([r * np.cos(t), r * np.sin(t), height * v], -1)

        return f, 0.5 * (r0 + r1) * span / np.hypot(height, r0 - r1), closed
    if family.startswith("tangent_"):
        if family == "tangent_helix":
            a, b = rng.uniform(0.8, 1.5), rng.uniform(0.2, 0.6)
            turns = rng.uniform(0.6, 1.2)

            def curve(s):
                t = 2 * np.pi * turns * s
                return np.stack([a * np.cos(t), a * np.sin(t), b * t], -1)

        elif family == "tangent_cubic":
            scale = rng.uniform(0.8, 1.5)
            lo = rng.uniform(-1.2, -0.6)

            def curve(s):
                t = lo + (-2 * lo) * s
                return scale * np.stack([t, t**2, t**3], -1)

        else:
            wx, wy, wz = _wavy(rng, amplitude=0.4), _wavy(rng, amplitude=0.4), _wavy(rng, amplitude=0.4)

            def curve(s):
                return np.stack([2.0 * s + wx(s), np.sin(2.5 * s) + wy(s), 0.6 * s**2 + wz(s)], -1)

        h = 1e-5
        ss = np.linspace(0, 1, 2001)
        length = np.linalg.norm(np.diff(curve(ss), axis=0), axis=1).sum()
        t0, t1 = 0.08 * length, rng.uniform(0.25, 0.4) * length

        def f(u, v):
            tangent = _unit(curve(u + h) - curve(u - h))
            return curve(u) + (t0 + (t1 - t0) * v)[..., None] * tangent

        return f, length / (t1 - t0), False
    if family in ("generalized_cylinder", "bent_sheet", "curved_fold", "generalized_cone"):
        wave = _wavy(rng, amplitude=0.25)
        width = rng.uniform(1.5, 3.0)
        if family == "bent_sheet":
            # A plane rolled with curvature kappa(s): arc length kept, so the
            # directrix is the integral of its turning angle.
            k0, k1 = rng.uniform(-1.0, 1.0), rng.uniform(0.5, 2.0)
            phase = rng.uniform(0, 2 * np.pi)
            ss = np.linspace(0, 1, 4001)
            angle = np.cumsum(k0 + k1 * np.sin(2 * np.pi * ss + phase)) * width / len(ss)
            xs = np.concatenate([[0], np.cumsum(np.cos(angle[:-1]))]) * width / len(ss)
            zs = np.concatenate([[0], np.cumsum(np.sin(angle[:-1]))]) * width / len(ss)

            def directrix(u):
                return np.stack([np.interp(u, ss, xs), np.zeros_like(u), np.interp(u, ss, zs)], -1)

        else:

            def directrix(u):
                return np.stack([width * u, np.zeros_like(u), width * wave(u)], -1)

        depth = rng.uniform(0.8, 2.0)
        if family == "generalized_cone":
            apex = np.array([0.5 * width, rng.uniform(2.5, 4.0) * depth, rng.uniform(-0.5, 0.5)])

            def f(u, v):
                d = directrix(u)
                w = (0.55 * v)[..., None]
                return d + w * (apex - d)

            return f, width / (0.55 * np.linalg.norm(apex - directrix(np.array(0.5)))), False
        if family != "curved_fold":

            def f(u, v):
                return directrix(u) + (depth * v)[..., None] * np.array([0.0, 1.0, 0.0])

            return f, width / depth, False
        # Curved fold: the generalized cylinder y -> (x(u), y, z(u)) cut by the
        # plane y cos a + z sin a = c; the side beyond it is reflected through
        # it. v = 0.5 is the crease: y runs from the crease by +-depth/2.
        tilt = rng.uniform(0.3, 0.7)
        normal = np.array([0.0, np.cos(tilt), np.sin(tilt)])

        def f(u, v):
            d = directrix(u)
            crease_y = -(d[..., 2] * np.sin(tilt)) / np.cos(tilt)
            y = crease_y + depth * (v - 0.5)
            p = d + y[..., None] * np.array([0.0, 1.0, 0.0])
            side = p @ normal
            beyond = side > 0
            p[beyond] -= 2 * side[beyond, None] * normal
            return p

        return f, width / depth, False
    if family == "plane":
        size = rng.uniform(1.0, 2.0)

        def f(u, v):
            return np.stack([size * u, size * v * 0.8, np.zeros_like(u)], -1)

        return f, 1.25, False
    raise ValueError("unknown family %r (families.FAMILIES)" % family)


# -- triangulations of the parameter square ------------------------------------------------


def _grid(rows, cols, closed, alternating):
    """Triangles of a (rows+1) x (cols+1) vertex grid, u along columns; closed: column
    cols is column 0 (the vertex grid then has cols columns)."""
    width = cols if closed else cols + 1
    tris = []
    for r in range(rows):
        for c in range(cols):
            a = r * width + c
            b = r * width + (c + 1) % width if closed else a + 1
            d, e = a + width, b + width
            if alternating and (r + c) % 2:
                tris += [(a, b, d), (b, e, d)]
            else:
                tris += [(a, b, e), (a, e, d)]
    return np.array(tris, dtype=np.int32)


def _grid_uv(rows, cols, closed):
    u = np.arange(cols if closed else cols + 1) / cols
    v = np.arange(rows + 1) / rows
    uu, vv = np.meshgrid(u, v)
    return uu.ravel(), vv.ravel()


def _irregular(count_u, count_v, rng):
    """Delaunay triangles of jittered points; the border points stay on the border."""
    from scipy.spatial import Delaunay

    uu, vv = np.meshgrid(np.arange(count_u + 1) / count_u, np.arange(count_v + 1) / count_v)
    u, v = uu.ravel().copy(), vv.ravel().copy()
    inner_u = (u > 0) & (u < 1)
    inner_v = (v > 0) & (v < 1)
    u[inner_u] += rng.uniform(-0.35, 0.35, inner_u.sum()) / count_u
    v[inner_v] += rng.uniform(-0.35, 0.35, inner_v.sum()) / count_v
    tri = Delaunay(np.c_[u * count_u, v * count_v]).simplices.astype(np.int32)
    # Drop slivers Delaunay puts along the straight border (zero-area caps).
    p = np.c_[u, v]
    area = np.abs(np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]]))
    tri = tri[area > 1e-3 / (count_u * count_v)]
    used = np.unique(tri)
    remap = -np.ones(len(u), dtype=np.int64)
    remap[used] = np.arange(len(used))
    return u[used], v[used], remap[tri].astype(np.int32)


def make(family, triangulation="grid", faces=2000, noise=0.02, seed=0):
    """A FamilyMesh: `faces` triangles (about), noise amplitude in AE (0.005-0.05 in the
    issue), everything else drawn from `seed`."""
    if triangulation not in TRIANGULATIONS:
        raise ValueError("unknown triangulation %r (families.TRIANGULATIONS)" % triangulation)
    if family == "curved_fold" and triangulation == "irregular":
        raise ValueError("curved folds need a grid triangulation (the crease is a row of edges)")
    rng = np.random.default_rng([seed, FAMILIES.index(family), TRIANGULATIONS.index(triangulation)])
    surface, aspect, closed = _surface(family, rng)
    if triangulation == "slivers":
        aspect = aspect / 6.0  # cells 6 times longer along v than along u
    cols = max(4, int(round(np.sqrt(faces / 2 * aspect))))
    rows = max(2, int(round(faces / 2 / cols)))
    if family == "curved_fold" and rows % 2:
        rows += 1  # the crease row v = 0.5
    if triangulation == "irregular":
        u, v, triangles = _irregular(cols, rows, rng)
        if closed:  # irregular bands: keep them open (a seam of jittered points would not close)
            u = u * 0.95
    else:
        u, v = _grid_uv(rows, cols, closed)
        triangles = _grid(rows, cols, closed, alternating=triangulation == "alternating")
    clean = surface(u, v).reshape(-1, 3).astype(np.float64)
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    ae = np.linalg.norm(clean[edges[:, 0]] - clean[edges[:, 1]], axis=1).mean()
    positions = clean + rng.uniform(-1.0, 1.0, clean.shape) * noise * ae
    return FamilyMesh(
        family,
        triangulation,
        seed,
        noise,
        positions,
        clean,
        triangles,
        {"rows": rows, "cols": cols, "closed": closed, "ae": ae},
    )


def angle_defects(positions, triangles):
    """(angle defect per vertex in rad, interior mask), as native/core/measures.h defines them."""
    p, t = np.asarray(positions, dtype=np.float64), np.asarray(triangles)
    n = len(p)
    angles = np.zeros(n)
    for c in range(3):
        a, b, d = p[t[:, c]], p[t[:, (c + 1) % 3]], p[t[:, (c + 2) % 3]]
        u, w = b - a, d - a
        np.add.at(angles, t[:, c], np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), (u * w).sum(1)))
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    boundary = np.zeros(n, dtype=bool)
    boundary[unique[count == 1].ravel()] = True
    interior = ~boundary & (np.bincount(t.ravel(), minlength=n) > 0)
    return 2 * np.pi - angles, interior


def face_normals(positions, triangles):
    """Unit normal per triangle (zero for a degenerate one)."""
    p, t = positions, triangles
    n = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def random_case(family, seed, faces=(500, 5000), noise=(0.005, 0.05), triangulations=None):
    """make() with the face count (log-uniform), the noise (log-uniform) and the
    triangulation (one of `triangulations`, default every one the family takes)
    drawn from `seed` too."""
    rng = np.random.default_rng([seed, 7919, FAMILIES.index(family)])
    options = [t for t in (triangulations or TRIANGULATIONS) if not (family == "curved_fold" and t == "irregular")]
    triangulation = options[int(rng.integers(len(options)))]
    count = int(np.exp(rng.uniform(np.log(faces[0]), np.log(faces[1]))))
    amplitude = float(np.exp(rng.uniform(np.log(noise[0]), np.log(noise[1]))))
    return make(family, triangulation, count, amplitude, seed)

"""Generated test meshes: exact developable surfaces, their noisy versions and
the paper's curved cone. Each returns (positions float64 (n, 3), triangles
int32 (m, 3)); grids are triangulated with alternating diagonals so that no
direction is favoured."""
import numpy as np


def grid_triangles(rows, cols, wrap=False):
    """Triangles of a rows x cols vertex grid (row-major); wrap joins the last
    column to the first (a closed band)."""
    tris = []
    col_count = cols if wrap else cols - 1
    for i in range(rows - 1):
        for j in range(col_count):
            a = i * cols + j
            b = i * cols + (j + 1) % cols
            c = (i + 1) * cols + j
            d = (i + 1) * cols + (j + 1) % cols
            if (i + j) % 2 == 0:
                tris += [(a, b, d), (a, d, c)]
            else:
                tris += [(a, b, c), (b, d, c)]
    return np.array(tris, dtype=np.int32)


def plane(rows=12, cols=15, size=2.0):
    u, v = np.meshgrid(np.linspace(0, size, cols), np.linspace(0, size * 0.8, rows))
    pos = np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], axis=1)
    return pos, grid_triangles(rows, cols)


def cylinder(rows=10, cols=40, radius=1.0, height=2.0, angle=2 * np.pi):
    """Open cylinder (a closed band when angle is 2 pi) along z."""
    closed = np.isclose(angle, 2 * np.pi)
    t = np.linspace(0, angle, cols, endpoint=not closed)
    z = np.linspace(0, height, rows)
    tt, zz = np.meshgrid(t, z)
    pos = np.stack([radius * np.cos(tt).ravel(), radius * np.sin(tt).ravel(), zz.ravel()], axis=1)
    return pos, grid_triangles(rows, cols, wrap=closed)


def cone(rows=10, cols=48, r0=1.5, r1=0.6, height=1.5, bulge=0.0):
    """A cone frustum band along z from radius r0 to r1; bulge pushes the
    middle rows outward by bulge * sin(pi t), bending the rulings (the paper's
    curved cone)."""
    t = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    s = np.linspace(0, 1, rows)
    tt, ss = np.meshgrid(t, s)
    r = r0 + (r1 - r0) * ss + bulge * np.sin(np.pi * ss)
    pos = np.stack([r.ravel() * np.cos(tt).ravel(), r.ravel() * np.sin(tt).ravel(),
                    height * ss.ravel()], axis=1)
    return pos, grid_triangles(rows, cols, wrap=True)


def curved_cone():
    """The paper's Fig. 3 / Table I model: a closed band of 80 x 9 vertices
    (720 v, 1280 f), slightly bulged: mean |defect| 2.47e-3 and AE 0.118,
    against the paper's 2.498e-3 and 0.1169."""
    return cone(rows=9, cols=80, r0=1.36, r1=0.68, height=0.72, bulge=0.066)


def demo_cone_band():
    """The run command's demo mesh (devkit/meshes.py), its quads split in two."""
    from devkit.meshes import demo_cone_band as band
    return band()


def add_noise(positions, amplitude, seed=1):
    """Uniform random displacement of every vertex, in [-amplitude, amplitude]^3."""
    rng = np.random.default_rng(seed)
    return positions + rng.uniform(-amplitude, amplitude, positions.shape)


def noisy_cylinder_patch(rows=16, cols=24, radius=1.0, noise=0.01, seed=1):
    """A 120-degree cylinder patch with noise of `noise` x radius."""
    pos, tris = cylinder(rows=rows, cols=cols, radius=radius, height=1.5, angle=2 * np.pi / 3)
    return add_noise(pos, noise * radius, seed), tris


def write_obj(path, positions, triangles):
    with open(path, "w") as f:
        for p in positions:
            f.write("v %.17g %.17g %.17g\n" % tuple(p))
        for t in triangles:
            f.write("f %d %d %d\n" % tuple(np.asarray(t) + 1))


def read_obj(path):
    pos, tris = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                pos.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
                for k in range(1, len(idx) - 1):
                    tris.append([idx[0], idx[k], idx[k + 1]])
    return np.array(pos, dtype=np.float64), np.array(tris, dtype=np.int32)


def folded_sheet(rows=12, cols=15, angle_degrees=90.0, size=2.0):
    """A square sheet folded along the straight line x = size / 2 (two planes
    meeting at `angle_degrees`); with an odd `cols` the crease runs along a
    column of edges."""
    pos, tris = plane(rows=rows, cols=cols, size=size)
    fold = size / 2
    turn = np.radians(180.0 - angle_degrees)
    beyond = pos[:, 0] > fold
    d = pos[beyond, 0] - fold
    pos[beyond, 0] = fold + d * np.cos(turn)
    pos[beyond, 2] = d * np.sin(turn)
    return pos, tris


def cylinder_cone(rows_each=8, cols=40, radius=1.0, height=1.0, apex_height=1.2):
    """A cylinder of `height` joined along its top ring to a cone frustum that
    narrows to half the radius: two developable pieces meeting at a circle.
    Returns positions, triangles and the per-face piece (0 cylinder, 1 cone)."""
    t = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    rings = []
    for s in np.linspace(0, 1, rows_each):
        rings.append((radius, height * s))
    for s in np.linspace(0, 1, rows_each)[1:]:
        rings.append((radius * (1 - 0.5 * s), height + apex_height * 0.5 * s))
    pos = np.array([[r * np.cos(a), r * np.sin(a), z] for r, z in rings for a in t])
    tris = grid_triangles(len(rings), cols, wrap=True)
    piece = np.repeat((np.arange(len(rings) - 1) >= rows_each - 1).astype(int), 2 * cols)
    return pos, tris, piece


def curved_fold(seed=0, rows=13, cols=41):
    """An exact discrete curved fold: a generalized cylinder (a wavy curve in
    the xz-plane swept along y) whose part beyond an oblique plane is mirrored
    across it. Strips between two rulings are planar and the mirror is an
    isometry, so the mesh is intrinsically flat; the crease, where the plane
    meets the rulings, is a curve through mesh vertices. The seed picks the
    wave and the plane."""
    rng = np.random.default_rng(seed)
    amplitude = rng.uniform(0.15, 0.35)
    waves = rng.uniform(0.7, 1.4)
    tilt = rng.uniform(0.3, 0.8)
    x = np.linspace(0.0, 2.0, cols)
    z = amplitude * np.sin(waves * np.pi * x)
    width = 2.0
    crease = 0.45 * width + tilt * z  # y of the crease on each ruling
    half = rows // 2 + 1
    t1 = np.linspace(0.0, 1.0, half)
    t2 = np.linspace(0.0, 1.0, rows - half + 1)[1:]
    y = np.concatenate([np.outer(t1, crease), crease + np.outer(t2, width - crease)])
    pos = np.stack([np.broadcast_to(x, y.shape).ravel(), y.ravel(),
                    np.broadcast_to(z, y.shape).ravel()], axis=1)
    # Mirror the rows beyond the crease across the plane y - tilt z = 0.45 width.
    normal = np.array([0.0, 1.0, -tilt]) / np.sqrt(1.0 + tilt * tilt)
    offset = 0.45 * width / np.sqrt(1.0 + tilt * tilt)
    beyond = np.repeat(np.arange(rows) >= half, cols)
    d = pos[beyond] @ normal - offset
    pos[beyond] -= 2.0 * d[:, None] * normal
    return pos, grid_triangles(rows, cols)


def sphere_cap(angle_degrees, rings=12, sectors=36, radius=1.0):
    """The cap of a sphere within `angle_degrees` of its pole: a centre vertex
    and `rings` rings of `sectors` vertices."""
    theta = np.radians(angle_degrees) * np.arange(1, rings + 1) / rings
    phi = 2 * np.pi * np.arange(sectors) / sectors
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    ring_pos = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], axis=-1)
    pos = np.vstack([[0.0, 0.0, 1.0], ring_pos.reshape(-1, 3)]) * radius
    tris = [(0, 1 + s, 1 + (s + 1) % sectors) for s in range(sectors)]
    for r in range(rings - 1):
        for s in range(sectors):
            a = 1 + r * sectors + s
            b = 1 + r * sectors + (s + 1) % sectors
            c = a + sectors
            d = b + sectors
            tris += [(a, c, d), (a, d, b)]
    return pos, np.array(tris, dtype=np.int32)

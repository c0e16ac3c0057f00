"""Generated meshes. Each returns (positions float64 (n, 3), triangles int32
(m, 3)) unless it says otherwise; grids are triangulated with alternating
diagonals so that no direction is favoured, in numpy so that a million faces
take a second."""
import numpy as np

from .obj import read_obj


# -- grids ------------------------------------------------------------------------


def grid_triangles(rows, cols, wrap=False):
    """Triangles of a rows x cols vertex grid (row-major); wrap joins the last
    column to the first (a closed band)."""
    col_count = cols if wrap else cols - 1
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(col_count), indexing="ij")
    i, j = i.ravel(), j.ravel()
    a = i * cols + j
    b = i * cols + (j + 1) % cols
    c = (i + 1) * cols + j
    d = (i + 1) * cols + (j + 1) % cols
    even = ((i + j) % 2 == 0)[:, None]
    first = np.where(even, np.stack([a, b, d], 1), np.stack([a, b, c], 1))
    second = np.where(even, np.stack([a, d, c], 1), np.stack([b, d, c], 1))
    return np.stack([first, second], 1).reshape(-1, 3).astype(np.int32)


def grid_quads(nu, nv):
    """Quads (m, 4) int32 of an nu x nv vertex grid (row-major, rows of nv)."""
    idx = np.arange(nu * nv).reshape(nu, nv)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1)
    return quads.reshape(-1, 4).astype(np.int32)


def quads_to_triangles(quads):
    """Each quad (a, b, c, d) split along a-c."""
    quads = np.asarray(quads)
    return np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]).astype(np.int32)


def add_noise(positions, amplitude, seed=1):
    """Uniform random displacement of every vertex, in [-amplitude, amplitude]^3."""
    rng = np.random.default_rng(seed)
    return positions + rng.uniform(-amplitude, amplitude, positions.shape)


# -- exact developable surfaces and their noisy versions ------------------------------


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
    pos = np.stack([r.ravel() * np.cos(tt).ravel(), r.ravel() * np.sin(tt).ravel(), height * ss.ravel()], axis=1)
    return pos, grid_triangles(rows, cols, wrap=True)


def curved_cone():
    """The paper's Fig. 3 / Table I model: a closed band of 80 x 9 vertices
    (720 v, 1280 f), slightly bulged: mean |defect| 2.47e-3 and AE 0.118,
    against the paper's 2.498e-3 and 0.1169."""
    return cone(rows=9, cols=80, r0=1.36, r1=0.68, height=0.72, bulge=0.066)


def noisy_cylinder_patch(rows=16, cols=24, radius=1.0, noise=0.01, seed=1):
    """A 120-degree cylinder patch with noise of `noise` x radius."""
    pos, tris = cylinder(rows=rows, cols=cols, radius=radius, height=1.5, angle=2 * np.pi / 3)
    return add_noise(pos, noise * radius, seed), tris


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
    s = np.linspace(0, 1, rows_each)
    ring_r = np.concatenate([np.full(rows_each, radius), radius * (1 - 0.5 * s[1:])])
    ring_z = np.concatenate([height * s, height + apex_height * 0.5 * s[1:]])
    pos = np.stack(
        [np.outer(ring_r, np.cos(t)).ravel(), np.outer(ring_r, np.sin(t)).ravel(), np.repeat(ring_z, cols)], axis=1
    )
    tris = grid_triangles(len(ring_r), cols, wrap=True)
    piece = np.repeat((np.arange(len(ring_r) - 1) >= rows_each - 1).astype(int), 2 * cols)
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
    pos = np.stack([np.broadcast_to(x, y.shape).ravel(), y.ravel(), np.broadcast_to(z, y.shape).ravel()], axis=1)
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
    s = np.arange(sectors)
    fan = np.stack([np.zeros(sectors, int), 1 + s, 1 + (s + 1) % sectors], axis=1)
    r, s = np.meshgrid(np.arange(rings - 1), s, indexing="ij")
    a = (1 + r * sectors + s).ravel()
    b = (1 + r * sectors + (s + 1) % sectors).ravel()
    c, d = a + sectors, b + sectors
    rings_tris = np.stack([np.stack([a, c, d], 1), np.stack([a, d, b], 1)], 1).reshape(-1, 3)
    return pos, np.vstack([fan, rings_tris]).astype(np.int32)


def pipe_elbow(rng):
    """An open pipe elbow (a torus section: the tube's radius 1, the bend's
    radius 2-5, bent by 45-120 degrees, 24-64 columns around and 16-50 rings),
    drawn from the numpy Generator `rng`. Not developable: Gauss-Bonnet with
    its two end circles fixes its total curvature, which can only gather."""
    bend_radius, angle = rng.uniform(2.0, 5.0), np.radians(rng.uniform(45.0, 120.0))
    around, rings = int(rng.integers(24, 65)), int(rng.integers(16, 51))
    u = np.linspace(0, 2 * np.pi, around, endpoint=False)
    v = np.linspace(0, angle, rings)
    vv, uu = np.meshgrid(v, u, indexing="ij")  # a row per ring
    positions = np.stack(
        [(bend_radius + np.cos(uu)) * np.cos(vv), (bend_radius + np.cos(uu)) * np.sin(vv), np.sin(uu)], -1
    ).reshape(-1, 3)
    return positions, grid_triangles(rings, around, wrap=True)


def open_box(rng):
    """A box without a lid, random in proportions and in the grid each side is
    cut into: developable piecewise, its curvature on the edges and corners."""
    size = rng.uniform(0.5, 3.0, 3)
    cells = rng.integers(2, 9, 3)
    points, tris, index = [], [], {}

    def vertex(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(points)
            points.append(p)
        return index[key]

    # each side: an origin corner and two edge vectors (outward normal = e1 x e2)
    x, y, z = np.diag(size)
    sides = [
        (np.zeros(3), y, x, (1, 0)),
        (np.zeros(3), x, z, (0, 2)),
        (y, z, x, (2, 0)),
        (np.zeros(3), z, y, (2, 1)),
        (x, y, z, (1, 2)),
    ]
    for origin, e1, e2, (a, b) in sides:
        n1, n2 = cells[a], cells[b]
        grid = [[vertex(origin + e1 * i / n1 + e2 * j / n2) for j in range(n2 + 1)] for i in range(n1 + 1)]
        for i in range(n1):
            for j in range(n2):
                tris += [
                    (grid[i][j], grid[i + 1][j], grid[i + 1][j + 1]),
                    (grid[i][j], grid[i + 1][j + 1], grid[i][j + 1]),
                ]
    return np.array(points), np.array(tris, dtype=np.int32)


def ring_torus_quads(n_major=48, n_minor=16, r=0.35, stagger=1.0):
    """A torus (major radius 1) of n_major rings of n_minor quads, minor radius
    r; `stagger` turns every other ring by that much of half a step. Aligned
    (0), each ring of quads is a cone frustum (developable piecewise); turned
    (1), no ring is. Returns (points, quads)."""
    a = np.linspace(0, 2 * np.pi, n_major, endpoint=False)
    b = np.linspace(0, 2 * np.pi, n_minor, endpoint=False)
    A, B = np.meshgrid(a, b, indexing="ij")
    A = A + stagger * (np.pi / n_major) * (np.arange(n_minor) % 2)
    points = np.stack([(1 + r * np.cos(B)) * np.cos(A), (1 + r * np.cos(B)) * np.sin(A), r * np.sin(B)], -1).reshape(
        -1, 3
    )
    idx = np.arange(n_major * n_minor).reshape(n_major, n_minor)
    right, up = np.roll(idx, -1, axis=0), np.roll(idx, -1, axis=1)
    corner = np.roll(right, -1, axis=1)
    return points, np.stack([idx, right, corner, up], -1).reshape(-1, 4)


def ring_torus(n_major, n_minor, r, stagger):
    """ring_torus_quads split into triangles (each quad along its first diagonal)."""
    points, quads = ring_torus_quads(n_major, n_minor, r, stagger)
    return points, np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]).astype(np.int32)


def lobster_elbow(rng, turns_degrees=(10.0, 40.0), pieces=(2, 6)):
    """A lobster-back pipe elbow: 2-6 (the range `pieces`) straight cylinder pieces of radius 1,
    each turning by an angle drawn from `turns_degrees` (a range) from the
    last, in one plane, joined by mitres
    (every joint ring lies in the plane that halves the turn), 16-48 columns
    around, 2-6 rings along each piece, drawn from the numpy Generator `rng`;
    no two mitres cross. Developable piecewise: its curvature sits on the
    mitre rings only."""
    pieces, around = int(rng.integers(pieces[0], pieces[1] + 1)), int(rng.integers(16, 49))
    turns = np.radians(rng.uniform(*turns_degrees, pieces - 1))
    lengths = rng.uniform(0.5, 2.0, pieces)
    # A mitre reaches tan(turn / 2) along the axis at the pipe's wall: a piece
    # is long enough for its two mitres not to cross, with a quarter of the
    # radius of straight wall between them.
    reach = np.tan(turns / 2)
    lengths = np.maximum(lengths, np.r_[reach, 0.0] + np.r_[0.0, reach] + 0.25)
    along = [int(rng.integers(2, 7)) for _ in range(pieces)]
    normal = np.array([0.0, 0.0, 1.0])  # of the bend's plane
    u = np.linspace(0, 2 * np.pi, around, endpoint=False)
    axes, start = [np.array([1.0, 0.0, 0.0])], [np.zeros(3)]
    for k in range(pieces - 1):
        start.append(start[-1] + lengths[k] * axes[-1])
        c, s = np.cos(turns[k]), np.sin(turns[k])
        a = axes[-1]
        axes.append(c * a + s * np.cross(normal, a))

    def ring(centre, axis, plane_normal):
        """The cylinder (centre, axis) cut by the plane through centre with plane_normal."""
        side = np.cross(normal, axis)
        offsets = np.cos(u)[:, None] * side + np.sin(u)[:, None] * normal
        t = -(offsets @ plane_normal) / (axis @ plane_normal)
        return centre + offsets + t[:, None] * axis

    rows = []
    for k in range(pieces):
        a = axes[k]
        begin = a if k == 0 else (axes[k - 1] + a) / np.linalg.norm(axes[k - 1] + a)
        end = a if k == pieces - 1 else (a + axes[k + 1]) / np.linalg.norm(a + axes[k + 1])
        first = ring(start[k], a, begin)
        last = ring(start[k] + lengths[k] * a, a, end)
        for i in range(0 if k == 0 else 1, along[k] + 1):
            rows.append(first + (last - first) * (i / along[k]))
    positions = np.vstack(rows)
    return positions, grid_triangles(len(rows), around, wrap=True)


def noisy_grid(faces, seed=0):
    """A noisy, gently curved height-field grid of about `faces` triangles
    (cheap to build at millions of faces: memory-budget tests)."""
    cols = int(np.sqrt(faces / 2)) + 1
    rows = max(2, faces // (2 * (cols - 1)) + 1)
    u, v = np.meshgrid(np.arange(cols, dtype=float), np.arange(rows, dtype=float))
    rng = np.random.default_rng(seed)
    z = 0.001 * (u - cols / 2) ** 2 + 0.05 * rng.standard_normal(u.shape)
    p = np.stack([u.ravel(), v.ravel(), z.ravel()], 1)
    return p, grid_triangles(rows, cols)


# -- the run command's demo meshes (quads, as a modeller has them) ----------------------


def cone_band(nu=80, nv=9, noise=0.004, bulge=0.06, seed=1):
    """A curved cone band like the paper's Fig. 3 (80 x 9 = 720 vertices), made
    non-developable by a smooth bulge plus random noise.
    Returns (vertices (nu*nv, 3) float64, quads (m, 4) int32)."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.5 * np.pi, nu)  # around the axis
    v = np.linspace(0.0, 1.0, nv)  # along the rulings
    U, V = np.meshgrid(u, v, indexing="ij")
    r = 1.0 + 0.8 * V  # cone: radius grows along v
    pts = np.stack([r * np.cos(U), r * np.sin(U), 1.2 * V], axis=-1)
    # "curved": bend the band (a developable cone stays developable only without it)
    radial = np.stack([np.cos(U), np.sin(U), np.zeros_like(U)], axis=-1)
    bump = bulge * np.sin(np.pi * V) * np.sin(3.0 * U) ** 2
    pts = pts + radial * bump[..., None]
    pts = pts + rng.normal(scale=noise, size=pts.shape)
    return pts.reshape(-1, 3), grid_quads(nu, nv)


def half_cylinder(nu=40, nv=20, noise=0.01, seed=2):
    """A noisy half-cylinder sheet. Returns (vertices, quads)."""
    rng = np.random.default_rng(seed)
    U, V = np.meshgrid(np.linspace(0.0, np.pi, nu), np.linspace(0.0, 2.0, nv), indexing="ij")
    pts = np.stack([np.cos(U), V, np.sin(U)], axis=-1)
    pts = pts + rng.normal(scale=noise, size=pts.shape)
    return pts.reshape(-1, 3), grid_quads(nu, nv)


DEMOS = {"cone_band": cone_band, "half_cylinder": half_cylinder}


def demo_cone_band():
    """The run command's demo mesh, its quads split in two."""
    positions, quads = cone_band()
    return positions, quads_to_triangles(quads)


# -- benchmark families of any size --------------------------------------------------------


def band_size(faces):
    """rows, cols of a closed band with rows - 1 = cols / 2 and ~faces faces."""
    cols = max(8, int(round(np.sqrt(faces))))
    cols += cols % 2
    return cols // 2 + 1, cols


def noisy_cylinder(faces, noise=0.03, seed=1):
    """Closed cylinder band (radius 1, height pi, square cells) with uniform
    noise of `noise` grid spacings on every coordinate."""
    rows, cols = band_size(faces)
    pos, tris = cylinder(rows=rows, cols=cols, height=np.pi)
    return add_noise(pos, noise * 2 * np.pi / cols, seed), tris


def noisy_cone(faces, noise=0.03, seed=2):
    """Closed cone frustum band (radius 1.5 to 0.6 over height 1.5) with noise
    of `noise` mean grid spacings."""
    rows, cols = band_size(faces)
    pos, tris = cone(rows=rows, cols=cols)
    return add_noise(pos, noise * 2 * np.pi * 1.05 / cols, seed), tris


def generalized_cone(rows, cols, span=2 * np.pi, waist=0.5, pleats=8, pleat_depth=0.08, height=1.6, wave=0.02, waves=2):
    """A generalized cone (apex at the origin, rulings to a pleated directrix
    r(theta) = 1 + pleat_depth sin(pleats theta), z = -height), cut between
    s = waist and s = 1 of the ruling, with wavy rulings: every ruling is
    bent sideways (radially) by wave * sin(waves pi u), u in [0, 1] along the
    band. wave = 0 is exactly developable."""
    closed = np.isclose(span, 2 * np.pi)
    t = np.linspace(0, span, cols, endpoint=not closed)
    s = np.linspace(waist, 1.0, rows)
    tt, ss = np.meshgrid(t, s)
    r = 1.0 + pleat_depth * np.sin(pleats * tt)
    u = (ss - waist) / (1.0 - waist)
    radial = ss * r + wave * np.sin(waves * np.pi * u)
    pos = np.stack([(radial * np.cos(tt)).ravel(), (radial * np.sin(tt)).ravel(), (-height * ss).ravel()], 1)
    return pos, grid_triangles(rows, cols, wrap=closed)


def wavy_generalized_cone(faces):
    """The scaling family: a closed pleated generalized cone band with two
    waves along every ruling."""
    return generalized_cone(*band_size(faces))


def skirt():
    """Table II's skirt stand-in: an open (slit) pleated generalized cone of
    29 x 34 vertices = 986 v, 1848 f as in the paper, one bulge along the
    rulings; mean |defect| and AE are tuned near the paper's 4.91e-3 and 0.1113."""
    pos, tris = generalized_cone(
        rows=29, cols=34, span=2 * np.pi * 0.9, waist=0.45, pleats=6, pleat_depth=0.06, height=2.2, wave=0.1556, waves=1
    )
    return pos * 0.9679, tris


FAMILIES = {"cylinder": noisy_cylinder, "cone": noisy_cone, "gcone": wavy_generalized_cone}
FAMILY_TITLES = {"cylinder": "noisy cylinder", "cone": "noisy cone", "gcone": "generalized cone, wavy rulings"}
NAMED = {"curved_cone": curved_cone, "skirt": skirt}


def load(spec):
    """(positions, triangles) of a mesh spec dict: {'file': path} |
    {'family': name, 'faces': n} | {'named': 'curved_cone' | 'skirt'}."""
    if "file" in spec:
        return read_obj(spec["file"])
    if "family" in spec:
        return FAMILIES[spec["family"]](int(spec["faces"]))
    if spec.get("named") in NAMED:
        return NAMED[spec["named"]]()
    raise ValueError(spec)

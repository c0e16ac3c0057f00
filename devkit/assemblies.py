"""Seeded random sheet-metal assemblies of issue 35, each with its noise-free twin and its
natural pieces, and sheets with scan noise.

    mesh = assemblies.make("elbow4", "irregular", faces=3000, noise=0.02, seed=3)
    mesh.positions       noisy vertices (n, 3)
    mesh.clean           the noise-free twin, same connectivity: exactly piecewise developable
    mesh.triangles       (m, 3) int32: one welded, manifold, consistently oriented mesh
    mesh.pieces          (m,) int32: the natural piece of every face, 0 .. natural_pieces - 1
    mesh.natural_pieces  how many pieces the part is made of (NATURAL_PIECES)
    mesh.creases         (e, 2) int32: the vertex pairs (lower index first) of the edges between
                         faces of two different pieces: the seams
    mesh.info            the drawn dimensions, "ae" (the twin's mean edge length), "spacing"
                         (the grid's edge length), "holes_meshed" (holed sheets)

Parts (PARTS), each made of planes, cylinders and cones that meet at seams, with dimensions,
proportions and orientation drawn from the seed (sizes of order 1):
  transition   a square-to-round duct transition, open at both ends: four flat triangles (a side
               of the square and the point of the circle where the circle's tangent is parallel
               to that side) and four oblique cones from the square's corners to the quarter
               circles between those points; 8 pieces by kind of surface. A triangle and its
               two cones share a ruling and are tangent along it (the dihedral angle across it
               is the cone's facet angle): the twin is flat and ruled on those seams too, so as
               a developable sheet the transition is one piece, and a tool that keeps it whole
               is right
  reducer      a conical reducer between two cylinders: concentric, or (on half the seeds)
               eccentric, flush along one side with an oblique cone; 3 pieces
  elbow4/6     lobster-back elbows of 4 / 6 gores (half gores at the ends, 60-120 degrees in
               all), the gores cut by the mitre planes that halve each turn; a piece per gore
  tee          a branch cylinder meeting a larger main cylinder at a right angle, their axes
               crossing; the main pipe is cut open inside their intersection curve; 2 pieces
  ybranch      a breeches piece: a trunk and two branches of one radius at random angles to it,
               cut along the plane curves where they meet (two mitres and the crotch); 3 pieces
  cup          a paper cup: a cone frustum side and a flat disc bottom, open top; 2 pieces
  holed_sheet  a rectangle, flat or (on half the seeds) bent around a cylinder between two flat
               ends, with 1-3 round holes; 1 piece
Every part is open where the real one is (pipe ends, the cup's rim, the sheet's edges and holes).

Triangulations (TRIANGULATIONS), each piece meshed in its own parameter domain, the pieces
sharing the vertices of their seams (which lie on the intersection curves):
  grid         every column of a curved piece has the same rows (but where a hole or seam cuts
               it), each quad cut along the same diagonal; a flat piece's rows have as many
               points as their length takes
  alternating  the same rows, the diagonals alternating in a checkerboard
  irregular    the columns jittered by up to 35 % of their spacing, on each column its own
               number of points, jittered too, neighbouring columns joined along the shorter
               diagonal (the Delaunay choice within a strip): every valence, no two rows alike
  slivers      columns sqrt(6) times closer and rows sqrt(6) times farther apart than the grid's:
               cells six times longer than wide, corners under 10 degrees
Columns are rulings (the straight lines of a cylinder or cone; on a flat piece, rows across it,
on the cup's bottom rings around its centre) and every triangle has its corners on two
neighbouring columns. Two neighbouring rulings of a cylinder or a cone lie in one plane, so
every vertex inside a piece is surrounded by two planar strips meeting along its ruling: the
noise-free twin has an angle defect of rounding size (< 1e-9 rad) and normals on one great
circle (measures.ruled_spread 0) at every vertex strictly inside a piece, whatever the
triangulation. (A Delaunay
triangulation of points jittered over a curved piece would not be developable: families.py's
irregular twins are not.) The price: columns meet a seam where they meet it, so the main pipe of
a tee has thin strips beside the branch (the columns through the intersection curve bunch up
where the curve runs along them, kept at least 0.3 column spacings apart), and the cones' columns
meet at their apex.

Noise: each coordinate moves by a uniform random amount in +-noise AE (AE: the twin's mean edge
length), seams and boundaries included, as families.py and objects.py do: "noise 0.02" means the
same in all three. Everything derives from the seed: the same arguments give the same mesh bit
for bit.

scan_sheet / random_scan_sheet: a family of families.py with scan-like noise of 10-50 % of the
edge length (families.random_case draws 0.5-5 %), for benchmarks of sheets with scan noise.
"""
from dataclasses import dataclass, field

import numpy as np

from . import families

PARTS = ("transition", "reducer", "elbow4", "elbow6", "tee", "ybranch", "cup", "holed_sheet")
TRIANGULATIONS = families.TRIANGULATIONS
NATURAL_PIECES = {
    "transition": 8,
    "reducer": 3,
    "elbow4": 4,
    "elbow6": 6,
    "tee": 2,
    "ybranch": 3,
    "cup": 2,
    "holed_sheet": 1,
}
MIN_FACES = 500  # below this the holes and seams would be a few edges long
JITTER = 0.35  # of the spacing: how far irregular columns and points move
SLIVER_ASPECT = 6.0  # cell length over width in the slivers triangulation
UP = np.array([0.0, 0.0, 1.0])


@dataclass
class AssemblyMesh:
    part: str
    triangulation: str
    seed: int
    noise: float  # amplitude in AE
    positions: np.ndarray  # noisy (n, 3)
    clean: np.ndarray  # noise-free twin (n, 3)
    triangles: np.ndarray  # (m, 3) int32
    pieces: np.ndarray  # (m,) int32, 0 .. natural_pieces - 1
    natural_pieces: int
    creases: np.ndarray  # (e, 2) int32 vertex pairs of the seam edges
    info: dict = field(default_factory=dict)


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


# -- meshing between rulings ---------------------------------------------------------------


@dataclass
class _Column:
    """The vertices along one ruling: their indices, parameters (increasing) and positions;
    cuts: hole -> (position of the vertex below it, of the vertex above it) in idx, the same
    position twice where the ruling only touches the hole."""

    idx: np.ndarray
    t: np.ndarray
    pts: np.ndarray
    cuts: dict = field(default_factory=dict)


class _Assembly:
    """Vertices and faces as a part is put together: pieces share the vertex indices of their
    seams. `h` is the edge length of the grid triangulations."""

    def __init__(self, triangulation, h, rng):
        self.style, self.rng = triangulation, rng
        stretch = np.sqrt(SLIVER_ASPECT) if triangulation == "slivers" else 1.0
        self.across, self.along = h / stretch, h * stretch  # column spacing, row spacing
        self._points, self._count = [], 0
        self._faces, self._labels = [], []
        self.info = {}  # what the part reports about its mesh (the holes that fit)

    @property
    def irregular(self):
        return self.style == "irregular"

    def add(self, points):
        """Indices of new vertices at `points` (k, 3)."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        self._points.append(points)
        self._count += len(points)
        return np.arange(self._count - len(points), self._count)

    @staticmethod
    def intervals(length, step):
        return max(1, int(round(length / step)))

    def rows(self, length):
        """Rows of a piece `length` long along its rulings: two at least, so that every piece
        has vertices inside it, off its seams and boundary."""
        return max(2, self.intervals(length, self.along))

    def spacing(self, start, stop, intervals, closed=False):
        """Parameters from start to stop in `intervals` equal steps, both ends included (closed:
        a full turn, stop left out), jittered when irregular (the ends of an open range stay)."""
        s = start + (stop - start) * np.arange(intervals if closed else intervals + 1) / intervals
        inner = slice(None) if closed else slice(1, -1)
        if self.irregular:
            s[inner] += self.rng.uniform(-JITTER, JITTER, len(s[inner])) * (stop - start) / intervals
        return s

    def ruling(self, anchors, grid, holes=(), step=None, fixed=False):
        """A column through `anchors`, [(vertex, t, point)] sorted by t from 0 to 1 on one straight
        line (its ends, and where it meets holes), with points added between them: the piece's
        rows at k / grid (structured triangulations, so that neighbouring columns share their
        rows), or `step`-spaced jittered points (irregular: two intervals at least on a column
        with no hole; `fixed`: grid intervals anyway, for two seams that must have as many
        points). holes: [(hole, q_low, q_high)] anchor numbers
        around each hole the ruling crosses (q_high = q_low + 1, nothing added between) or
        touches (q_high = q_low)."""
        step = step or self.along
        length = np.linalg.norm(anchors[-1][2] - anchors[0][2]) / (anchors[-1][1] - anchors[0][1])
        gaps = {q for _, q, r in holes if r == q + 1}
        idx, ts, pts, where = [], [], [], []
        for q, (vertex, t, p) in enumerate(anchors):
            where.append(len(idx))
            idx.append(vertex)
            ts.append(t)
            pts.append(p)
            if q + 1 == len(anchors) or q in gaps:
                continue
            t1, p1 = anchors[q + 1][1], anchors[q + 1][2]
            if self.irregular:
                n = grid if fixed else max(self.intervals((t1 - t) * length, step), 2 if len(anchors) == 2 else 1)
                levels = t + (t1 - t) * (np.arange(1, n) + self.rng.uniform(-JITTER, JITTER, n - 1)) / n
            else:
                # The piece's rows, but none within 0.3 rows of an anchor (no sliver there).
                levels = np.arange(1, grid) / grid
                levels = levels[(levels > t + 0.3 / grid) & (levels < t1 - 0.3 / grid)]
            inner = p + ((levels - t) / (t1 - t))[:, None] * (p1 - p)
            idx += list(self.add(inner))
            ts += list(levels)
            pts += list(inner)
        return _Column(np.array(idx), np.array(ts), np.array(pts), {hole: (where[q], where[r]) for hole, q, r in holes})

    def line(self, start, start_point, end, end_point, grid, step=None, fixed=False):
        """A column from vertex `start` to vertex `end` (ruling() with two anchors)."""
        return self.ruling([(start, 0.0, start_point), (end, 1.0, end_point)], grid, step=step, fixed=fixed)

    @staticmethod
    def ring(vertices, angles, points):
        """A closed column around a centre: sorted by angle, its first vertex repeated at the end."""
        a = np.mod(angles, 2 * np.pi)
        order = np.argsort(a)
        return _Column(
            np.r_[vertices[order], vertices[order[0]]],
            np.r_[a[order], a[order[0]] + 2 * np.pi],
            np.vstack([points[order], points[order[:1]]]),
        )

    def strip(self, a, b, piece, parity=0):
        """The triangles between neighbouring columns a and b of `piece`, cut where a hole lies
        between them. parity: the column's place, for the alternating diagonals."""
        holes = sorted(
            (a.cuts[h][0], h)
            for h in a.cuts
            if h in b.cuts and not (a.cuts[h][0] == a.cuts[h][1] and b.cuts[h][0] == b.cuts[h][1])
        )
        i = j = 0
        for _, h in holes:
            (a_low, a_high), (b_low, b_high) = a.cuts[h], b.cuts[h]
            self._zip(a, i, a_low + 1, b, j, b_low + 1, piece, parity)
            i, j = a_high, b_high
        self._zip(a, i, len(a.idx), b, j, len(b.idx), piece, parity)

    def _zip(self, a, i, i_end, b, j, j_end, piece, parity):
        """Triangles between a[i:i_end] and b[j:j_end], walking up both (a zipper): each triangle
        takes the next point of one column. A shared end (a cone's apex) gives no triangle."""
        faces = []
        while i < i_end - 1 or j < j_end - 1:
            if i == i_end - 1 or j == j_end - 1:
                step_a = j == j_end - 1
            elif self.irregular:  # the shorter diagonal: Delaunay's choice within a flat strip
                step_a = np.linalg.norm(a.pts[i + 1] - b.pts[j]) <= np.linalg.norm(a.pts[i] - b.pts[j + 1])
            elif abs(a.t[i + 1] - b.t[j + 1]) > 1e-9:
                step_a = a.t[i + 1] < b.t[j + 1]
            else:  # a quad of the grid
                step_a = self.style != "alternating" or (i + parity) % 2 == 0
            if step_a:
                face = (a.idx[i], b.idx[j], a.idx[i + 1])
                i += 1
            else:
                face = (a.idx[i], b.idx[j], b.idx[j + 1])
                j += 1
            if len(set(face)) == 3:
                faces.append(face)
        self._faces += faces
        self._labels += [piece] * len(faces)

    def tube(self, rings, pieces):
        """A pipe: rings [(vertex indices, points)] with the same columns around, piece
        pieces[k] between ring k and k + 1; structured rows per piece."""
        count = len(rings[0][0])
        for k, piece in enumerate(pieces):
            (v0, p0), (v1, p1) = rings[k], rings[k + 1]
            grid = self.rows(np.linalg.norm(p1 - p0, axis=1).mean())
            columns = [self.line(v0[j], p0[j], v1[j], p1[j], grid) for j in range(count)]
            for j in range(count):
                self.strip(columns[j], columns[(j + 1) % count], piece, j)

    def finish(self):
        """(points, triangles, piece per face, info), the pieces oriented alike."""
        points = np.vstack(self._points)
        triangles = np.array(self._faces, dtype=np.int32).reshape(-1, 3)
        labels = np.array(self._labels, dtype=np.int32)
        return points, _orient_pieces(triangles, labels), labels, self.info


def _edge_faces(triangles):
    """(edge (k, 2) lower vertex first, first face, second face, whether both faces run the edge
    the same way) for every edge of two faces."""
    m = len(triangles)
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    face = np.tile(np.arange(m), 3)
    key = np.sort(directed, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, directed, face = key[order], directed[order], face[order]
    first = np.nonzero(np.all(key[1:] == key[:-1], axis=1))[0]
    return key[first], face[first], face[first + 1], directed[first, 0] == directed[first + 1, 0]


def _orient_pieces(triangles, labels):
    """Each piece is built consistently oriented, but in its own parameter domain: whole pieces
    are turned over so that every seam is crossed consistently too (from piece 0 outwards)."""
    _, f, g, same = _edge_faces(triangles)
    seam = labels[f] != labels[g]
    links = np.unique(np.c_[labels[f][seam], labels[g][seam], same[seam]], axis=0)
    flip = {0: False}
    todo = [0]
    while todo:
        p = todo.pop()
        for a, b, s in links[(links[:, 0] == p) | (links[:, 1] == p)]:
            q = b if a == p else a
            if q not in flip:
                flip[q] = flip[p] ^ bool(s)
                todo.append(q)
    out = triangles.copy()
    for piece, turn in flip.items():
        if turn:
            out[labels == piece] = out[labels == piece][:, ::-1]
    return out


# -- the parts: dimensions drawn from the seed (_draw_*) and meshed at a spacing (_build_*) ---


def _draw_transition(rng):
    a = rng.uniform(0.8, 1.2)  # half the square's side
    r = a * rng.uniform(0.45, 0.85)  # the circle's radius
    height = a * rng.uniform(1.0, 2.0)
    centre = np.r_[(a - r) * rng.uniform(-0.4, 0.4, 2), height]
    slant = np.hypot(height, a - r)
    return {"half_side": a, "radius": r, "centre": centre, "area": (4 * a + np.pi * r) * slant}


def _build_transition(g, asm):
    a, r, centre = g["half_side"], g["radius"], g["centre"]
    corners = np.array([[-a, -a, 0.0], [a, -a, 0.0], [a, a, 0.0], [-a, a, 0.0]])
    cv = asm.add(corners)
    facing = -np.pi / 2 + np.pi / 2 * np.arange(4)  # side i (corner i to i + 1) faces this way

    def circle(angle):
        return centre + r * np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], -1)

    tangent = circle(facing)
    tv = asm.add(tangent)
    # The seams: corner i -> T_i and corner i + 1 -> T_i bound triangle i, whose rows join them
    # point by point, so both get one count.
    lengths = np.array(
        [[np.linalg.norm(tangent[i] - corners[i]), np.linalg.norm(tangent[i] - corners[(i + 1) % 4])] for i in range(4)]
    )
    grids = [asm.rows(lengths.mean())] * 4
    if asm.irregular:
        grids = [asm.rows(lengths[i].mean()) for i in range(4)]
    left = [asm.line(cv[i], corners[i], tv[i], tangent[i], grids[i], fixed=True) for i in range(4)]
    right = [asm.line(cv[(i + 1) % 4], corners[(i + 1) % 4], tv[i], tangent[i], grids[i], fixed=True) for i in range(4)]
    quarter = asm.intervals(r * np.pi / 2, asm.across)
    for i in range(4):  # cone i: apex corner i, from T_{i-1} to T_i
        angles = asm.spacing(facing[i] - np.pi / 2, facing[i], quarter)[1:-1]
        arc = circle(angles)
        columns = (
            [right[i - 1]]
            + [asm.line(cv[i], corners[i], v, p, grids[0]) for v, p in zip(asm.add(arc), arc)]
            + [left[i]]
        )
        for j in range(len(columns) - 1):
            asm.strip(columns[j], columns[j + 1], 4 + i, j)
    for i in range(4):  # triangle i: rows from its left seam to its right one, up to T_i
        rows = [
            asm.line(
                cv[i],
                corners[i],
                cv[(i + 1) % 4],
                corners[(i + 1) % 4],
                asm.intervals(2 * a, asm.across),
                step=asm.across,
            )
        ]
        for k in range(1, len(left[i].idx) - 1):
            p, q = left[i].pts[k], right[i].pts[k]
            rows.append(
                asm.line(
                    left[i].idx[k],
                    p,
                    right[i].idx[k],
                    q,
                    asm.intervals(np.linalg.norm(q - p), asm.across),
                    step=asm.across,
                )
            )
        rows.append(_Column(tv[i : i + 1], np.zeros(1), tangent[i : i + 1]))
        for k in range(len(rows) - 1):
            asm.strip(rows[k], rows[k + 1], i, k)


def _draw_reducer(rng):
    r1 = rng.uniform(0.5, 0.9)
    r2 = r1 * rng.uniform(0.45, 0.8)
    cone = (r1 - r2) / np.tan(np.radians(rng.uniform(12.0, 35.0)))  # half-angle 12-35 degrees
    l1, l2 = r1 * rng.uniform(0.6, 1.5), r2 * rng.uniform(0.8, 2.0)
    eccentric = bool(rng.integers(2))
    towards = rng.uniform(0, 2 * np.pi)
    # Eccentric: the small pipe's axis moved by r1 - r2, so that one side runs straight through.
    offset = (r1 - r2) * np.array([np.cos(towards), np.sin(towards), 0.0]) if eccentric else np.zeros(3)
    slant = np.hypot(cone, r1 - r2)
    return {
        "radii": (r1, r2),
        "cone_length": cone,
        "lengths": (l1, l2),
        "eccentric": eccentric,
        "offset": offset,
        "area": 2 * np.pi * (r1 * l1 + r2 * l2) + np.pi * (r1 + r2) * slant,
    }


def _build_reducer(g, asm):
    (r1, r2), (l1, l2), h = g["radii"], g["lengths"], g["cone_length"]
    theta = asm.spacing(0, 2 * np.pi, asm.intervals(np.pi * (r1 + r2), asm.across), closed=True)
    around = np.stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)], -1)
    rings = [
        r1 * around - l1 * UP,
        r1 * around,
        g["offset"] + r2 * around + h * UP,
        g["offset"] + r2 * around + (h + l2) * UP,
    ]
    asm.tube([(asm.add(p), p) for p in rings], [0, 1, 2])


def _draw_elbow(rng, gores):
    radius = rng.uniform(0.4, 0.8)
    bend = radius * rng.uniform(1.5, 3.0)  # the centre line's radius
    turn = np.radians(rng.uniform(60.0, 120.0)) / (gores - 1)  # per mitre
    extension = radius * rng.uniform(0.0, 1.0)  # straight pipe on the end gores
    length = 2 * bend * np.tan(turn / 2)  # a whole gore along its axis
    axes = np.stack([np.cos(turn * np.arange(gores)), np.sin(turn * np.arange(gores)), np.zeros(gores)], -1)
    sides = np.cross(UP, axes)
    lengths = np.r_[length / 2 + extension, np.full(gores - 2, length), length / 2 + extension]
    joints = np.vstack([np.zeros(3), np.cumsum(lengths[:, None] * axes, axis=0)])
    # Ring k: the end of gore k - 1 and the start of gore k, in the plane that halves the turn.
    rings = [(joints[0], axes[0], sides[0], axes[0])]
    rings += [(joints[k], axes[k - 1], sides[k - 1], _unit(axes[k - 1] + axes[k])) for k in range(1, gores)]
    rings += [(joints[-1], axes[-1], sides[-1], axes[-1])]
    return {
        "radius": radius,
        "bend_radius": bend,
        "gores": gores,
        "turn": turn,
        "rings": rings,
        "area": 2 * np.pi * radius * lengths.sum(),
    }


def _build_elbow(g, asm):
    radius = g["radius"]
    theta = asm.spacing(0, 2 * np.pi, asm.intervals(2 * np.pi * radius, asm.across), closed=True)
    rings = []
    for centre, axis, side, normal in g["rings"]:
        offset = radius * (np.cos(theta)[:, None] * side + np.sin(theta)[:, None] * UP)
        p = centre + offset - ((offset @ normal) / (axis @ normal))[:, None] * axis
        rings.append((asm.add(p), p))
    asm.tube(rings, range(g["gores"]))


def _draw_tee(rng):
    big = rng.uniform(0.5, 0.8)
    small = big * rng.uniform(0.4, 0.8)  # equal radii would pinch the curve to a point
    main = 2 * small + big * rng.uniform(2.0, 4.0)
    branch = big + big * rng.uniform(1.0, 2.5)  # the branch's end above the main axis
    return {
        "radii": (big, small),
        "main_length": main,
        "branch_height": branch,
        "area": 2 * np.pi * (big * main + small * branch),
    }


def _build_tee(g, asm):
    (big, small), length, height = g["radii"], g["main_length"], g["branch_height"]
    # The branch's columns on its half facing +x, from -pi/2 to pi/2; each meets the main pipe
    # on the main's column at psi, which also meets the branch's column at pi - phi.
    phi = asm.spacing(-np.pi / 2, np.pi / 2, asm.intervals(np.pi * small, asm.across))
    psi = np.arcsin(small * np.sin(phi) / big)
    gap = 0.3 * asm.across / big
    keep = [0]
    for k in range(1, len(phi)):
        if psi[k] - psi[keep[-1]] >= gap or k == len(phi) - 1:
            keep.append(k)
    if psi[keep[-1]] - psi[keep[-2]] < gap and len(keep) > 3:
        del keep[-2]
    phi, psi = phi[keep], psi[keep]
    half = len(phi)
    around = np.r_[phi, np.pi - phi[-2:0:-1]]
    meet = np.stack(
        [small * np.cos(around), small * np.sin(around), np.sqrt(big**2 - (small * np.sin(around)) ** 2)], -1
    )
    mv = asm.add(meet)
    top = meet * [1, 1, 0] + height * UP
    tv = asm.add(top)
    grid = asm.rows(np.linalg.norm(top - meet, axis=1).mean())
    branch = [asm.line(mv[q], meet[q], tv[q], top[q], grid) for q in range(len(around))]
    for q in range(len(around)):
        asm.strip(branch[q], branch[(q + 1) % len(around)], 1, q)

    def main_point(angle, x):
        return np.array([x, big * np.sin(angle), big * np.cos(angle)])

    grid = asm.rows(length)
    columns = []
    free = asm.spacing(psi[-1], 2 * np.pi - psi[-1], asm.intervals(big * (2 * np.pi - 2 * psi[-1]), asm.across))
    for k, angle in enumerate(np.r_[psi, free[1:-1]]):
        ends = [main_point(angle, -length / 2), main_point(angle, length / 2)]
        ev = asm.add(ends)
        anchors, holes = [(ev[0], 0.0, ends[0])], []
        if k in (0, half - 1):  # touches the curve at phi = -+pi/2
            anchors.append((mv[k], 0.5, meet[k]))
            holes = [(0, 1, 1)]
        elif k < half:  # crosses it at pi - phi (x < 0) and at phi (x > 0)
            low = half + (half - 2 - k)
            anchors += [(mv[low], 0.5 + meet[low, 0] / length, meet[low]), (mv[k], 0.5 + meet[k, 0] / length, meet[k])]
            holes = [(0, 1, 2)]
        anchors.append((ev[1], 1.0, ends[1]))
        columns.append(asm.ruling(anchors, grid, holes))
    for k in range(len(columns)):
        asm.strip(columns[k], columns[(k + 1) % len(columns)], 0, k)


def _draw_ybranch(rng):
    radius = rng.uniform(0.4, 0.7)
    b1, b2 = np.radians(rng.uniform(25.0, 50.0, 2))
    axes = np.array([[np.sin(b1), 0.0, np.cos(b1)], [-np.sin(b2), 0.0, np.cos(b2)]])
    crotch = _unit(axes[0] - axes[1])  # normal of the plane where the branches meet
    # How far up a branch the crotch reaches: its length is that plus 1-2.5 radii.
    frame = _unit(crotch - (crotch @ axes[0]) * axes[0])
    phi = np.linspace(np.pi / 2, 3 * np.pi / 2, 181)
    q = radius * (np.cos(phi)[:, None] * frame + np.sin(phi)[:, None] * np.array([0.0, 1.0, 0.0]))
    reach = np.max(-(q @ crotch) / (axes[0] @ crotch))
    trunk = radius * rng.uniform(1.5, 3.0)
    lengths = reach + radius * rng.uniform(1.0, 2.5, 2)
    return {
        "radius": radius,
        "angles": (b1, b2),
        "axes": axes,
        "trunk_length": trunk,
        "branch_lengths": lengths,
        "area": 2 * np.pi * radius * (trunk + lengths.sum()),
    }


def _build_ybranch(g, asm):
    r, axes, lengths = g["radius"], g["axes"], g["branch_lengths"]
    y = np.array([0.0, 1.0, 0.0])
    mitres = _unit(UP + axes)  # trunk / branch i: the plane that halves the turn
    crotch = _unit(axes[0] - axes[1])
    n = asm.intervals(np.pi * r, asm.across)
    # The trunk's columns: the half facing branch 0 (x >= 0, -pi/2 .. pi/2) meets it, the other
    # half branch 1; both halves share the columns at +-pi/2, whose tops are the triple points.
    theta = np.r_[asm.spacing(-np.pi / 2, np.pi / 2, n), asm.spacing(np.pi / 2, 3 * np.pi / 2, n)[1:-1]]
    base = r * np.stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)], -1)
    facing = np.where(np.arange(len(theta)) <= n, 0, 1)
    top = base - ((np.einsum("ij,ij->i", base, mitres[facing])) / (mitres[facing] @ UP))[:, None] * UP
    bottom = base - g["trunk_length"] * UP
    top_v, bottom_v = asm.add(top), asm.add(bottom)
    grid = asm.rows(np.linalg.norm(top - bottom, axis=1).mean())
    trunk = [asm.line(bottom_v[k], bottom[k], top_v[k], top[k], grid) for k in range(len(theta))]
    for k in range(len(trunk)):
        asm.strip(trunk[k], trunk[(k + 1) % len(trunk)], 0, k)
    # The crotch: branch 0's columns on its inner half, cut by the plane between the branches.
    frame = _unit(crotch - (crotch @ axes[0]) * axes[0])
    phi = asm.spacing(np.pi / 2, 3 * np.pi / 2, n)[1:-1]
    q = r * (np.cos(phi)[:, None] * frame + np.sin(phi)[:, None] * y)
    inner = q - ((q @ crotch) / (axes[0] @ crotch))[:, None] * axes[0]
    inner_v = asm.add(inner)
    for i in range(2):
        own = np.arange(n + 1) if i == 0 else np.r_[np.arange(n, len(theta)), 0]
        seam_v, seam = np.r_[top_v[own], inner_v], np.vstack([top[own], inner])
        away = _unit((1 - 2 * i) * crotch - ((1 - 2 * i) * crotch @ axes[i]) * axes[i])
        angle = np.mod(np.arctan2(seam @ np.cross(axes[i], away), seam @ away) + np.pi / 2, 2 * np.pi)
        order = np.argsort(angle)
        seam_v, seam = seam_v[order], seam[order]
        end = seam + (lengths[i] - seam @ axes[i])[:, None] * axes[i]
        end_v = asm.add(end)
        grid = asm.rows(np.linalg.norm(end - seam, axis=1).mean())
        columns = [asm.line(seam_v[k], seam[k], end_v[k], end[k], grid) for k in range(len(seam))]
        for k in range(len(columns)):
            asm.strip(columns[k], columns[(k + 1) % len(columns)], 1 + i, k)


def _draw_cup(rng):
    bottom = rng.uniform(0.5, 0.8)
    top = bottom * rng.uniform(1.2, 1.6)
    height = bottom * rng.uniform(1.5, 3.0)
    return {
        "radii": (bottom, top),
        "height": height,
        "area": np.pi * (bottom + top) * np.hypot(height, top - bottom) + np.pi * bottom**2,
    }


def _build_cup(g, asm):
    (rb, rt), height = g["radii"], g["height"]
    count = asm.intervals(np.pi * (rb + rt), asm.across)
    theta = asm.spacing(0, 2 * np.pi, count, closed=True)
    around = np.stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)], -1)
    rim = (asm.add(rb * around), rb * around)
    asm.tube([rim, (asm.add(rt * around + height * UP), rt * around + height * UP)], [0])
    # The bottom: rings around its centre, as many points on each as its length takes (slivers:
    # the side's count on every ring, a polar grid of ever thinner cells).
    rings = [_Column(asm.add(np.zeros(3)), np.zeros(1), np.zeros((1, 3)))]
    for radius in rb * asm.spacing(0, 1, asm.intervals(rb, asm.along))[1:-1]:
        n = count if asm.style == "slivers" else max(3, asm.intervals(2 * np.pi * radius, asm.across))
        angles = asm.spacing(0, 2 * np.pi, n, closed=True)
        p = radius * np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], -1)
        rings.append(asm.ring(asm.add(p), angles, p))
    rings.append(asm.ring(rim[0], theta, rim[1]))
    for k in range(len(rings) - 1):
        asm.strip(rings[k], rings[k + 1], 1, k)


def _draw_holed_sheet(rng):
    width, depth = rng.uniform(1.5, 3.0), rng.uniform(1.0, 2.0)
    holes = [(width * rng.uniform(0.3, 0.7), depth * rng.uniform(0.35, 0.65), depth * rng.uniform(0.12, 0.22))]
    wanted = int(rng.integers(1, 4))
    for _ in range(50):  # more holes where they fit, clear of the edges and of each other
        if len(holes) == wanted:
            break
        rho = depth * rng.uniform(0.08, 0.18)
        u, v = rng.uniform(rho + 0.1 * depth, width - rho - 0.1 * depth), rng.uniform(
            rho + 0.1 * depth, depth - rho - 0.1 * depth
        )
        if all(np.hypot(u - a, v - b) > rho + c + 0.15 * depth for a, b, c in holes):
            holes.append((u, v, rho))
    bent = bool(rng.integers(2))
    turn = np.radians(rng.uniform(40.0, 120.0)) if bent else 0.0
    radius = width * rng.uniform(0.15, 0.4)
    if bent:
        radius = min(radius, 0.5 * width / turn)
    start = width * rng.uniform(0.15, 0.85 - radius * turn / width)
    return {
        "width": width,
        "depth": depth,
        "holes": holes,
        "bent": bent,
        "turn": turn,
        "bend_radius": radius,
        "bend_start": start,
        "area": width * depth,
    }


def _sheet_point(g, u, v):
    """The sheet's point at developed coordinates (u across, v along the rulings): flat up to
    bend_start, then around a cylinder of bend_radius by `turn`, then flat again."""
    u, v = np.asarray(u, dtype=np.float64), np.asarray(v, dtype=np.float64)
    s, r, turn = g["bend_start"], g["bend_radius"], g["turn"]
    if not g["bent"]:
        return np.stack([u, v, np.zeros_like(u)], -1)
    angle = np.clip(u - s, 0, r * turn) / r
    beyond = np.maximum(u - s - r * turn, 0)
    x = np.minimum(u, s) + r * np.sin(angle) + beyond * np.cos(turn)
    z = r * (1 - np.cos(angle)) + beyond * np.sin(turn)
    return np.stack([x, v, z], -1)


def _build_holed_sheet(g, asm):
    width, depth = g["width"], g["depth"]
    u = asm.spacing(0, width, asm.intervals(width, asm.across))
    # Each hole's leftmost and rightmost points move to the nearest columns (it stays round):
    # between them, every column crosses it at two vertices; those two only touch it.
    holes = []
    for centre_u, centre_v, rho in g["holes"]:
        lo = int(np.argmin(np.abs(u - (centre_u - rho))))
        hi = max(int(np.argmin(np.abs(u - (centre_u + rho)))), lo + 2)
        if hi >= len(u) - 1:
            continue
        cu, radius = (u[lo] + u[hi]) / 2, (u[hi] - u[lo]) / 2
        clear = 0.05 * depth + radius
        if (
            clear < centre_v < depth - clear
            and lo >= 1
            and all(np.hypot(cu - a, centre_v - b) > radius + c + 0.05 * depth for a, b, c, _, _ in holes)
        ):
            holes.append((cu, centre_v, radius, lo, hi))
    if not holes:
        raise ValueError("no hole fits the holed sheet at this spacing (too few faces?)")
    grid = asm.rows(depth)
    columns = []
    for k, x in enumerate(u):
        ends = _sheet_point(g, [x, x], [0.0, depth])
        ev = asm.add(ends)
        inside = []  # (v, hole, vertices of the hole on this column)
        for h, (cu, cv, radius, lo, hi) in enumerate(holes):
            if lo <= k <= hi:
                half = 0.0 if k in (lo, hi) else np.sqrt(max(radius**2 - (x - cu) ** 2, 0.0))
                vs = [cv] if k in (lo, hi) else [cv - half, cv + half]
                p = _sheet_point(g, [x] * len(vs), vs)
                inside.append((cv, h, list(zip(asm.add(p), vs, p))))
        anchors, cuts = [(ev[0], 0.0, ends[0])], []
        for _, h, points in sorted(inside, key=lambda item: item[0]):
            cuts.append((h, len(anchors), len(anchors) + len(points) - 1))
            anchors += [(vertex, v / depth, p) for vertex, v, p in points]
        anchors.append((ev[1], 1.0, ends[1]))
        columns.append(asm.ruling(anchors, grid, cuts))
    for k in range(len(columns) - 1):
        asm.strip(columns[k], columns[k + 1], 0, k)
    asm.info["holes_meshed"] = len(holes)


_DRAW = {
    "transition": _draw_transition,
    "reducer": _draw_reducer,
    "elbow4": lambda rng: _draw_elbow(rng, 4),
    "elbow6": lambda rng: _draw_elbow(rng, 6),
    "tee": _draw_tee,
    "ybranch": _draw_ybranch,
    "cup": _draw_cup,
    "holed_sheet": _draw_holed_sheet,
}
_BUILD = {
    "transition": _build_transition,
    "reducer": _build_reducer,
    "elbow4": _build_elbow,
    "elbow6": _build_elbow,
    "tee": _build_tee,
    "ybranch": _build_ybranch,
    "cup": _build_cup,
    "holed_sheet": _build_holed_sheet,
}


# -- the generators ---------------------------------------------------------------------------


def make(part, triangulation="grid", faces=3000, noise=0.02, seed=0):
    """An AssemblyMesh of `part` (PARTS) in `triangulation` (TRIANGULATIONS) with about `faces`
    triangles (at least MIN_FACES; within 10 % but where whole rows forbid it: every piece has
    two rows at least, so six sliver gores take 700 faces, and from 1000 faces on the count is
    within 25 %), noise amplitude in AE (0.005-0.05 in the issue), dimensions and orientation
    drawn from `seed`."""
    if part not in PARTS:
        raise ValueError("unknown part %r (assemblies.PARTS)" % part)
    if triangulation not in TRIANGULATIONS:
        raise ValueError("unknown triangulation %r (assemblies.TRIANGULATIONS)" % triangulation)
    if faces < MIN_FACES:
        raise ValueError("faces must be at least %d" % MIN_FACES)
    which = [seed, PARTS.index(part), TRIANGULATIONS.index(triangulation)]
    rng = np.random.default_rng([seed, PARTS.index(part), 35])
    geometry = _DRAW[part](rng)
    rotation, shift = _random_rotation(rng), rng.uniform(-1.0, 1.0, 3)

    def build(h):
        asm = _Assembly(triangulation, h, np.random.default_rng(which + [1]))
        _BUILD[part](geometry, asm)
        return asm.finish()

    # Two faces per h x h cell; the seams, apexes and rows rounded to whole numbers make the
    # count differ, so the spacing is corrected from the count (the closest of six builds kept:
    # on short gores a row more or less is a jump).
    h = np.sqrt(2 * geometry["area"] / faces)
    best = None
    for attempt in range(6):
        points, triangles, pieces, built = build(h)
        if best is None or abs(len(triangles) - faces) < abs(len(best[1]) - faces):
            best = (points, triangles, pieces, built, h)
        if abs(len(triangles) / faces - 1) <= 0.1:
            break
        h *= (len(triangles) / faces) ** (0.5 ** (attempt + 1))  # damped: steps would oscillate
    points, triangles, pieces, built, h = best
    clean = points @ rotation.T + shift
    edges = np.unique(
        np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1), axis=0
    )
    ae = np.linalg.norm(clean[edges[:, 0]] - clean[edges[:, 1]], axis=1).mean()
    positions = clean + np.random.default_rng(which + [2]).uniform(-1.0, 1.0, clean.shape) * noise * ae
    edge, f, g, _ = _edge_faces(triangles)
    creases = edge[pieces[f] != pieces[g]].astype(np.int32)
    info = {key: value for key, value in geometry.items() if key not in ("rings", "area")}
    info.update(built, ae=ae, spacing=h)
    return AssemblyMesh(
        part, triangulation, seed, noise, positions, clean, triangles, pieces, NATURAL_PIECES[part], creases, info
    )


def random_case(part, seed, faces=(1000, 8000), noise=(0.005, 0.05), triangulations=None):
    """make() with the face count (log-uniform over `faces`), the noise (log-uniform over `noise`)
    and the triangulation (one of `triangulations`, default all) drawn from `seed` too."""
    rng = np.random.default_rng([seed, 7927, PARTS.index(part)])
    options = list(triangulations or TRIANGULATIONS)
    triangulation = options[int(rng.integers(len(options)))]
    count = int(np.exp(rng.uniform(np.log(faces[0]), np.log(faces[1]))))
    amplitude = float(np.exp(rng.uniform(np.log(noise[0]), np.log(noise[1]))))
    return make(part, triangulation, count, amplitude, seed)


def scan_sheet(family, triangulation="grid", faces=3000, noise=0.2, seed=0):
    """families.make with scan-like noise: `noise` in AE, 0.1-0.5 for "sheets with scan noise of
    10-50 % of the edge length" (families.random_case draws 0.5-5 %). A families.FamilyMesh."""
    return families.make(family, triangulation, faces, noise, seed)


def random_scan_sheet(family, seed, faces=(1000, 8000), noise=(0.1, 0.5)):
    """scan_sheet with the triangulation (every one the family takes), the face count and the
    noise (both log-uniform) drawn from `seed`."""
    rng = np.random.default_rng([seed, 7933, families.FAMILIES.index(family)])
    options = [t for t in TRIANGULATIONS if not (family == "curved_fold" and t == "irregular")]
    triangulation = options[int(rng.integers(len(options)))]
    count = int(np.exp(rng.uniform(np.log(faces[0]), np.log(faces[1]))))
    amplitude = float(np.exp(rng.uniform(np.log(noise[0]), np.log(noise[1]))))
    return scan_sheet(family, triangulation, count, amplitude, seed)

"""Quality measures computed in numpy, the same for the engine's results and
for any other tool's output (bench/run.py --compare), in tests and bench."""
import numpy as np

FLAT = 1e-3  # rad: an interior vertex with |defect| below this counts as developable
RULED = 0.02  # rad: a vertex whose ruled_spread is below this counts as ruled


def boundary_vertices(n, triangles):
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.sort(e, axis=1)
    key = e[:, 0].astype(np.int64) * n + e[:, 1]
    uniq, count = np.unique(key, return_counts=True)
    once = uniq[count == 1]
    mask = np.zeros(n, dtype=bool)
    mask[once // n] = True
    mask[once % n] = True
    return mask


def angle_defects(positions, triangles):
    """2 pi minus the angle sum at every vertex (boundary and unused vertices: 0),
    and the interior mask."""
    n = len(positions)
    tri = positions[triangles]
    defect = np.full(n, 2 * np.pi)
    for k in range(3):
        a, b, c = tri[:, k], tri[:, (k + 1) % 3], tri[:, (k + 2) % 3]
        u, v = b - a, c - a
        angle = np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))
        defect -= np.bincount(triangles[:, k], weights=angle, minlength=n)
    used = np.bincount(triangles.ravel(), minlength=n) > 0
    interior = used & ~boundary_vertices(n, triangles)
    defect[~interior] = 0.0
    return defect, interior


def average_edge_length(positions, triangles):
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    return float(np.linalg.norm(positions[e[:, 0]] - positions[e[:, 1]], axis=1).mean())


def defect_summary(positions, triangles):
    d, interior = angle_defects(positions, triangles)
    a = np.abs(d[interior])
    if not len(a):
        return {"mean": float("nan"), "max": float("nan"), "flat": float("nan")}
    return {"mean": float(a.mean()), "max": float(a.max()), "flat": float((a < FLAT).mean())}


def flat_share(defects, interior):
    """Share of the interior vertices with |defect| < FLAT (0..1)."""
    return float(np.mean(np.abs(defects[interior]) < FLAT))


def face_normals(positions, triangles):
    """Unit normals (m, 3) of the triangles (zero-area ones: a zero vector)."""
    p = positions[triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def turned_faces(before, after, triangles):
    """Per face: the cosine of the angle its normal turned from `before` to
    `after` (< 0: turned over by more than 90 degrees, a fold)."""
    return np.einsum("ij,ij->i", face_normals(before, triangles), face_normals(after, triangles))


def seam_vertices(n, triangles, patch_ids):
    """Vertices whose faces belong to more than one patch."""
    first = np.full(n, -1)
    seam = np.zeros(n, dtype=bool)
    for corner in range(3):
        v = triangles[:, corner]
        unset = first[v] < 0
        first[v[unset]] = patch_ids[unset]
        seam[v[first[v] != patch_ids]] = True
    return seam


def sharpened_edges(before, after, triangles, patch_ids=None, growth_degrees=20.0):
    """Edges of two faces (of one patch, when patch_ids is given) whose angle
    between the face normals grew by more than growth_degrees from `before`
    to `after`: creases the run made (the engine's crease guard, measures.h).
    Returns the (k, 2) face pairs."""
    sides = {}
    for f, t in enumerate(np.asarray(triangles).tolist()):
        for k in range(3):
            a, b = t[k], t[(k + 1) % 3]
            sides.setdefault((min(a, b), max(a, b)), []).append(f)
    pairs = np.array([fs for fs in sides.values() if len(fs) == 2], dtype=int).reshape(-1, 2)
    if patch_ids is not None:
        pairs = pairs[patch_ids[pairs[:, 0]] == patch_ids[pairs[:, 1]]]

    def angles(positions):
        n = face_normals(positions, triangles)
        return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", n[pairs[:, 0]], n[pairs[:, 1]]), -1.0, 1.0)))

    return pairs[angles(after) - angles(before) > growth_degrees]


def tip_angles(positions, triangles):
    """(m, 3): the angle (rad) of every triangle at each of its corners."""
    tri = positions[triangles]
    out = np.empty(triangles.shape)
    for k in range(3):
        u, v = tri[:, (k + 1) % 3] - tri[:, k], tri[:, (k + 2) % 3] - tri[:, k]
        out[:, k] = np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))
    return out


def ruled_spread(positions, triangles):
    """Per vertex: how far (rad) the unit normals of the faces around it spread off their
    best-fitting great circle. A developable surface is flat (zero angle defect) and ruled: a
    straight line runs through every point, the normals along it are parallel, so the normals
    around a vertex lie on one great circle (one arc: a cylinder's, a cone's; two points: a
    fold). A mesh can have zero angle defects and still be crumpled (a Miura-ori, scan noise
    polished flat vertex by vertex); this measure sees that. It is the covariance measure of
    Stein, Grinspun, Crane, "Developability of triangle meshes" (2018): with
    M = sum over the faces f around the vertex of w_f n_f n_f^T, its smallest eigenvalue
    lambda_min is the weighted sum of the squared sines of the normals' angles off the great
    circle orthogonal to its eigenvector (the circle that makes that sum least); the spread is
    arcsin(sqrt(lambda_min / sum of w_f)), a root mean square of those angles.

    Weights: the faces' angles at the vertex (tip angles), as Stein et al. weigh them, rather
    than areas or nothing: the weights then cover the vertex's surroundings the same way
    however its star is cut (a fan of thin triangles weighs what one triangle over the same
    angle weighs), so the figure does not depend on the triangulation, and a long sliver
    reaching far from the vertex does not outweigh its neighbours.

    Vertices with fewer than 3 faces: 0 (one or two normals always lie on a great circle).
    Boundary vertices: NaN, never counted as ruled: their faces cover only part of a disc
    around them, and the fit would grade a rim by half a star.
    Vectorised: bincount per entry of M, one batched eigvalsh."""
    positions = np.asarray(positions, dtype=np.float64)
    n = len(positions)
    normals = np.repeat(face_normals(positions, triangles), 3, axis=0)  # per corner
    corner = np.asarray(triangles).ravel()
    weight = tip_angles(positions, triangles).ravel()
    m = np.empty((n, 3, 3))
    for i in range(3):
        for j in range(i, 3):
            m[:, i, j] = m[:, j, i] = np.bincount(corner, weight * normals[:, i] * normals[:, j], minlength=n)
    total = np.bincount(corner, weight, minlength=n)
    smallest = np.linalg.eigvalsh(m)[:, 0]
    spread = np.arcsin(np.sqrt(np.clip(smallest / np.maximum(total, 1e-300), 0.0, 1.0)))
    spread[np.bincount(corner, minlength=n) < 3] = 0.0
    spread[boundary_vertices(n, np.asarray(triangles))] = np.nan
    return spread


def developability_figures(positions, triangles, interior=None, flat=FLAT, ruled=RULED):
    """Shares (0..1) of the counted vertices that are flat (|angle defect| < flat rad),
    ruled (ruled_spread < ruled rad), flat and ruled (developable in the sense of Stein et
    al.), and crumpled (flat but not ruled), with their count. interior: a mask of the
    vertices to count (e.g. those off the seams of a piecewise developable part); only its
    interior vertices are counted; default every interior vertex. Shares are NaN when no
    vertex is counted."""
    defects, inner = angle_defects(np.asarray(positions, dtype=np.float64), np.asarray(triangles))
    counted = inner if interior is None else inner & np.asarray(interior, dtype=bool)
    is_flat = np.abs(defects[counted]) < flat
    with np.errstate(invalid="ignore"):  # NaN (boundary) spreads are not ruled
        is_ruled = ruled_spread(positions, triangles)[counted] < ruled
    count = int(counted.sum())

    def share(mask):
        return float(mask.mean()) if count else float("nan")

    return {
        "vertices": count,
        "flat": share(is_flat),
        "ruled": share(is_ruled),
        "flat_and_ruled": share(is_flat & is_ruled),
        "crumpled": share(is_flat & ~is_ruled),
    }


def dihedral_angles(positions, triangles, edges):
    """Per edge (vertex pair, (e, 2)) shared by two faces: the angle (rad) between their unit
    normals, 0 where they lie flat, pi / 2 at a right-angled crease. ValueError for an edge
    that is not between two faces."""
    triangles, edges = np.asarray(triangles), np.asarray(edges)
    n = len(positions)
    sides = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    keys = sides[:, 0].astype(np.int64) * n + sides[:, 1]
    order = np.argsort(keys, kind="stable")
    keys = keys[order]
    face = np.tile(np.arange(len(triangles)), 3)[order]
    wanted = np.sort(edges, axis=1)
    query = wanted[:, 0].astype(np.int64) * n + wanted[:, 1]
    first = np.searchsorted(keys, query)
    second = np.minimum(first + 1, len(keys) - 1)
    if len(query) and not (np.all(keys[np.minimum(first, len(keys) - 1)] == query) and np.all(keys[second] == query)):
        raise ValueError("dihedral_angles: an edge is not shared by two faces")
    normals = face_normals(np.asarray(positions, dtype=np.float64), triangles)
    cosine = np.einsum("ij,ij->i", normals[face[first]], normals[face[second]])
    return np.arccos(np.clip(cosine, -1.0, 1.0))

"""Quality measures computed in numpy, the same for the engine's results and
for any other tool's output (bench/run.py --compare), in tests and bench."""
import numpy as np

FLAT = 1e-3  # rad: an interior vertex with |defect| below this counts as developable


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

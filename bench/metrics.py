"""Quality measures computed in numpy, the same for the engine and for any
other tool's output (--compare)."""
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

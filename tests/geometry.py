"""Exact distances between triangle meshes, for quality bounds (numpy only)."""
import numpy as np


def _dot(x, y):
    return np.sum(x * y, axis=-1)


def point_triangle_distance(points, a, b, c):
    """Exact distance from each point (k, 3) to a triangle (a, b, c): one
    triangle (3,) for all points, or one per point (k, 3). Ericson, Real-Time
    Collision Detection, 5.1.5, vectorised."""
    points = np.asarray(points, dtype=np.float64)
    a, b, c = (np.broadcast_to(x, points.shape) for x in (a, b, c))
    ab, ac = b - a, c - a
    ap = points - a
    d1, d2 = _dot(ap, ab), _dot(ap, ac)
    bp = points - b
    d3, d4 = _dot(bp, ab), _dot(bp, ac)
    cp = points - c
    d5, d6 = _dot(cp, ab), _dot(cp, ac)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    denom = va + vb + vc
    denom = np.where(np.abs(denom) < 1e-300, 1e-300, denom)
    v = vb / denom
    w = vc / denom
    closest = a + v[:, None] * ab + w[:, None] * ac  # inside the face
    # Regions, in Ericson's order of precedence (applied last-to-first so the
    # earliest test wins).
    def blend(mask, value):
        closest[mask] = value[mask]

    with np.errstate(divide="ignore", invalid="ignore"):
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        blend((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + t_bc[:, None] * (c - b))
        t_ac = d2 / (d2 - d6)
        blend((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + t_ac[:, None] * ac)
        t_ab = d1 / (d1 - d3)
        blend((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + t_ab[:, None] * ab)
    blend((d6 >= 0) & (d5 <= d6), c)
    blend((d3 >= 0) & (d4 <= d3), b)
    blend((d1 <= 0) & (d2 <= 0), a)
    return np.linalg.norm(points - closest, axis=1)


def samples(positions, triangles):
    """Vertices, edge midpoints and face centroids: where a one-sided distance
    between two triangle meshes of the same connectivity peaks in practice."""
    tri = positions[triangles]
    mids = np.concatenate([(tri[:, 0] + tri[:, 1]) / 2, (tri[:, 1] + tri[:, 2]) / 2,
                           (tri[:, 2] + tri[:, 0]) / 2])
    return np.concatenate([positions, mids, tri.mean(axis=1)])


def one_sided(points, positions, triangles, chunk=512, candidates=24):
    """max over points of the exact distance to the nearest triangle.

    Triangles are ranked by the distance to their bounding box (a lower bound);
    the exact distance to the nearest `candidates` decides, and a point whose
    answer is not below the next lower bound is checked against all."""
    tri = positions[triangles]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    k = min(candidates, len(tri))
    worst = 0.0
    for start in range(0, len(points), chunk):
        p = points[start:start + chunk]
        gap = np.maximum(np.maximum(lo[None] - p[:, None], p[:, None] - hi[None]), 0)
        box = np.einsum("ijk,ijk->ij", gap, gap)
        nearest = np.argpartition(box, k - 1, axis=1)[:, :k] if k < len(tri) else \
            np.tile(np.arange(len(tri)), (len(p), 1))
        exact = np.full(len(p), np.inf)
        for column in range(nearest.shape[1]):
            j = nearest[:, column]
            exact = np.minimum(exact, _distance_rows(p, tri[j]))
        if k < len(tri):
            bound = np.sqrt(np.partition(box, k, axis=1)[:, k])
            for row in np.nonzero(exact > bound)[0]:
                exact[row] = min(point_triangle_distance(p[row:row + 1], *t)[0] for t in tri)
        worst = max(worst, float(exact.max()))
    return worst


def _distance_rows(points, triangles):
    """Distance from points[i] to triangles[i], row by row."""
    return point_triangle_distance(points, triangles[:, 0], triangles[:, 1], triangles[:, 2])


def hausdorff(pos_a, tri_a, pos_b, tri_b):
    """Symmetric Hausdorff distance between two triangle meshes, measured
    from the vertices, edge midpoints and centroids of each to the exact
    surface of the other."""
    return max(one_sided(samples(pos_a, tri_a), pos_b, tri_b),
               one_sided(samples(pos_b, tri_b), pos_a, tri_a))


def bbox_diagonal(positions):
    return float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))

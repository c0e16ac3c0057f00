"""Exact distances between triangle meshes, for quality bounds (numpy, scipy)."""
import numpy as np
from scipy.spatial import cKDTree


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


def one_sided(points, positions, triangles, candidates=8):
    """max over points of the exact distance to the nearest triangle.

    The triangles whose centroids are nearest are tried first; a triangle t
    farther than |p - centroid_t| - radius_t cannot be nearer, so a point whose
    answer beats that bound for every untried triangle is done, and the few
    others are checked against every triangle within reach."""
    tri = positions[triangles]
    centroids = tri.mean(axis=1)
    radius = np.linalg.norm(tri - centroids[:, None], axis=2).max()
    tree = cKDTree(centroids)
    k = min(candidates, len(tri))
    reach, nearest = tree.query(points, k=k)
    reach, nearest = reach.reshape(len(points), k), nearest.reshape(len(points), k)
    exact = np.full(len(points), np.inf)
    for column in range(k):
        t = tri[nearest[:, column]]
        exact = np.minimum(exact, point_triangle_distance(points, t[:, 0], t[:, 1], t[:, 2]))
    if k < len(tri):
        rows = np.nonzero(exact > reach[:, -1] - radius)[0]
        for start in range(0, len(rows), 4096):
            chunk = rows[start:start + 4096]
            near = tree.query_ball_point(points[chunk], exact[chunk] + radius)
            owner = np.repeat(chunk, [len(n) for n in near])
            t = tri[np.concatenate(near).astype(np.int64)]
            d = point_triangle_distance(points[owner], t[:, 0], t[:, 1], t[:, 2])
            np.minimum.at(exact, owner, d)
    return float(exact.max())


def hausdorff(pos_a, tri_a, pos_b, tri_b):
    """Symmetric Hausdorff distance between two triangle meshes, measured
    from the vertices, edge midpoints and centroids of each to the exact
    surface of the other."""
    return max(one_sided(samples(pos_a, tri_a), pos_b, tri_b),
               one_sided(samples(pos_b, tri_b), pos_a, tri_a))


def bbox_diagonal(positions):
    return float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))

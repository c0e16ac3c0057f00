"""Distances between triangle meshes (numpy only).

point_triangle_distance is exact. sampled_hausdorff measures the samples of
each mesh (vertices, edge midpoints, face centroids) against the exact
surface of the other: exact for those points, so it is a lower bound of the
true Hausdorff distance, equal to it when the farthest point is a sample
(in practice, for two meshes of the same connectivity, it peaks there).

Candidate triangles come from a uniform grid of cell size ~ one mean edge
length: every triangle is listed in each cell its bounding box overlaps, and
a point with search radius r looks at the cells overlapping the box
[p - r, p + r]. Any triangle outside those cells is farther than r, so a
point whose nearest candidate is within r has its exact answer; the others
are searched again with r set to the distance found (or doubled when nothing
was found). No correspondence between the meshes is needed, so the same code
measures other tools' outputs; millions of faces take seconds."""
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
    mids = np.concatenate([(tri[:, 0] + tri[:, 1]) / 2, (tri[:, 1] + tri[:, 2]) / 2, (tri[:, 2] + tri[:, 0]) / 2])
    return np.concatenate([positions, mids, tri.mean(axis=1)])


def _expand(lo, hi):
    """For integer boxes lo..hi (k, 3) inclusive: (owner row, cell ix, iy, iz)
    of every cell in every box."""
    span = hi - lo + 1
    count = span[:, 0] * span[:, 1] * span[:, 2]
    owner = np.repeat(np.arange(len(lo)), count)
    first = np.cumsum(count) - count
    local = np.arange(count.sum()) - np.repeat(first, count)
    sx, sy = span[owner, 0], span[owner, 1]
    ix = lo[owner, 0] + local % sx
    iy = lo[owner, 1] + (local // sx) % sy
    iz = lo[owner, 2] + local // (sx * sy)
    return owner, ix, iy, iz


class TriangleGrid:
    def __init__(self, positions, triangles, cell=None):
        self.tri = np.ascontiguousarray(positions[triangles], dtype=np.float64)
        self.lo = self.tri.min(axis=1)
        self.hi = self.tri.max(axis=1)
        if cell is None:
            edges = np.linalg.norm(self.tri - np.roll(self.tri, 1, axis=1), axis=2)
            cell = 1.5 * float(edges.mean())
        extent = float(np.max(self.hi.max(axis=0) - self.lo.min(axis=0)))
        self.cell = max(cell, extent / 1024.0, 1e-300)  # at most ~1024 cells per side
        self.origin = self.lo.min(axis=0)
        self.dims = np.floor((self.hi.max(axis=0) - self.origin) / self.cell).astype(np.int64) + 1
        keys, tris = [], []
        step = 1 << 20
        for start in range(0, len(self.tri), step):
            lo = self._index(self.lo[start : start + step])
            hi = self._index(self.hi[start : start + step])
            owner, ix, iy, iz = _expand(lo, hi)
            keys.append(self._key(ix, iy, iz))
            tris.append(owner + start)
        keys, tris = np.concatenate(keys), np.concatenate(tris)
        order = np.argsort(keys, kind="stable")
        keys, self.items = keys[order], tris[order]
        self.keys, first = np.unique(keys, return_index=True)
        self.starts = first
        self.ends = np.append(first[1:], len(keys))

    def _index(self, points):
        idx = np.floor((points - self.origin) / self.cell).astype(np.int64)
        return np.clip(idx, 0, self.dims - 1)

    def _key(self, ix, iy, iz):
        return ix + self.dims[0] * (iy + self.dims[1] * iz)

    def candidates(self, points, radius):
        """(point row, triangle) pairs: triangles in the cells overlapping each
        point's box of half-size radius, pruned by their bounding boxes."""
        owner, ix, iy, iz = _expand(self._index(points - radius[:, None]), self._index(points + radius[:, None]))
        key = self._key(ix, iy, iz)
        slot = np.searchsorted(self.keys, key)
        slot = np.minimum(slot, len(self.keys) - 1)
        hit = self.keys[slot] == key
        owner, slot = owner[hit], slot[hit]
        count = self.ends[slot] - self.starts[slot]
        pair_owner = np.repeat(owner, count)
        first = np.cumsum(count) - count
        local = np.arange(count.sum()) - np.repeat(first, count)
        pair_tri = self.items[np.repeat(self.starts[slot], count) + local]
        p = points[pair_owner]
        gap = np.maximum(np.maximum(self.lo[pair_tri] - p, p - self.hi[pair_tri]), 0.0)
        keep = np.einsum("ij,ij->i", gap, gap) <= radius[pair_owner] ** 2
        return pair_owner[keep], pair_tri[keep]

    def distances(self, points, radius=None, chunk=100_000):
        """Exact distance from each point to the surface."""
        points = np.asarray(points, dtype=np.float64)
        out = np.empty(len(points))
        for start in range(0, len(points), chunk):
            out[start : start + chunk] = self._distances(
                points[start : start + chunk], None if radius is None else radius[start : start + chunk]
            )
        return out

    def _distances(self, points, radius):
        n = len(points)
        r = np.full(n, 0.5 * self.cell)
        if radius is not None:
            r = np.minimum(r, np.asarray(radius, dtype=np.float64))
        best = np.full(n, np.inf)
        todo = np.arange(n)
        for _ in range(64):
            if not len(todo):
                break
            rr = r[todo] * (1 + 1e-9) + 1e-12 * self.cell
            owner, tri = self.candidates(points[todo], rr)
            if len(owner):
                d = point_triangle_distance(points[todo][owner], self.tri[tri, 0], self.tri[tri, 1], self.tri[tri, 2])
                found = np.full(len(todo), np.inf)
                np.minimum.at(found, owner, d)
                best[todo] = np.minimum(best[todo], found)
            done = best[todo] <= rr
            rest = todo[~done]
            # Next radius: the distance already found, or twice the box.
            r[rest] = np.where(np.isfinite(best[rest]), best[rest], 2 * r[rest])
            todo = rest
        if len(todo):  # pathological: brute force
            for i in todo:
                best[i] = point_triangle_distance(
                    points[i : i + 1][[0] * len(self.tri)], self.tri[:, 0], self.tri[:, 1], self.tri[:, 2]
                ).min()
        return best


def one_sided(pos_a, tri_a, pos_b, tri_b, grid_b=None, hint=None):
    """max over the samples of A of the exact distance to the surface of B.
    hint: per-sample upper bound guess of the answer (a search radius), e.g.
    the move of the same sample when the meshes share connectivity."""
    grid = grid_b or TriangleGrid(pos_b, tri_b)
    return float(grid.distances(samples(pos_a, tri_a), hint).max())


def sampled_hausdorff(pos_a, tri_a, pos_b, tri_b):
    """Symmetric Hausdorff distance from the samples of each mesh to the exact
    surface of the other (see the module's docstring)."""
    hint = None
    if len(pos_a) == len(pos_b) and np.array_equal(tri_a, tri_b):
        hint = np.linalg.norm(samples(pos_a, tri_a) - samples(pos_b, tri_b), axis=1)
    return max(one_sided(pos_a, tri_a, pos_b, tri_b, hint=hint), one_sided(pos_b, tri_b, pos_a, tri_a, hint=hint))


def bbox_diagonal(positions):
    return float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))

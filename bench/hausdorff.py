"""Exact two-sided Hausdorff distance between triangle meshes, fast enough for
millions of faces in numpy.

Samples of one mesh (vertices, edge midpoints, face centroids: the same set as
tests/geometry.py) are measured against the exact surface of the other
(point-to-triangle, Ericson). Candidate triangles come from a uniform grid of
cell size ~ one mean edge length: every triangle is listed in each cell its
bounding box overlaps, and a point with search radius r looks at the cells
overlapping the box [p - r, p + r]. Any triangle outside those cells is farther
than r, so a point whose nearest candidate is within r has its exact answer;
the others are searched again with r set to the distance found (or doubled
when nothing was found). No correspondence between the meshes is needed, so
the same code measures other tools' outputs."""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "tests"))
from geometry import point_triangle_distance, samples  # noqa: E402


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
            lo = self._index(self.lo[start:start + step])
            hi = self._index(self.hi[start:start + step])
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
        owner, ix, iy, iz = _expand(self._index(points - radius[:, None]),
                                    self._index(points + radius[:, None]))
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
            out[start:start + chunk] = self._distances(
                points[start:start + chunk],
                None if radius is None else radius[start:start + chunk])
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
                d = point_triangle_distance(points[todo][owner], self.tri[tri, 0],
                                            self.tri[tri, 1], self.tri[tri, 2])
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
                best[i] = point_triangle_distance(points[i:i + 1][[0] * len(self.tri)],
                                                  self.tri[:, 0], self.tri[:, 1],
                                                  self.tri[:, 2]).min()
        return best


def one_sided(pos_a, tri_a, pos_b, tri_b, grid_b=None, hint=None):
    """max over the samples of A of the exact distance to the surface of B.
    hint: per-sample upper bound guess of the answer (a search radius), e.g.
    the move of the same sample when the meshes share connectivity."""
    grid = grid_b or TriangleGrid(pos_b, tri_b)
    pts = samples(pos_a, tri_a)
    return float(grid.distances(pts, hint).max())


def hausdorff(pos_a, tri_a, pos_b, tri_b):
    """Symmetric Hausdorff distance (same sampling as tests/geometry.py)."""
    hint_ab = hint_ba = None
    if len(pos_a) == len(pos_b) and np.array_equal(tri_a, tri_b):
        move = np.linalg.norm(samples(pos_a, tri_a) - samples(pos_b, tri_b), axis=1)
        hint_ab = hint_ba = move
    return max(one_sided(pos_a, tri_a, pos_b, tri_b, hint=hint_ab),
               one_sided(pos_b, tri_b, pos_a, tri_a, hint=hint_ba))

# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's own checks of a mesh, in numpy (no bpy): what to hand the
engine, where a mesh the engine refused is bad (so that it can be selected and
named in plain words), whether it is one-sided, whether its seams are welded,
and whether its faces are flat pieces already.

Element numbers in messages are Blender's own vertex and face indices (the
engine's triangle numbers depend on how n-gons are split, which the user never
sees)."""

import re

import numpy as np

from .text import plural

# dev_validate / dev_run statuses that mean a bad mesh (native.STATUS_NAMES).
DEGENERATE_TRIANGLE = 4
DUPLICATE_TRIANGLE = 5
NON_MANIFOLD = 6
MESH_PROBLEMS = {DEGENERATE_TRIANGLE, DUPLICATE_TRIANGLE, NON_MANIFOLD}


def _edge_table(triangles):
    """Directed edges (a, b) of all triangles, with their triangle."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    a = t[:, [0, 1, 2]].reshape(-1)
    b = t[:, [1, 2, 0]].reshape(-1)
    face = np.repeat(np.arange(len(t)), 3)
    return a, b, face


def drop_shared_triangles(triangles, tri_polygon, polygon_vertex_sets):
    """Blender's validate() accepts two different faces that share a triangle
    (a triangle lying on a quad, say) and so the add-on does too: of each set
    of triangles with the same three vertices, coming from faces with different
    vertex sets, the first (lowest face index) is kept. Identical faces are left
    for the engine to refuse (validate() refuses them too).

    polygon_vertex_sets: callable(polygon index) -> frozenset of its vertices.
    Returns (triangles, tri_polygon, number dropped)."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(t) < 2:
        return triangles, tri_polygon, 0
    key = np.sort(t, axis=1)
    order = np.lexsort((tri_polygon, key[:, 2], key[:, 1], key[:, 0]))
    k = key[order]
    same = np.all(k[1:] == k[:-1], axis=1)
    if not same.any():
        return triangles, tri_polygon, 0
    keep = np.ones(len(t), dtype=bool)
    first = order[0]
    for i in np.nonzero(same)[0]:  # only over duplicates, which are few
        if i == 0 or not same[i - 1]:
            first = order[i]  # the first of a run of equal triangles
        cur = order[i + 1]
        if polygon_vertex_sets(int(tri_polygon[cur])) != polygon_vertex_sets(int(tri_polygon[first])):
            keep[cur] = False
    dropped = int((~keep).sum())
    return (
        np.ascontiguousarray(np.asarray(triangles)[keep]),
        np.ascontiguousarray(np.asarray(tri_polygon)[keep]),
        dropped,
    )


def non_manifold_edges(triangles):
    """The edges shared by more than two triangles, (k, 2) sorted vertex pairs.
    (Neighbours that disagree on orientation are no refusal: the engine turns
    faces to agree, core/orientation.h.)"""
    a, b, _ = _edge_table(triangles)
    if a.size == 0:
        return np.zeros((0, 2), np.int64)
    uniq, count = np.unique(np.sort(np.stack([a, b], axis=1), axis=1), axis=0, return_counts=True)
    return uniq[count > 2]


def _manifold_pairs(triangles):
    """The triangle pairs across edges shared by exactly two triangles:
    (first (k,), second (k,), alike (k,) bool: the two use the edge in
    opposite directions, i.e. are oriented alike), and the sorted edges (k, 2)."""
    a, b, face = _edge_table(triangles)
    if a.size == 0:
        empty = np.zeros(0, np.int64)
        return empty, empty, np.zeros(0, bool), np.zeros((0, 2), np.int64)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    order = np.argsort(lo * (int(hi.max()) + 1) + hi, kind="stable")  # faces stay in order within an edge
    lo, hi, face, forward = lo[order], hi[order], face[order], (a < b)[order]
    start = np.ones(len(lo), dtype=bool)
    start[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    run = np.cumsum(start) - 1
    count = np.bincount(run)
    first = np.nonzero(start)[0]
    two = first[count == 2]
    return face[two], face[two + 1], forward[two] != forward[two + 1], np.stack([lo[two], hi[two]], axis=1)


def degenerate_triangles(positions, triangles):
    """Mask of the triangles the engine calls degenerate (a repeated vertex, or
    zero area relative to the mesh size)."""
    p = np.asarray(positions, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(t) == 0:
        return np.zeros(0, dtype=bool)
    diagonal = np.linalg.norm(p.max(axis=0) - p.min(axis=0))
    cross = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    area2 = np.linalg.norm(cross, axis=1)
    repeated = (t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 0] == t[:, 2])
    return repeated | ~(area2 > 2e-14 * diagonal * diagonal)


def duplicate_polygons(triangles, tri_polygon):
    """Pairs (later face, earlier face) whose triangles repeat each other."""
    t = np.sort(np.asarray(triangles, dtype=np.int64).reshape(-1, 3), axis=1)
    if len(t) < 2:
        return []
    order = np.lexsort((tri_polygon, t[:, 2], t[:, 1], t[:, 0]))
    k = t[order]
    same = np.nonzero(np.all(k[1:] == k[:-1], axis=1))[0]
    pairs = {(int(tri_polygon[order[i + 1]]), int(tri_polygon[order[i]])) for i in same}
    return sorted(pairs)


def face_normals(positions, triangles):
    p = np.asarray(positions, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if t.size == 0:
        return np.zeros((0, 3))
    n = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    length = np.linalg.norm(n, axis=1)
    length[length == 0] = 1.0
    return n / length[:, None]


def diagonal(positions):
    """The bounding box's diagonal of the finite positions (0 for none)."""
    p = np.asarray(positions, dtype=np.float64)
    if len(p) == 0:
        return 0.0
    finite = p[np.isfinite(p).all(axis=1)]
    if len(finite) == 0:
        return 0.0
    return float(np.linalg.norm(finite.max(axis=0) - finite.min(axis=0)))


def boundary_vertices(triangles, n_vertices):
    """Mask of the vertices on an edge that only one triangle uses."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    mask = np.zeros(n_vertices, dtype=bool)
    if len(t) == 0:
        return mask
    a, b = t.reshape(-1), t[:, [1, 2, 0]].reshape(-1)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    keys, count = np.unique(lo * max(n_vertices, int(hi.max()) + 1) + hi, return_counts=True)
    single = keys[count == 1]
    span = max(n_vertices, int(hi.max()) + 1)
    mask[single // span] = True
    mask[single % span] = True
    return mask


# An unwelded seam: boundary vertices closer than this share of the mesh's size
# (float32 coordinates carry about 6e-8 of it; a weld that went wrong leaves
# copies at exactly one place).
WELD_DISTANCE = 1e-6


def unwelded_vertices(positions, on_boundary):
    """Boundary vertices that lie where another boundary vertex lies (within
    WELD_DISTANCE of the size): the two sides of a seam that was never
    welded, which the engine treats as two separate edges. on_boundary: the
    mask of boundary vertices (boundary_vertices). Returns their indices
    (sorted). Coordinates are snapped to a grid of that spacing twice, the
    second grid shifted by half a cell, so that a pair straddling a cell
    border is found too."""
    p = np.asarray(positions, dtype=np.float64)
    on_boundary = np.nonzero(on_boundary)[0]
    if len(on_boundary) < 2:
        return np.zeros(0, dtype=np.int64)
    q = p[on_boundary]
    if not diagonal(q) > 0:
        return on_boundary
    cell = WELD_DISTANCE * diagonal(p)
    shared = np.zeros(len(q), dtype=bool)
    for shift in (0.0, 0.5):
        keys = np.floor(q / cell + shift).astype(np.int64)
        _, inverse, count = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
        shared |= count[inverse.reshape(-1)] > 1
    return on_boundary[shared]


def _union(n, a, b):
    """Ids 0..k-1 of the sets of n elements joined by the pairs (a[i], b[i]),
    numbered in the order of their first element, and k: union-find by
    repeated hooking of roots, in numpy."""
    parent = np.arange(n)

    def root(x):
        while True:
            up = parent[x]
            if np.array_equal(up, x):
                return x
            parent[x] = parent[up]
            x = parent[x]

    while a.size:
        ra, rb = root(a), root(b)
        differ = ra != rb
        lo, hi = np.minimum(ra, rb)[differ], np.maximum(ra, rb)[differ]
        parent[hi] = lo
        a, b = a[differ], b[differ]
    _, ids = np.unique(root(np.arange(n)), return_inverse=True)
    return ids.reshape(-1), int(ids.max()) + 1 if n else 0


def flat_pieces(positions, triangles, angle):
    """Flat pieces of the mesh as it stands: triangles joined across every edge
    where their normals differ by less than `angle` (rad). Returns (piece id
    per triangle, number of pieces)."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    f, g, alike, _ = _manifold_pairs(t)
    normals = face_normals(positions, t)
    cos = np.clip((normals[f] * normals[g]).sum(axis=1), -1.0, 1.0)
    join = alike & (np.arccos(cos) < angle)
    return _union(len(t), f[join], g[join])


def flat_faced(positions, triangles, angle):
    """Whether the mesh is made of flat pieces already, its curvature all on
    the edges where they meet (a box, a prism with n-gon caps): every flat
    piece (flat_pieces) holds at least two triangles, i.e. a face the user
    drew with four or more corners, or coplanar triangles. A piece of one
    triangle carries no sign of flatness (every triangle is flat), so a
    triangulated or noisy mesh, whose every edge bends, never passes. Returns
    the number of pieces, or 0 when it does not pass."""
    ids, count = flat_pieces(positions, triangles, angle)
    if count == 0 or np.bincount(ids).min() < 2:
        return 0
    return count


def sheet_like(triangles):
    """One connected, open piece: a sheet of material (a disc, a band, a plate
    with holes), which a one-piece job suits; a closed object or one of
    several parts is no sheet."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(t) == 0 or closed(t):
        return False
    f, g, _, _ = _manifold_pairs(t)
    return _union(len(t), f, g)[1] == 1


def closed(triangles):
    """Every edge is shared by two triangles (no boundary)."""
    t = np.asarray(triangles)
    return len(t) > 0 and not boundary_vertices(t, int(t.max()) + 1).any()


def _where(world, vertices):
    """World position (x, y, z) of the mean of the given vertices, as text."""
    idx = np.asarray(vertices, dtype=np.int64).reshape(-1)
    if idx.size == 0:
        return ""
    return "near (%.3g, %.3g, %.3g)" % tuple(np.asarray(world)[idx].mean(axis=0))


def describe_problem(name, verb, status, status_name, message, world, triangles, tri_polygon):
    """For a mesh the engine refused: (what to select as (vertices, edges,
    polygons) or None, a message in the user's terms naming Blender's own
    elements). name: the object's; verb: "make X developable" or "unfold X";
    world: (n, 3) world positions (for "near (x, y, z)"); triangles and
    tri_polygon: what the engine was given and each triangle's polygon."""
    tris, tri_poly = np.asarray(triangles), np.asarray(tri_polygon)
    head = "Cannot %s (%s): " % (verb, status_name)
    tail = " Selected in Edit mode"
    if status == NON_MANIFOLD:
        many = non_manifold_edges(tris)
        if len(many):
            return (many.reshape(-1), many, ()), head + (
                "%s shared by more than two faces (a non-manifold edge), %s.%s; "
                "Select > Select All by Trait > Non Manifold shows them all."
                % (plural(len(many), "edge is", "edges are"), _where(world, many[0]), tail)
            )
        vertex = re.search(r"vertex (\d+) is non-manifold", message)
        if vertex:
            v = int(vertex.group(1))
            return ([v], (), ()), head + (
                "vertex %d is non-manifold: the surface touches itself there, %s.%s; "
                "Vertex > Rip or Separate fixes it." % (v, _where(world, [v]), tail)
            )
    if status == DEGENERATE_TRIANGLE:
        bad = np.unique(tri_poly[degenerate_triangles(world, tris)])
        if len(bad):
            return ((), (), bad), head + (
                "%s zero area (e.g. face %d), %s.%s; Mesh > Clean Up > Degenerate Dissolve "
                "removes them."
                % (
                    plural(len(bad), "face has", "faces have"),
                    bad[0],
                    _where(world, tris[tri_poly == bad[0]].reshape(-1)),
                    tail,
                )
            )
    if status == DUPLICATE_TRIANGLE:
        pairs = duplicate_polygons(tris, tri_poly)
        if pairs:
            later, earlier = pairs[0]
            faces = sorted({p for pair in pairs for p in pair})
            return ((), (), faces), head + (
                "face %d repeats the vertices of face %d (%s), %s.%s; delete one of them."
                % (
                    later,
                    earlier,
                    plural(len(pairs), "pair", "pairs"),
                    _where(world, tris[tri_poly == later].reshape(-1)),
                    tail,
                )
            )
    # Any other message naming the engine's triangles: Blender's faces instead.
    named = sorted({int(i) for i in re.findall(r"triangle (\d+)", message) if int(i) < len(tri_poly)})
    if named:
        faces = sorted({int(tri_poly[i]) for i in named})
        text = re.sub(
            r"triangle (\d+)",
            lambda m: "face %d" % tri_poly[int(m.group(1))] if int(m.group(1)) < len(tri_poly) else m.group(0),
            message,
        )
        return ((), (), faces), head + text + ("." if not text.endswith(".") else "") + tail + "."
    return None, head + message

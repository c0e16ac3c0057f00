# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's own checks, in numpy (no bpy): what to hand the engine, where a
mesh the engine refused is bad (so that it can be selected and named in
plain words), and the figures of a result in the user's terms.

Element numbers in messages are Blender's own vertex and face indices (the
engine's triangle numbers depend on how n-gons are split, which the user never
sees)."""

import numpy as np

FLAT = 1e-3  # rad: a vertex counts as flat below this |angle defect| (as in the README)


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


def bad_edges(triangles):
    """(edges shared by more than two triangles (k, 2), edges used twice in the
    same direction by two triangles: neighbours that disagree on orientation)."""
    a, b, _ = _edge_table(triangles)
    if a.size == 0:
        return np.zeros((0, 2), np.int64), np.zeros((0, 2), np.int64)
    und = np.sort(np.stack([a, b], axis=1), axis=1)
    uniq, count = np.unique(und, axis=0, return_counts=True)
    many = uniq[count > 2]
    directed, dcount = np.unique(np.stack([a, b], axis=1), axis=0, return_counts=True)
    same_dir = np.sort(directed[dcount > 1], axis=1)
    if len(many) and len(same_dir):
        n = int(max(und.max(), 0)) + 1
        same_dir = same_dir[~np.isin(same_dir[:, 0] * n + same_dir[:, 1], many[:, 0] * n + many[:, 1])]
    return many, np.unique(same_dir, axis=0) if len(same_dir) else same_dir


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


def figures(before, after, triangles, interior, defect_before, defect_after):
    """The result in the user's terms (all in the coordinates given, world space
    in the add-on): share of flat interior vertices before/after, the largest
    move as % of the size (bounding-box diagonal of `before`), and the faces
    whose normal turned by more than 90 degrees; closed: every vertex a face
    uses is interior (no boundary)."""
    before = np.asarray(before, dtype=np.float64)
    after = np.asarray(after, dtype=np.float64)
    interior = np.asarray(interior, dtype=bool)
    size = float(np.linalg.norm(before.max(axis=0) - before.min(axis=0))) if len(before) else 0.0
    move = float(np.linalg.norm(after - before, axis=1).max()) if len(before) else 0.0

    def flat(d):
        d = np.abs(np.asarray(d)[interior])
        return float((d < FLAT).mean()) if d.size else 0.0

    dots = (face_normals(before, triangles) * face_normals(after, triangles)).sum(axis=1)
    return {
        "size": size,
        "max_move": move,
        "move_percent": 100.0 * move / size if size > 0 else 0.0,
        "flat_before": flat(defect_before),
        "flat_after": flat(defect_after),
        "faces_turned": int((dots < 0.0).sum()),
        "closed": bool(interior[np.unique(np.asarray(triangles))].all()) if len(triangles) else False,
    }


def average_edge_length(positions, triangles):
    p = np.asarray(positions, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if t.size == 0:
        return 0.0
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return float(np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1).mean())


def diagonal(positions):
    p = np.asarray(positions, dtype=np.float64)
    if len(p) == 0:
        return 0.0
    finite = p[np.isfinite(p).all(axis=1)]
    if len(finite) == 0:
        return 0.0
    return float(np.linalg.norm(finite.max(axis=0) - finite.min(axis=0)))


def plural(n, one, many):
    return "%d %s" % (n, one if n == 1 else many)


# Where a warning quotes the engine's own check (the panel shows that on a line
# of its own and cuts the warning there).
ENGINE_WORDS = " Engine: "

# The engine's reasons for returning the input that mean there was nothing to
# do (dev_stats.unchanged_reason: native.UNCHANGED_ALREADY_DEVELOPABLE,
# _DEVELOPABLE_PIECEWISE, _ALREADY_FLAT), in the user's words: not a failure,
# so no advice.
NOTHING_TO_DO = {
    1: "it is already developable",
    2: "it is already developable piecewise: its curvature sits on the seams between flat pieces",
    3: "every vertex is already flat (curvature under 0.001 rad)",
}


def verdict(obj_name, stats, fig):
    """(report level 'INFO' or 'WARNING', verdict 'IMPROVED' / 'WORSE' /
    'UNCHANGED' / 'DEVELOPABLE', message): a warning when a figure got worse
    or nothing changed, with what to try; an info line when the input came back
    because it was developable already (NOTHING_TO_DO). stats: the engine's
    dev_stats as a dict; fig: figures() (the engine's own flat shares and
    turned faces when it has them)."""
    e0, e1 = stats["mean_defect_before"], stats["mean_defect_after"]
    engine_said = stats.get("result_message", "")
    unchanged = stats.get("result") == 1 or fig["max_move"] == 0.0
    flat = "flat %.0f %% \u2192 %.0f %%" % (100 * fig["flat_before"], 100 * fig["flat_after"])
    summary = "%s, curvature %+.1f %%, moved at most %.2g %% of its size, %s, %.0f ms" % (
        flat,
        stats["change_percent"],
        fig["move_percent"],
        plural(fig["faces_turned"], "face turned over", "faces turned over"),
        stats["time_total_ms"],
    )
    if unchanged:
        nothing_to_do = NOTHING_TO_DO.get(stats.get("unchanged_reason"))
        if nothing_to_do:
            # Nothing got worse and nothing is left to try. The engine's words
            # have their own line in the panel.
            return "INFO", "DEVELOPABLE", "%s: nothing to do, %s." % (obj_name, nothing_to_do)
        # The engine's reason after ENGINE_WORDS: the panel shows it once, on
        # its own line, and the report line keeps it.
        why = engine_said.strip() or "no better shape was found within the limits."
        return (
            "WARNING",
            "UNCHANGED",
            (
                "%s: nothing changed. Try a larger 'Shape May Move', or the job 'Whole object into "
                "pieces' for a closed object.%s%s" % (obj_name, ENGINE_WORDS, why)
            ),
        )
    worse = []
    if e1 > e0 * (1.0 + 1e-9):
        worse.append("the mean curvature grew (%+.1f %%)" % stats["change_percent"])
    if fig["flat_after"] < fig["flat_before"]:
        worse.append("fewer vertices are flat (%s)" % flat)
    m0, m1 = stats["max_defect_before"], stats["max_defect_after"]
    peaked = m1 > m0 * (1.0 + 1e-9)
    if peaked:
        worse.append("the largest curvature grew (%.3g → %.3g rad)" % (m0, m1))
    if fig["faces_turned"] > 0:
        worse.append(plural(fig["faces_turned"], "face turned over", "faces turned over"))
    if worse:
        tips = []
        if fig["faces_turned"] > 0:
            tips.append("a smaller 'Shape May Move' or Pin Boundary")
        if (e1 > e0 or peaked) and fig["flat_after"] > fig["flat_before"]:
            # A closed surface keeps its total curvature (Gauss-Bonnet): flat
            # pieces gather it on their seams, where it no longer cancels. An
            # open one's flat vertices gave theirs to fewer others.
            why = (
                "a closed surface keeps its total curvature; it gathered on the seams"
                if fig.get("closed", True)
                else "the curvature the flat vertices gave up gathered on fewer others"
            )
            tips.append("setting the key to 1 if flat pieces are what you want (%s)" % why)
        elif e1 > e0 or peaked or fig["flat_after"] < fig["flat_before"]:
            tips.append(
                "the job 'Whole object into pieces' (a closed or doubly curved object " "cannot flatten as one piece)"
            )
        engine = "%s%s" % (ENGINE_WORDS, engine_said.rstrip()) if engine_said else ""
        return (
            "WARNING",
            "WORSE",
            (
                "%s got worse: %s. The result is kept in the shape key 'Developable' at 0 (slide it "
                "to look). Try %s.%s [%s]" % (obj_name, "; ".join(worse), " or ".join(tips), engine, summary)
            ),
        )
    return "INFO", "IMPROVED", "%s: %s" % (obj_name, summary)

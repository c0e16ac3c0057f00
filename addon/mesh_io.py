# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh <-> flat numpy buffers for the engine.

Every bulk transfer uses foreach_get/foreach_set; no per-vertex Python loops.
The user's polygons are never changed: the engine gets mesh.loop_triangles,
and triangle results are mapped back to polygons with loop_triangle.polygon_index.
"""

import bpy
import numpy as np

from .core import checks


class MeshBuffers:
    """What the engine needs from one mesh, captured at one moment."""

    def __init__(self, positions, triangles, tri_polygon, n_polygons):
        self.positions = positions  # (n, 3) float64
        self.triangles = triangles  # (t, 3) int32
        self.tri_polygon = tri_polygon  # (t,) int32: polygon of each loop triangle
        self.n_polygons = n_polygons

    @property
    def n_vertices(self):
        return self.positions.shape[0]


def read_positions(mesh):
    n = len(mesh.vertices)
    co = np.empty(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(n, 3).astype(np.float64)


def read_mesh(mesh):
    """Positions (the base mesh, not any shape key mix) and loop triangles."""
    positions = read_positions(mesh)
    mesh.calc_loop_triangles()
    t = len(mesh.loop_triangles)
    tris = np.empty(t * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    tri_poly = np.empty(t, dtype=np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", tri_poly)
    return MeshBuffers(positions, tris.reshape(t, 3), tri_poly, len(mesh.polygons))


def read_selection(mesh):
    n = len(mesh.vertices)
    sel = np.zeros(n, dtype=bool)
    if n:
        mesh.vertices.foreach_get("select", sel)
    return sel


def read_vertex_group(obj, group_name, mesh=None):
    """Weights (n,) float32 of the object's vertex group `group_name` (0 where
    unassigned), of its own mesh or of `mesh` (one made from it).

    Vertex groups are not part of the Python attribute API, so a throw-away
    object with a one-node Geometry Nodes modifier copies the group into a
    generic point attribute that foreach_get can read in bulk.
    """
    mesh = mesh or obj.data
    n = len(mesh.vertices)
    if not group_name or group_name not in obj.vertex_groups or n == 0:
        return np.zeros(n, dtype=np.float32)
    attr_name = "__developable_pin_weight"
    tree = _weight_tree(group_name, attr_name)
    tmp = bpy.data.objects.new("__developable_tmp", mesh)
    for vg in obj.vertex_groups:  # names are per object in 3.x
        if vg.name not in tmp.vertex_groups:
            tmp.vertex_groups.new(name=vg.name)
    scene = bpy.context.scene
    scene.collection.objects.link(tmp)
    try:
        mod = tmp.modifiers.new("pin weights", "NODES")
        mod.node_group = tree
        depsgraph = bpy.context.evaluated_depsgraph_get()
        depsgraph.update()
        ev = tmp.evaluated_get(depsgraph)
        ev_mesh = ev.to_mesh()
        try:
            attr = ev_mesh.attributes.get(attr_name)
            weights = np.zeros(len(ev_mesh.vertices), dtype=np.float32)
            if attr is not None and len(ev_mesh.vertices) == n:
                attr.data.foreach_get("value", weights)
            else:
                weights = np.zeros(n, dtype=np.float32)
        finally:
            ev.to_mesh_clear()
    finally:
        bpy.data.objects.remove(tmp, do_unlink=True)
        bpy.data.node_groups.remove(tree)
    return weights


def _socket(sockets, name, kind):
    """The enabled socket `name` of type `kind` (3.x nodes have one per data type)."""
    for s in sockets:
        if s.name == name and s.type == kind and getattr(s, "enabled", True):
            return s
    for s in sockets:
        if s.name == name and getattr(s, "enabled", True):
            return s
    return sockets[name]


def _weight_tree(group_name, attr_name):
    tree = bpy.data.node_groups.new("__developable_pin_weight", "GeometryNodeTree")
    if hasattr(tree, "interface"):  # Blender 4.0+
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    nodes = tree.nodes
    gin = nodes.new("NodeGroupInput")
    gout = nodes.new("NodeGroupOutput")
    read = nodes.new("GeometryNodeInputNamedAttribute")
    read.data_type = "FLOAT"
    _socket(read.inputs, "Name", "STRING").default_value = group_name
    store = nodes.new("GeometryNodeStoreNamedAttribute")
    store.data_type = "FLOAT"
    store.domain = "POINT"
    _socket(store.inputs, "Name", "STRING").default_value = attr_name
    links = tree.links
    links.new(gin.outputs[0], _socket(store.inputs, "Geometry", "GEOMETRY"))
    links.new(_socket(read.outputs, "Attribute", "VALUE"), _socket(store.inputs, "Value", "VALUE"))
    links.new(_socket(store.outputs, "Geometry", "GEOMETRY"), gout.inputs[0])
    return tree


# ---------------------------------------------------------------------------
# What the user sees: the shape key mix, in world space.


class MeshInputError(Exception):
    """The mesh cannot be read as the user sees it; the message says why."""


def _key_co(kb):
    a = np.empty(len(kb.data) * 3, dtype=np.float32)
    kb.data.foreach_get("co", a)
    return a.reshape(-1, 3).astype(np.float64)


def read_visible_positions(obj, exclude=()):
    """(reference coordinates, the shape key mix shown in the viewport) in
    object space, float64 (n, 3). The keys named in `exclude` (the add-on's
    own result) are left out of the mix. Without shape keys both are the
    mesh's coordinates. Modifiers are not applied (the engine needs the mesh's
    own vertices). Raises MeshInputError for absolute (non-relative) keys."""
    mesh = obj.data
    keys = mesh.shape_keys
    base = read_positions(mesh)
    if keys is None or len(keys.key_blocks) == 0:
        return base, base
    if not keys.use_relative:
        raise MeshInputError(
            "%s uses absolute shape keys (Relative is off), whose shape depends on the "
            "frame: tick Relative in its Shape Keys panel, or apply the keys" % obj.name
        )
    blocks = keys.key_blocks
    reference = keys.reference_key
    ref_co = _key_co(reference)
    if obj.show_only_shape_key:  # the pin in the Shape Keys panel: only the active key shows
        active = obj.active_shape_key
        if active is None or active.name in exclude:
            return ref_co, ref_co
        return ref_co, _key_co(active)
    mix = ref_co.copy()
    cache = {reference.name: ref_co}
    for kb in blocks:
        if kb == reference or kb.name in exclude or kb.mute or kb.value == 0.0:
            continue
        rel = kb.relative_key
        if rel.name not in cache:
            cache[rel.name] = _key_co(rel)
        delta = _key_co(kb) - cache[rel.name]
        if kb.vertex_group:
            weights = read_vertex_group(obj, kb.vertex_group).astype(np.float64)
            delta *= weights[:, None]
        mix += kb.value * delta
    return ref_co, mix


def linear_part(obj):
    """The 3x3 linear part of the object's world matrix (no translation: the
    figures do not depend on it and far-off objects keep their precision)."""
    m = np.array(obj.matrix_world, dtype=np.float64)[:3, :3]
    return m


def read_polygons(mesh):
    """(loop_start (p,), loop_total (p,), loop vertex indices (l,)) int32."""
    p = len(mesh.polygons)
    start = np.empty(p, dtype=np.int32)
    total = np.empty(p, dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", start)
    mesh.polygons.foreach_get("loop_total", total)
    loops = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loops)
    return start, total, loops


def select_in_edit_mode(obj, vertices=(), edges=(), polygons=()):
    """Enters Edit mode on `obj` (active, in Object mode) with exactly the given
    vertices, edges (vertex pairs) and polygons selected, as the 3D-Print
    Toolbox shows what is wrong. Only the bad elements are visited (few); the
    rest is deselected in one call."""
    import bmesh

    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.faces.ensure_lookup_table()
    for v in np.asarray(vertices, dtype=np.int64).reshape(-1)[:100000]:
        bm.verts[int(v)].select = True
    for a, b in np.asarray(edges, dtype=np.int64).reshape(-1, 2)[:100000]:
        edge = bm.edges.get((bm.verts[int(a)], bm.verts[int(b)]))
        if edge is not None:
            edge.select = True
    for p in np.asarray(polygons, dtype=np.int64).reshape(-1)[:100000]:
        bm.faces[int(p)].select = True
    bmesh.update_edit_mesh(obj.data)


# ---------------------------------------------------------------------------
# Modifiers: the shape the viewport shows may not be the mesh's own.


def shown_modifiers(obj):
    """Names of the object's modifiers shown in the viewport."""
    return [m.name for m in obj.modifiers if m.show_viewport]


def mesh_as_shown(obj, name):
    """A new mesh datablock holding what the viewport shows of the object (its
    modifiers and shape keys applied, as Object > Convert > Mesh makes it),
    with the object's vertex groups and attributes kept where the modifiers
    keep them. Not linked to anything: the caller assigns or removes it."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = bpy.data.meshes.new_from_object(evaluated, preserve_all_data_layers=True, depsgraph=depsgraph)
    mesh.name = name
    return mesh


# ---------------------------------------------------------------------------
# Unwelded seams, for the panel: cached per mesh until its geometry changes.

_UNWELDED = {}  # mesh pointer -> (vertex, edge, polygon counts, unwelded vertices)


def boundary_mask(mesh):
    """Vertices on an edge that only one face uses, from Blender's own edges."""
    n = len(mesh.vertices)
    edge_index = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", edge_index)
    uses = np.bincount(edge_index, minlength=len(mesh.edges))
    ev = np.empty(len(mesh.edges) * 2, dtype=np.int32)
    mesh.edges.foreach_get("vertices", ev)
    mask = np.zeros(n, dtype=bool)
    mask[ev.reshape(-1, 2)[uses == 1].reshape(-1)] = True
    return mask


def unwelded(mesh):
    """The mesh's unwelded vertices (checks.unwelded_vertices), cached until
    its geometry changes (the depsgraph handler below forgets it then)."""
    key = mesh.as_pointer()
    counts = (len(mesh.vertices), len(mesh.edges), len(mesh.polygons))
    cached = _UNWELDED.get(key)
    if cached is not None and cached[0] == counts:
        return cached[1]
    found = checks.unwelded_vertices(read_positions(mesh), boundary_mask(mesh))
    _UNWELDED[key] = (counts, found)
    return found


@bpy.app.handlers.persistent
def _forget_changed(_scene, depsgraph):
    for update in depsgraph.updates:
        if update.is_updated_geometry and isinstance(update.id, bpy.types.Object) and update.id.type == "MESH":
            _UNWELDED.pop(update.id.original.data.as_pointer(), None)


@bpy.app.handlers.persistent
def _forget_all(*_args):
    _UNWELDED.clear()


_HANDLERS = (
    ("depsgraph_update_post", _forget_changed),
    ("load_post", _forget_all),
    ("undo_post", _forget_all),  # undo rebuilds the meshes: a pointer may then name another
    ("redo_post", _forget_all),
)


def register():
    for name, fn in _HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    for handlers, fn in ((getattr(bpy.app.handlers, name), fn) for name, fn in _HANDLERS):
        if fn in handlers:
            handlers.remove(fn)
    _UNWELDED.clear()

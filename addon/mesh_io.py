# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh <-> flat numpy buffers for the engine.

Every bulk transfer uses foreach_get/foreach_set; no per-vertex Python loops.
The user's polygons are never changed: the engine gets mesh.loop_triangles,
and triangle results are mapped back to polygons with loop_triangle.polygon_index.
"""

import numpy as np

import bpy


class MeshBuffers:
    """What the engine needs from one mesh, captured at one moment."""

    def __init__(self, positions, triangles, tri_polygon, n_polygons):
        self.positions = positions      # (n, 3) float64
        self.triangles = triangles      # (t, 3) int32
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


def read_vertex_group(obj, group_name):
    """Weights (n,) float32 of vertex group `group_name` (0 where unassigned).

    Vertex groups are not part of the Python attribute API, so a throw-away
    object with a one-node Geometry Nodes modifier copies the group into a
    generic point attribute that foreach_get can read in bulk.
    """
    mesh = obj.data
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


def face_normals(positions, triangles):
    """Unit normals (t, 3) of triangles over positions (numpy, no bpy)."""
    p = np.asarray(positions, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    if t.size == 0:
        return np.zeros((0, 3))
    n = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    length = np.linalg.norm(n, axis=1)
    length[length == 0] = 1.0
    return n / length[:, None]

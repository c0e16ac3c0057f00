# SPDX-License-Identifier: GPL-3.0-or-later
"""Generated test meshes (numpy), and a helper that turns vertex/face arrays
into a Blender mesh with foreach_set. Used by the batch script's --demo, by
run.sh and by the tests; nothing here is needed to use the add-on."""

import numpy as np


def cone_band(nu=80, nv=9, noise=0.004, bulge=0.06, seed=1):
    """A curved cone band like the paper's Fig. 3 (80 x 9 = 720 vertices), made
    non-developable by a smooth bulge plus random noise along the normals.
    Returns (vertices (nu*nv, 3) float64, quads (m, 4) int32)."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, 1.5 * np.pi, nu)            # around the axis
    v = np.linspace(0.0, 1.0, nv)                    # along the rulings
    U, V = np.meshgrid(u, v, indexing="ij")
    r = 1.0 + 0.8 * V                                # cone: radius grows along v
    x = r * np.cos(U)
    y = r * np.sin(U)
    z = 1.2 * V
    # "curved": bend the band (a developable cone stays developable only without it)
    pts = np.stack([x, y, z], axis=-1)
    radial = np.stack([np.cos(U), np.sin(U), np.zeros_like(U)], axis=-1)
    bump = bulge * np.sin(np.pi * V) * np.sin(3.0 * U) ** 2
    pts = pts + radial * bump[..., None]
    pts = pts + rng.normal(scale=noise, size=pts.shape)
    verts = pts.reshape(-1, 3)
    idx = np.arange(nu * nv).reshape(nu, nv)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    return verts, quads.astype(np.int32)


def half_cylinder(nu=40, nv=20, noise=0.01, seed=2):
    """A noisy half-cylinder sheet (grid of quads)."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, np.pi, nu)
    v = np.linspace(0.0, 2.0, nv)
    U, V = np.meshgrid(u, v, indexing="ij")
    pts = np.stack([np.cos(U), V, np.sin(U)], axis=-1)
    pts = pts + rng.normal(scale=noise, size=pts.shape)
    idx = np.arange(nu * nv).reshape(nu, nv)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    return pts.reshape(-1, 3), quads.astype(np.int32)


def mesh_from_arrays(name, verts, faces):
    """A new bpy mesh from (n,3) vertices and (m,k) faces (one polygon size)."""
    import bpy
    verts = np.asarray(verts, dtype=np.float32).reshape(-1, 3)
    faces = np.asarray(faces, dtype=np.int32)
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(verts))
    me.vertices.foreach_set("co", verts.reshape(-1))
    if faces.size:
        m, k = faces.shape
        me.loops.add(m * k)
        me.loops.foreach_set("vertex_index", faces.reshape(-1))
        me.polygons.add(m)
        me.polygons.foreach_set("loop_start", np.arange(0, m * k, k, dtype=np.int32))
        try:  # read-only (derived) since Blender 4.0
            me.polygons.foreach_set("loop_total", np.full(m, k, dtype=np.int32))
        except (AttributeError, TypeError, RuntimeError):
            pass
    me.update(calc_edges=True)
    me.validate()
    return me


def object_from_arrays(name, verts, faces, context=None):
    import bpy
    context = context or bpy.context
    me = mesh_from_arrays(name, verts, faces)
    ob = bpy.data.objects.new(name, me)
    context.scene.collection.objects.link(ob)
    context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob

"""numpy arrays -> Blender objects, for test scenarios and the batch script's
demo meshes (import only inside Blender)."""
import bpy
import numpy as np


def mesh_from_arrays(name, verts, faces):
    """A new bpy mesh from (n,3) vertices and (m,k) faces (one polygon size),
    with foreach_set."""
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
    """A new object of that mesh, linked to the scene, active and selected."""
    context = context or bpy.context
    ob = bpy.data.objects.new(name, mesh_from_arrays(name, verts, faces))
    context.scene.collection.objects.link(ob)
    context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob

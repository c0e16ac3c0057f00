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


def workbench_scene(scene, width, height, background):
    """Sets `scene` up for Workbench renders of vertex colours as they are:
    studio light, no cavity, no back-face culling, 8x anti-aliasing, the
    Standard view transform, a plain world colour, PNG (RGB) output."""
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.display.render_aa = "8"
    shading = scene.display.shading
    shading.light = "STUDIO"
    shading.color_type = "VERTEX"
    shading.show_backface_culling = False
    shading.show_cavity = False
    shading.show_specular_highlight = False
    scene.view_settings.view_transform = "Standard"
    scene.world = scene.world or bpy.data.worlds.new("World")
    scene.world.color = background

# SPDX-License-Identifier: GPL-3.0-or-later
"""The Gauss image (paper Fig. 2-3 g-i) as Blender objects, in a collection
"Gauss Image: <object>" placed beside the object:
  - a unit sphere (wire);
  - the face normals before and after as the vertices of two point-cloud
    meshes (each vertex instanced as a small dot so they show and render);
  - the ideal curves (dev_result_curve_*) as one poly curve object."""

import bmesh
import bpy
import numpy as np

from .mesh_io import face_normals

PREFIX = "Gauss Image: "
DOT_RADIUS = 0.012


def collection_name(obj):
    return PREFIX + obj.name


def _remove_collection(name):
    coll = bpy.data.collections.get(name)
    if coll is None:
        return
    for ob in list(coll.objects):
        data = ob.data
        bpy.data.objects.remove(ob, do_unlink=True)
        if data is not None and data.users == 0:
            if isinstance(data, bpy.types.Mesh):
                bpy.data.meshes.remove(data)
            elif isinstance(data, bpy.types.Curve):
                bpy.data.curves.remove(data)
    bpy.data.collections.remove(coll)


def _material(name, rgba):
    mat = bpy.data.materials.get(name)
    if mat is None:
        mat = bpy.data.materials.new(name)
    mat.diffuse_color = rgba
    return mat


def _points_mesh(name, points):
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(points))
    me.vertices.foreach_set("co", np.ascontiguousarray(points, dtype=np.float32).reshape(-1))
    me.update()
    return me


def _dot_mesh(name, rgba):
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=1, radius=DOT_RADIUS)
    bm.to_mesh(me)
    bm.free()
    me.materials.append(_material(name + " Material", rgba))
    return me


def _new_object(coll, name, data, parent=None):
    ob = bpy.data.objects.new(name, data)
    coll.objects.link(ob)
    if parent is not None:
        ob.parent = parent
    return ob


def build(obj, base_positions, deformed_positions, triangles, curves):
    """(Re)builds the Gauss image of `obj`. curves: [(points (k,3), patch, closed)]."""
    name = collection_name(obj)
    _remove_collection(name)
    coll = bpy.data.collections.new(name)
    bpy.context.scene.collection.children.link(coll)

    # Beside the object, to the +x side of its bounding box.
    corners = np.array([obj.matrix_world @ _vec(c) for c in obj.bound_box])
    size = max(float(np.ptp(corners, axis=0).max()), 1e-6)
    centre = corners.mean(axis=0)
    root = _new_object(coll, obj.name + " Gauss Image", None)
    root.empty_display_type = 'SPHERE'
    root.empty_display_size = 1.0
    root.scale = (0.35 * size,) * 3
    root.location = (corners[:, 0].max() + 0.5 * size, centre[1], centre[2])

    sphere_me = bpy.data.meshes.new(obj.name + " Gauss Sphere")
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=1.0)
    bm.to_mesh(sphere_me)
    bm.free()
    sphere = _new_object(coll, obj.name + " Gauss Sphere", sphere_me, root)
    sphere.display_type = 'WIRE'
    sphere.hide_render = True

    for label, positions, rgba in (("Before", base_positions, (0.6, 0.6, 0.6, 1.0)),
                                   ("After", deformed_positions, (0.1, 0.35, 1.0, 1.0))):
        normals = face_normals(positions, triangles)
        cloud = _new_object(coll, "%s Normals %s" % (obj.name, label),
                            _points_mesh("%s Normals %s" % (obj.name, label), normals), root)
        cloud.instance_type = 'VERTS'
        cloud.show_instancer_for_viewport = True
        cloud.show_instancer_for_render = False
        _new_object(coll, "%s Normal Dot %s" % (obj.name, label),
                    _dot_mesh("%s Normal Dot %s" % (obj.name, label), rgba), cloud)

    cu = bpy.data.curves.new(obj.name + " Ideal Curves", 'CURVE')
    cu.dimensions = '3D'
    cu.bevel_depth = DOT_RADIUS * 0.6
    for points, _patch, closed in curves:
        if len(points) < 2:
            continue
        spline = cu.splines.new('POLY')
        spline.points.add(len(points) - 1)
        co = np.ones((len(points), 4), dtype=np.float32)
        co[:, :3] = points
        spline.points.foreach_set("co", co.reshape(-1))
        spline.use_cyclic_u = bool(closed)
    cu.materials.append(_material("Gauss Ideal Curve", (0.05, 0.8, 0.1, 1.0)))
    _new_object(coll, obj.name + " Ideal Curves", cu, root)
    obj.developable.show_gauss_image = True
    return coll


def _vec(c):
    from mathutils import Vector
    return Vector(c)


def set_visible(obj, visible):
    coll = bpy.data.collections.get(collection_name(obj))
    if coll is None:
        return False
    coll.hide_viewport = not visible
    coll.hide_render = not visible
    return True


def exists(obj):
    return bpy.data.collections.get(collection_name(obj)) is not None

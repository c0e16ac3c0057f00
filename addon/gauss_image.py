# SPDX-License-Identifier: GPL-3.0-or-later
"""The Gauss image (paper Fig. 2-3 g-i) as Blender objects, in one collection
per object placed beside it (the object keeps a pointer to it, so a rename
does not orphan it and a re-run replaces it):
  - a unit sphere (wire);
  - the face normals before and after as dots (vertex instancing), at most
    MAX_DOTS of each, picked evenly so the picture stays legible;
  - the ideal curves as chains of smaller dots;
  - a legend (text objects) naming the three colours.
Every dot mesh carries its colour three ways: a colour attribute (the
add-on's Attribute shading), its material (Material shading and renders) and
the object colour (Object shading)."""

import bmesh
import bpy
import numpy as np

from .core.checks import face_normals

PREFIX = "Gauss Image: "
DOT_RADIUS = 0.02
CURVE_DOT_RADIUS = 0.012
MAX_DOTS = 2000
MAX_CURVE_DOTS = 1500

BEFORE = (0.45, 0.45, 0.45, 1.0)
AFTER = (0.05, 0.3, 1.0, 1.0)
CURVE = (0.05, 0.75, 0.1, 1.0)
LEGEND = (("Before: grey dots (face normals)", BEFORE), ("After: blue dots", AFTER), ("Ideal curves: green", CURVE))


def collection_name(obj):
    return PREFIX + obj.name


def collection_of(obj):
    """The object's Gauss image collection, if any (followed through renames)."""
    coll = obj.developable.gauss_collection
    if coll is not None and coll.name in bpy.data.collections:
        return coll
    return bpy.data.collections.get(collection_name(obj))


def _remove(coll):
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


def evenly(points, limit):
    """At most `limit` of the points, spread evenly over the list (deterministic)."""
    points = np.asarray(points)
    if len(points) <= limit:
        return points
    return points[np.linspace(0, len(points) - 1, limit).round().astype(np.int64)]


def _points_mesh(name, points):
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(points))
    me.vertices.foreach_set("co", np.ascontiguousarray(points, dtype=np.float32).reshape(-1))
    me.update()
    return me


def _dot_mesh(name, rgba, radius):
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=1, radius=radius)
    bm.to_mesh(me)
    bm.free()
    me.materials.append(_material(name + " Material", rgba))
    colour = me.color_attributes.new("Colour", "FLOAT_COLOR", "POINT")
    colour.data.foreach_set("color", np.tile(np.asarray(rgba, dtype=np.float32), len(me.vertices)))
    me.color_attributes.active_color = colour
    return me


def _new_object(coll, name, data, parent=None, rgba=None):
    ob = bpy.data.objects.new(name, data)
    coll.objects.link(ob)
    if parent is not None:
        ob.parent = parent
    if rgba is not None:
        ob.color = rgba
    return ob


def _dots(coll, root, name, points, rgba, radius):
    cloud = _new_object(coll, name, _points_mesh(name, points), root)
    cloud.instance_type = "VERTS"
    cloud.show_instancer_for_viewport = False
    cloud.show_instancer_for_render = False
    _new_object(coll, name + " Dot", _dot_mesh(name + " Dot", rgba, radius), cloud, rgba)
    return cloud


def _curve_points(curves, spacing):
    """The ideal curves resampled every `spacing` (unit sphere lengths)."""
    out = []
    for points, _patch, closed in curves:
        p = np.asarray(points, dtype=np.float64)
        if len(p) < 2:
            continue
        if closed:
            p = np.vstack([p, p[:1]])
        seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
        length = np.concatenate([[0.0], np.cumsum(seg)])
        if length[-1] <= 0:
            continue
        s = np.linspace(0.0, length[-1], max(2, int(length[-1] / spacing) + 1))
        out.append(np.stack([np.interp(s, length, p[:, k]) for k in range(3)], axis=1))
    return np.vstack(out) if out else np.zeros((0, 3))


def build(obj, base_positions, deformed_positions, triangles, curves):
    """(Re)builds the Gauss image of `obj`. curves: [(points (k,3), patch, closed)]."""
    old = collection_of(obj)
    if old is not None:
        _remove(old)
    stale = bpy.data.collections.get(collection_name(obj))  # e.g. from an older add-on
    if stale is not None:
        _remove(stale)
    name = collection_name(obj)
    coll = bpy.data.collections.new(name)
    bpy.context.scene.collection.children.link(coll)
    obj.developable.gauss_collection = coll

    # Beside the object, to the +x side of its bounding box.
    corners = np.array([obj.matrix_world @ _vec(c) for c in obj.bound_box])
    size = max(float(np.ptp(corners, axis=0).max()), 1e-6)
    centre = corners.mean(axis=0)
    root = _new_object(coll, obj.name + " Gauss Image", None)
    root.empty_display_type = "SPHERE"
    root.empty_display_size = 1.0
    root.scale = (0.35 * size,) * 3
    root.location = (corners[:, 0].max() + 0.5 * size, centre[1], centre[2])

    sphere_me = bpy.data.meshes.new(obj.name + " Gauss Sphere")
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=1.0)
    bm.to_mesh(sphere_me)
    bm.free()
    sphere = _new_object(coll, obj.name + " Gauss Sphere", sphere_me, root)
    sphere.display_type = "WIRE"
    sphere.hide_render = True

    for label, positions, rgba in (("Before", base_positions, BEFORE), ("After", deformed_positions, AFTER)):
        normals = evenly(face_normals(positions, triangles), MAX_DOTS)
        _dots(coll, root, "%s Normals %s" % (obj.name, label), normals, rgba, DOT_RADIUS)
    points = evenly(_curve_points(curves, 1.5 * CURVE_DOT_RADIUS), MAX_CURVE_DOTS)
    if len(points):
        _dots(coll, root, obj.name + " Ideal Curves", points, CURVE, CURVE_DOT_RADIUS)

    for i, (text, rgba) in enumerate(LEGEND):
        font = bpy.data.curves.new("%s Gauss Legend %d" % (obj.name, i), "FONT")
        font.body = text
        font.size = 0.16
        font.materials.append(_material("Gauss Legend %d" % i, rgba))
        label = _new_object(coll, "%s Gauss Legend %d" % (obj.name, i), font, root, rgba)
        label.location = (-1.0, 0.0, -1.3 - 0.22 * i)
        label.rotation_euler = (np.pi / 2, 0.0, 0.0)  # faces the default front view (-y)
    obj.developable.show_gauss_image = True
    return coll


def _vec(c):
    from mathutils import Vector

    return Vector(c)


def set_visible(obj, visible):
    coll = collection_of(obj)
    if coll is None:
        return False
    coll.hide_viewport = not visible
    coll.hide_render = not visible
    return True


def exists(obj):
    return collection_of(obj) is not None


def follow_renames():
    """Names every Gauss image collection after its object again."""
    for ob in bpy.data.objects:
        rec = getattr(ob, "developable", None)
        coll = rec.gauss_collection if rec is not None else None
        if coll is not None and coll.name != collection_name(ob):
            coll.name = collection_name(ob)


# A rename in the UI notifies the message bus; the subscription is lost when a
# file is loaded, so it is made again then.
_OWNER = object()


def _subscribe():
    bpy.msgbus.clear_by_owner(_OWNER)
    bpy.msgbus.subscribe_rna(key=(bpy.types.Object, "name"), owner=_OWNER, args=(), notify=follow_renames)


@bpy.app.handlers.persistent
def _load_post(*_args):
    _subscribe()


def register():
    _subscribe()
    bpy.app.handlers.load_post.append(_load_post)


def unregister():
    if _load_post in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(_load_post)
    bpy.msgbus.clear_by_owner(_OWNER)

# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes one engine result into the object: the "Developable" shape key, the
defect attributes and colours, the patch ids and the run's figures.

Called only after the engine returned OK, with the object in Object mode.
The base mesh (mesh.vertices co and the polygons) is never changed."""

import numpy as np

from . import native

SHAPE_KEY = "Developable"
BASIS = "Basis"
COLOUR_BEFORE = "Defect Before"
COLOUR_AFTER = "Defect After"
DEFECT_BEFORE = "defect_before"
DEFECT_AFTER = "defect_after"
PATCH_ID = "patch_id"

# Colour of vertices where the angle defect is not defined (boundary).
BOUNDARY_COLOUR = (0.55, 0.55, 0.55, 1.0)


def colour_scale(defect_before, defect_after, interior):
    """One scale for both colour maps: the 95th percentile of |defect| over the
    interior vertices of both states, so the maps compare directly."""
    d = np.concatenate([np.abs(defect_before[interior]), np.abs(defect_after[interior])])
    d = d[np.isfinite(d)]
    if d.size == 0:
        return 1e-6
    scale = float(np.percentile(d, 95.0))
    if not scale > 0.0:
        scale = float(d.max()) if d.max() > 0 else 1e-6
    return scale


def defect_colours(defect, interior, scale):
    """(n, 4) float32 linear RGBA: blue (-scale) .. white (0) .. red (+scale),
    grey where the defect is undefined."""
    t = np.clip(np.nan_to_num(defect / scale), -1.0, 1.0)
    n = defect.shape[0]
    rgba = np.ones((n, 4), dtype=np.float32)
    pos = t > 0
    neg = ~pos
    # positive: white -> red; negative: white -> blue
    rgba[pos, 1] = 1.0 - t[pos]
    rgba[pos, 2] = 1.0 - t[pos]
    rgba[neg, 0] = 1.0 + t[neg]
    rgba[neg, 1] = 1.0 + t[neg]
    rgba[~interior] = BOUNDARY_COLOUR
    return rgba


def write_shape_key(obj, positions, value=1.0):
    """Sets the coordinates of the "Developable" key (Basis added when the mesh has
    no keys), relative to the reference key. `positions` are the key's own
    coordinates (operators.py makes them so that the shown mix at value 1 is
    the result). A re-run overwrites the same key."""
    mesh = obj.data
    if mesh.shape_keys is None or len(mesh.shape_keys.key_blocks) == 0:
        obj.shape_key_add(name=BASIS, from_mix=False)
    key = mesh.shape_keys.key_blocks.get(SHAPE_KEY)
    if key is None:
        key = obj.shape_key_add(name=SHAPE_KEY, from_mix=False)
    key.relative_key = mesh.shape_keys.reference_key
    key.data.foreach_set("co", np.ascontiguousarray(positions, dtype=np.float32).reshape(-1))
    key.slider_min = min(key.slider_min, 0.0)
    key.mute = False
    key.value = value
    mesh.update()
    return key


def _attribute(mesh, name, data_type, domain):
    attr = mesh.attributes.get(name)
    if attr is not None and (attr.data_type != data_type or attr.domain != domain):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(name=name, type=data_type, domain=domain)
    return attr


def write_attributes(mesh, result, tri_polygon, n_polygons):
    """Raw defects, colours (one scale) and face patch ids. Returns the scale."""
    interior = result.interior
    scale = colour_scale(result.defect_before, result.defect_after, interior)
    for name, values in ((DEFECT_BEFORE, result.defect_before), (DEFECT_AFTER, result.defect_after)):
        _attribute(mesh, name, "FLOAT", "POINT").data.foreach_set(
            "value", np.ascontiguousarray(values, dtype=np.float32)
        )
    for name, values in ((COLOUR_BEFORE, result.defect_before), (COLOUR_AFTER, result.defect_after)):
        colours = defect_colours(values, interior, scale)
        attr = _attribute(mesh, name, "FLOAT_COLOR", "POINT")
        attr.data.foreach_set("color", colours.reshape(-1))
    patch = np.zeros(n_polygons, dtype=np.int32)
    if len(tri_polygon):
        patch[tri_polygon] = result.patch_ids
    _attribute(mesh, PATCH_ID, "INT", "FACE").data.foreach_set("value", patch)
    mesh.update()
    return scale


def show_colours(obj, after=True):
    """Makes "Defect After" (or "Before") the active and render colour attribute
    and, where there is a 3D view, switches its solid shading to attribute colours."""
    mesh = obj.data
    name = COLOUR_AFTER if after else COLOUR_BEFORE
    colours = mesh.color_attributes
    attr = colours.get(name)
    if attr is None:
        return False
    index = list(colours).index(attr) if hasattr(colours, "__iter__") else None
    colours.active_color = attr
    if index is not None and hasattr(colours, "render_color_index"):
        colours.render_color_index = index
    if hasattr(colours, "active_color_name"):
        colours.active_color_name = name
    if hasattr(colours, "default_color_name"):
        colours.default_color_name = name
    mesh.update()
    return True


def use_attribute_shading(context):
    """Solid shading by colour attribute in every 3D viewport of the screen."""
    screen = getattr(context, "screen", None)
    if screen is None:
        return
    for area in screen.areas:
        if area.type == "VIEW_3D":
            for space in area.spaces:
                if space.type == "VIEW_3D" and space.shading.type == "SOLID":
                    space.shading.color_type = "VERTEX"


def store_stats(obj, result, scale, pinned_count, figures, verdict, message, engine_result, world_space):
    s = result.stats
    rec = obj.developable
    rec.has_result = True
    rec.e_before = s["mean_defect_before"]
    rec.e_after = s["mean_defect_after"]
    rec.max_before = s["max_defect_before"]
    rec.max_after = s["max_defect_after"]
    rec.change_percent = s["change_percent"]
    rec.time_ms = s["time_total_ms"]
    rec.time_decompose_ms = s["time_decompose_ms"]
    rec.time_iterate_ms = s["time_iterate_ms"]
    rec.iterations = s["iterations"]
    rec.polish_iterations = s.get("polish_iterations", 0)
    rec.result_origin = native.ORIGIN_NAMES.get(s.get("result_origin", 0), "input")
    rec.ruled_before = s["ruled_share_before"]
    rec.ruled_after = s["ruled_share_after"]
    rec.stop_reason = native.STOP_REASONS.get(s["stop_reason"], str(s["stop_reason"]))
    rec.max_move = s["max_vertex_move"]
    rec.average_edge = s["average_edge_length"]
    ae = s["average_edge_length"]
    rec.max_move_ae = s["max_vertex_move"] / ae if ae > 0 else 0.0
    rec.patches = int(s["patches"])
    rec.curves = int(s["curves"])
    rec.pinned = int(pinned_count)
    rec.colour_scale = scale
    rec.flat_before = figures["flat_before"]
    rec.flat_after = figures["flat_after"]
    rec.faces_turned = figures["faces_turned"]
    rec.move_percent = figures["move_percent"]
    rec.size = figures["size"]
    rec.verdict = verdict
    rec.message = message[:1000]
    rec.engine_result = engine_result
    rec.world_space = world_space


def write_result(obj, key_positions, tri_polygon, n_polygons, result, key_value):
    """The key, the attributes and the colours (the object must be in Object
    mode). Returns the colour scale; the figures are stored by store_stats."""
    mesh = obj.data
    write_shape_key(obj, key_positions, key_value)
    scale = write_attributes(mesh, result, tri_polygon, n_polygons)
    rec = obj.developable
    if not rec.show_after:
        rec.show_after = True  # the update callback shows "after"
    else:
        show_colours(obj, after=True)
    return scale

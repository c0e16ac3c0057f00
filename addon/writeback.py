# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes one engine result into the object: the "Developable" shape key, the
defect attributes and colours, the patch ids and the run's record.

Called only after the engine returned OK, with the object in Object mode.
The base mesh (mesh.vertices co and the polygons) is never changed."""

import numpy as np

from .core import native
from .core.colours import colour_scale, defect_colours

SHAPE_KEY = "Developable"
BASIS = "Basis"
COLOUR_BEFORE = "Defect Before"
COLOUR_AFTER = "Defect After"
DEFECT_BEFORE = "defect_before"
DEFECT_AFTER = "defect_after"
PATCH_ID = "patch_id"


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
    scale = colour_scale(result.defect_before, result.defect_after, interior, result.stats["flat_threshold"])
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


def store_record(obj, result, figures, verdict, scale):
    """The record of a run (object.developable) from the engine's stats,
    the add-on's figures (a dict: size, move_percent, pinned, unwelded,
    world_space, job, shape_source) and the Verdict (core/verdict.py)."""
    s = result.stats
    rec = obj.developable
    rec.has_result = True
    rec.error = ""
    rec.verdict = verdict.kind
    rec.message = verdict.text[:1000]
    rec.engine_result = verdict.engine[:1000]
    rec.interior_vertices = int(s["interior_vertices"])
    rec.e_before = s["mean_defect_before"]
    rec.e_after = s["mean_defect_after"]
    rec.max_before = s["max_defect_before"]
    rec.max_after = s["max_defect_after"]
    rec.change_percent = s["change_percent"]
    rec.flat_threshold = s["flat_threshold"]
    rec.flat_before = s["flat_share_before"]
    rec.flat_after = s["flat_share_after"]
    rec.ruled_before = s["ruled_share_before"]
    rec.ruled_after = s["ruled_share_after"]
    rec.crumpled_before = s["crumpled_share_before"]
    rec.crumpled_after = s["crumpled_share_after"]
    rec.faces_turned = int(s["faces_turned_over"])
    rec.largest_move = s["max_vertex_move"]
    rec.move_limit = s["move_limit"]
    rec.time_ms = s["time_total_ms"]
    rec.time_decompose_ms = s["time_decompose_ms"]
    rec.time_iterate_ms = s["time_iterate_ms"]
    rec.iterations = s["iterations"]
    rec.polish_iterations = s["polish_iterations"]
    rec.result_origin = native.ORIGIN_NAMES.get(s["result_origin"], "input")
    rec.stop_reason = native.STOP_REASONS.get(s["stop_reason"], str(s["stop_reason"]))
    rec.average_edge = s["average_edge_length"]
    rec.patches = int(s["patches"])
    rec.curves = int(s["curves"])
    rec.colour_scale = scale
    for name in ("size", "move_percent", "pinned", "unwelded", "world_space", "job", "shape_source"):
        setattr(rec, name, figures[name])


def store_nothing_to_do(obj, text, figures):
    """The record of a mesh with nothing for the engine to do (no interior
    vertex: every vertex on the boundary): no key, no colours."""
    rec = obj.developable
    rec.has_result = True
    rec.error = ""
    rec.verdict = "DEVELOPABLE"
    rec.message = text[:1000]
    rec.engine_result = ""
    rec.interior_vertices = 0
    for name in ("flat_before", "flat_after", "ruled_before", "ruled_after", "crumpled_before", "crumpled_after"):
        setattr(rec, name, 0.0)
    for name in ("e_before", "e_after", "max_before", "max_after", "change_percent", "largest_move", "move_limit"):
        setattr(rec, name, 0.0)
    rec.faces_turned = rec.iterations = rec.polish_iterations = rec.patches = rec.curves = 0
    rec.time_ms = 0.0
    rec.result_origin, rec.stop_reason = "input", ""
    for name in ("size", "move_percent", "pinned", "unwelded", "world_space", "job", "shape_source"):
        setattr(rec, name, figures[name])


def write_result(obj, key_positions, tri_polygon, n_polygons, result, key_value):
    """The key, the attributes and the colours (the object must be in Object
    mode). The colours shown match the key: After at 1, Before when the key
    is left at 0 (the shape on screen is then the input). Returns the colour
    scale; the record is written by store_record."""
    mesh = obj.data
    write_shape_key(obj, key_positions, key_value)
    scale = write_attributes(mesh, result, tri_polygon, n_polygons)
    after = key_value > 0.0
    rec = obj.developable
    if rec.show_after != after:
        rec.show_after = after  # the update callback shows them
    else:
        show_colours(obj, after=after)
    return scale

# SPDX-License-Identifier: GPL-3.0-or-later
"""The sidebar panel (3D viewport, N panel, tab "Developable"): the job, how
far the shape may move, Run, the last run's figures; pins and the expert
settings in collapsed sub-panels. The redo panel draws the same settings.

Every text is laid out so that nothing is cut at the default sidebar width:
a long label goes on its own line above its field."""

import bpy
from bpy.types import Panel

from . import checks, gauss_image, native, writeback
from .operators import MESH_OT_make_developable, library_message

CATEGORY = "Developable"

# Expected run time on 2 cores, fitted to docs/benchmarks.md (10k-1M faces):
#   decoupled factorisation   faces * 3 us * (faces / 1e5)^0.35, once
#   one iteration             faces * 0.33 us on one patch, ~0.6 us segmented
#   iterations                ~25 on one patch (the engine's Anderson
#                             acceleration, above 25000 inner vertices),
#                             ~300 segmented
#   coupled factorisation     faces * 30 us * (faces / 1e4)^0.4: once in paper
#                             mode, every iteration with the coupled solver
#   angle polish              faces * 6 us (1M faces: 5.6 s), when it runs
# max_iterations caps the iterations. Automatic segmentation is decided by the
# engine, so the panel gives the range between the one-patch and the
# segmented run; an open mesh it splits, up to 10000 interior vertices
# (about SECOND_OPINION_FACES), is also run as one patch (docs/segmentation.md).
LARGE_MESH_FACES = 100_000
SECOND_OPINION_FACES = 20_000


def expected_seconds(faces, settings):
    """(shortest, longest) expected run time in seconds."""
    cap = int(settings.max_iterations)
    coupled = faces * 30e-6 * (faces / 1e4) ** 0.4
    if settings.mode == "PAPER":
        return (coupled,) * 2
    decoupled = faces * 3e-6 * (faces / 1e5) ** 0.35

    def run(iterations, per_face):
        iterations = min(cap, iterations)
        if settings.solver == "COUPLED":
            return iterations * (coupled + faces * per_face)
        return decoupled + iterations * faces * per_face

    one_patch, segmented = run(25, 0.33e-6), run(300, 0.6e-6)
    if settings.polish != "OFF":
        one_patch, segmented = one_patch + faces * 6e-6, segmented + faces * 6e-6
    if settings.segmentation == "OFF":
        return one_patch, one_patch
    if settings.segmentation == "ON" or (not settings.auto_target_patches and settings.target_patches > 1):
        return segmented, segmented
    return one_patch, segmented + (one_patch if faces <= SECOND_OPINION_FACES else 0.0)


def _duration_text(seconds):
    if seconds < 90:
        return "%.0f s" % max(seconds, 1)
    if seconds < 5400:
        return "%.0f min" % (seconds / 60)
    return "%.1f h" % (seconds / 3600)


def object_size(obj):
    """Bounding-box diagonal in world space (from the 8 corners: cheap to draw)."""
    from mathutils import Vector

    corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    lo = Vector(tuple(min(c[i] for c in corners) for i in range(3)))
    hi = Vector(tuple(max(c[i] for c in corners) for i in range(3)))
    return (hi - lo).length


def length_text(context, value):
    """A length in the scene's units (e.g. '1.2 cm'), as Blender writes them."""
    unit = context.scene.unit_settings
    try:
        return bpy.utils.units.to_string(
            unit.system, "LENGTH", value * unit.scale_length, precision=3, split_unit=False, compatible_unit=False
        )
    except Exception:  # an unknown unit system: plain number
        return "%.3g" % value


def line_chars(context, margin=40):
    """How many characters of the UI font fit on a line of the sidebar as it
    is now (about 6.8 pixels each at UI scale 1; `margin` pixels for the
    panel's and a box's borders): the lines are wrapped to it, never cut
    with an ellipsis."""
    scale = context.preferences.system.ui_scale
    return max(16, int((context.region.width - margin * scale) / (6.8 * scale)))


def wrap(text, width=34):
    words, line, lines = text.split(), "", []
    for w in words:
        if len(line) + len(w) + 1 > width and line:
            lines.append(line)
            line = w
        else:
            line = (line + " " + w).strip()
    if line:
        lines.append(line)
    return lines


def _labelled(col, owner, name, text):
    """A label line, then the field without a label: never cut."""
    col.label(text=text)
    col.prop(owner, name, text="")


def _automatic(col, owner, name, text):
    """A parameter with an 'Automatic' switch: the word when on, the value when off."""
    auto = getattr(owner, "auto_" + name)
    col.label(text=text)
    row = col.row(align=True)
    if auto:
        row.prop(owner, "auto_" + name, text="Automatic", toggle=True)
    else:
        row.prop(owner, name, text="")
        row.prop(owner, "auto_" + name, text="Auto", toggle=True)


def draw_main(layout, owner, context):
    """The job and how far the shape may move."""
    obj = context.active_object
    col = layout.column(align=True)
    col.label(text="Job")
    col.prop(owner, "preset", text="")
    col = layout.column(align=True)
    if owner.limit_in_edges:
        col.label(text="Shape may move (in edges)")
        col.prop(owner, "tolerance", text="")
        col.label(text="set in Advanced", icon="INFO")
    else:
        col.label(text="Shape may move")
        col.prop(owner, "move_limit", text="", slider=True)
        if obj is not None and obj.type == "MESH":
            size = object_size(obj)
            if owner.move_limit > 0:
                col.label(
                    text="up to %s (%g %% of %s)"
                    % (
                        length_text(context, owner.move_limit / 100.0 * size),
                        owner.move_limit,
                        length_text(context, size),
                    )
                )
            else:
                col.label(text="no limit")


def draw_pins(layout, owner, obj):
    col = layout.column(align=True)
    col.prop(owner, "pin_boundary")
    col.label(text="Pin vertex group")
    if obj is not None and obj.type == "MESH":
        col.prop_search(owner, "pin_group", obj, "vertex_groups", text="")
    else:
        col.prop(owner, "pin_group", text="")
    col.prop(owner, "pin_selection", text="Pin selection (Edit mode)")
    col.prop(owner, "use_mls_weights")


def draw_advanced(layout, owner):
    """Every engine parameter, in words (the paper's symbols in the tooltips)."""
    col = layout.column(align=True)
    _labelled(col, owner, "omega", "Flattening strength")
    col.prop(owner, "limit_in_edges")
    sub = col.column(align=True)
    sub.active = owner.limit_in_edges
    sub.prop(owner, "tolerance", text="Edge lengths")
    col = layout.column(align=True)
    _labelled(col, owner, "mode", "Targets")
    sub = col.column(align=True)
    sub.active = owner.mode != "PAPER"
    _labelled(sub, owner, "solver", "Solver")
    col = layout.column(align=True)
    _labelled(col, owner, "segmentation", "Pieces")
    sub = col.column(align=True)
    sub.active = owner.segmentation != "OFF"
    _automatic(sub, owner, "target_patches", "Number of pieces")
    _automatic(sub, owner, "segment_max_error", "Piece fit error")
    _labelled(sub, owner, "seams", "Seams")
    col = layout.column(align=True)
    _automatic(col, owner, "target_smoothing", "Target smoothing")
    _automatic(col, owner, "grid_resolution", "Curve search grid")
    _labelled(col, owner, "polish", "Angle polish")
    row = col.row()
    row.active = owner.polish != "OFF"  # its candidates are polishes
    row.prop(owner, "polish_smoothed_input")
    col = layout.column(align=True)
    _labelled(col, owner, "max_iterations", "Max iterations")
    _labelled(col, owner, "stop_relative_change", "Stop below change")
    _labelled(col, owner, "developable_threshold", "Flat enough below 10^ rad")
    layout.prop(owner, "gauss_image", text="Build the Gauss image")


def draw_settings(layout, owner, context, in_redo=False):
    """All settings of `owner` (scene settings or the operator in the redo panel)."""
    layout.use_property_split = False
    layout.use_property_decorate = False
    draw_main(layout, owner, context)
    if in_redo:
        wm = context.window_manager
        box = layout.box()
        box.prop(
            wm,
            "developable_show_pins",
            text="Pins",
            emboss=False,
            icon="TRIA_DOWN" if wm.developable_show_pins else "TRIA_RIGHT",
        )
        if wm.developable_show_pins:
            draw_pins(box, owner, context.active_object)
        box = layout.box()
        box.prop(
            wm,
            "developable_show_advanced",
            text="Advanced",
            emboss=False,
            icon="TRIA_DOWN" if wm.developable_show_advanced else "TRIA_RIGHT",
        )
        if wm.developable_show_advanced:
            draw_advanced(box, owner)


class VIEW3D_PT_developable(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_label = "Make Developable"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = False
        layout.use_property_decorate = False
        obj = context.active_object
        lib, err = native.try_load()
        if lib is None:
            col = layout.column(align=True)
            col.alert = True
            for i, line in enumerate(wrap(library_message(err), line_chars(context, 60))):
                col.label(text=line, icon="ERROR" if i == 0 else "BLANK1")
        settings = context.scene.developable
        draw_main(layout, settings, context)
        row = layout.row()
        row.scale_y = 1.5
        row.enabled = lib is not None
        meshes = [o for o in context.selected_objects if o.type == "MESH"]
        if obj is not None and obj.type == "MESH" and obj not in meshes:
            meshes.append(obj)
        row.operator(
            MESH_OT_make_developable.bl_idname,
            text="Run on %d meshes" % len(meshes) if len(meshes) > 1 else "Run",
            icon="PLAY",
        )
        if obj is None or obj.type != "MESH":
            layout.label(text="Select a mesh object", icon="INFO")
        elif context.mode not in {"OBJECT", "EDIT_MESH"}:
            for i, line in enumerate(
                wrap(
                    "Works in Object or Edit mode: leave %s mode first" % context.mode.replace("_", " ").title(),
                    line_chars(context, 60),
                )
            ):
                layout.label(text=line, icon="INFO" if i == 0 else "BLANK1")
        if context.mode == "EDIT_MESH" and settings.pin_selection:
            layout.label(text="Selected vertices stay put", icon="PINNED")
        if obj is not None and obj.type == "MESH":
            if obj.data.users > 1:
                layout.label(text="Mesh shared by %d objects" % obj.data.users, icon="LINKED")
            # triangles the engine will see: loop triangles when Blender has them,
            # else 2 per polygon (quads); never computed here, drawing must be cheap
            faces = len(obj.data.loop_triangles) or 2 * len(obj.data.polygons)
            if faces >= LARGE_MESH_FACES:
                shortest, longest = (_duration_text(t) for t in expected_seconds(faces, settings))
                expected = shortest if shortest == longest else "%s to %s" % (shortest, longest)
                layout.label(text="Large mesh: about %s" % expected, icon="TIME")


class VIEW3D_PT_developable_pins(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Pins"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        self.layout.use_property_split = False
        draw_pins(self.layout, context.scene.developable, context.active_object)


class VIEW3D_PT_developable_parameters(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Advanced"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        self.layout.use_property_split = False
        self.layout.use_property_decorate = False
        draw_advanced(self.layout, context.scene.developable)


# The engine's generators (native.ORIGIN_NAMES) in a designer's words, short enough for the
# default sidebar width.
ORIGIN_WORDS = {
    "deformation": "the deformation",
    "deformation_polish": "deformation + polish",
    "near_flat_polish": "deformation + polish",
    "input_polish": "polishing the input",
    "smoothed_input_polish": "smoothing + polish",
    "smoothed_step_polish": "smoothing + polish",
    "projected_input": "smoothing + projection",
}


def _pct(x):
    return "%.0f %%" % (100 * x) if x >= 0.01 or x == 0 else "%.1f %%" % (100 * x)


def draw_result(layout, context, obj):
    rec = obj.developable
    col = layout.column(align=True)
    title, icon = {
        "IMPROVED": ("Improved", "CHECKMARK"),
        "WORSE": ("A figure got worse", "ERROR"),
        "UNCHANGED": ("Nothing changed", "INFO"),
        "DEVELOPABLE": ("Already developable", "CHECKMARK"),
    }[rec.verdict]
    col.label(text=title, icon=icon)
    if rec.verdict != "IMPROVED":
        box = layout.box().column(align=True)
        # The figures in brackets and the engine's words have lines of their own below.
        for line in wrap(rec.message.split(" [")[0].split(checks.ENGINE_WORDS)[0], line_chars(context, 50)):
            box.label(text=line)
    col = layout.column(align=True)
    col.label(text="Flat vertices: %s \u2192 %s" % (_pct(rec.flat_before), _pct(rec.flat_after)))
    col.label(text="Flat, not crumpled: %s \u2192 %s" % (_pct(rec.ruled_before), _pct(rec.ruled_after)))
    col.label(text="Curvature: %+.1f %%" % rec.change_percent)
    col.label(text="Moved at most %.2g %% of size" % rec.move_percent)
    col.label(text="  (%s)" % length_text(context, rec.max_move))
    col.label(text="Faces turned over: %d" % rec.faces_turned, icon="ERROR" if rec.faces_turned else "NONE")
    col.label(
        text="Time: %s, %d iterations"
        % ("%.0f ms" % rec.time_ms if rec.time_ms < 10000 else "%.1f s" % (rec.time_ms / 1000), rec.iterations)
    )
    if rec.result_origin in ORIGIN_WORDS:
        col.label(text="Made by: %s" % ORIGIN_WORDS[rec.result_origin])
    col.label(text="Stopped: %s" % rec.stop_reason)
    col.label(text="Pieces: %d; pinned: %d" % (rec.patches, rec.pinned))
    if rec.engine_result:
        for i, line in enumerate(wrap("Engine check: " + rec.engine_result, line_chars(context))):
            col.label(text=line)
    if rec.world_space:
        col.label(text="In world space (object scale)", icon="OBJECT_ORIGIN")
    if obj.data.users > 1:
        col.label(text="Mesh shared with other objects", icon="LINKED")

    keys = obj.data.shape_keys
    kb = keys.key_blocks.get(writeback.SHAPE_KEY) if keys else None
    if kb is not None:
        layout.prop(kb, "value", text="Developable", slider=True)

    col = layout.column(align=True)
    col.label(text="Curvature colours")
    col.prop(rec, "show_after", text="After" if rec.show_after else "Before", toggle=True, icon="HIDE_OFF")
    col.label(text="blue \u2212 / white 0 / red +")
    col.label(text="full colour at \u00b1%.3g rad" % rec.colour_scale)
    space = context.space_data
    shading = getattr(space, "shading", None) if space else None
    if shading is not None:
        if shading.type == "SOLID":
            col.prop(shading, "color_type", text="")
            if shading.color_type != "VERTEX":
                col.label(text="Pick Attribute to see them", icon="INFO")
        else:
            col.label(text="Colours show in Solid view", icon="INFO")

    if gauss_image.exists(obj):
        layout.prop(rec, "show_gauss_image", text="Show Gauss Image")


class VIEW3D_PT_developable_result(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Last Run"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            layout.label(text="No mesh selected")
            return
        if not obj.developable.has_result:
            keys = obj.data.shape_keys
            if keys and keys.key_blocks.get(writeback.SHAPE_KEY) and obj.data.users > 1:
                for line in wrap(
                    "This mesh is shared: it was made developable through "
                    "another object, whose panel has the figures",
                    line_chars(context),
                ):
                    layout.label(text=line)
            else:
                layout.label(text="No run on this object yet")
            return
        draw_result(layout, context, obj)


classes = (
    VIEW3D_PT_developable,
    VIEW3D_PT_developable_result,
    VIEW3D_PT_developable_pins,
    VIEW3D_PT_developable_parameters,
)


def register():
    wm = bpy.types.WindowManager
    wm.developable_show_pins = bpy.props.BoolProperty(name="Pins", default=False)
    wm.developable_show_advanced = bpy.props.BoolProperty(name="Advanced", default=False)
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
    del bpy.types.WindowManager.developable_show_advanced
    del bpy.types.WindowManager.developable_show_pins

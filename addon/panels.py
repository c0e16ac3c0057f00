# SPDX-License-Identifier: GPL-3.0-or-later
"""The sidebar tab "Developable" (3D viewport, N panel): the job, how far the
shape may move, Keep the boundary, Run, the last run's figures; pins, the
expert settings and the flat pattern in collapsed sub-panels. The redo panel
draws the same settings (draw_settings). Panels only draw: the buttons name
the operators by their idname, the figures come from the objects' records.

No text is cut with an ellipsis at the default sidebar width: every label
that could be long goes on its own line and is wrapped between words to the
width it is measured to take (blf, the UI font at the UI scale), and fields
are drawn without a label of their own beside them."""

import blf
import bpy
from bpy.types import Panel

from . import gauss_image, mesh_io, writeback
from .core import native
from .core.estimate import LARGE_MESH_FACES, boundary_edges, expected_seconds
from .core.text import (
    designer_words,
    duration,
    library_message,
    milliseconds,
    percent,
    plural,
    share,
    signed_percent,
    wrap,
)
from .core.verdict import TITLES

CATEGORY = "Developable"
MAKE_DEVELOPABLE = "mesh.make_developable"
UNFOLD_PATTERN = "mesh.unfold_pattern"
WELD = "mesh.developable_weld"

# The sidebar's width at UI scale 1 when the window has none (Blender's
# UI_SIDEBAR_PANEL_WIDTH in 3.4 - 4.x; wider in later versions).
DEFAULT_SIDEBAR = 220
# Pixels at UI scale 1 between the sidebar's width and the room a label's
# text has in a panel (the category tabs, the panel's and the layout's
# margins, the label's own padding), and what an icon, a box, a checkbox, a
# button and a drop-down take from it. Measured on 3.4 in a window (the
# default 220-pixel sidebar): a label 158 pixels wide is drawn whole, one of
# 164 is cut; with an icon 131 / 137; in a box 143 / 152; a checkbox's text
# 137 / 143; a button's 152 / 158.
LABEL_MARGIN = 62
ICON = 27
BOX_MARGIN = 16
CHECKBOX = 22
BUTTON = 8
DROPDOWN = 22

# The engine's generators (native.ORIGIN_NAMES) in a designer's words.
ORIGIN_WORDS = {
    "input": "your mesh, unchanged",
    "deformation": "the deformation",
    "deformation_polish": "the deformation, then polish",
    "near_flat_polish": "the deformation, then polish",
    "input_polish": "polishing your mesh",
    "smoothed_input_polish": "smoothing, then polish",
    "smoothed_step_polish": "smoothing, then polish",
    "projected_input": "smoothing, then projection",
    "thinned_pieces": "thinning into ruled pieces, then polish",
    "ruled_finish": "polish, then straightening the rulings",
}
STOP_WORDS = {
    "already developable": "there was nothing to do",
    "converged": "the curvature stopped changing",
    "iteration limit": "it reached Max Iterations",
    "stalled": "it stopped gaining",
}


class Room:
    """How much text fits on a line of the region being drawn, measured in
    the UI font as Blender draws it (blf, at the UI scale)."""

    def __init__(self, context, inset=0):
        system = context.preferences.system
        self.scale = system.ui_scale if system.ui_scale > 0 else 1.0
        region = context.region
        width = region.width if region is not None and region.width > 1 else DEFAULT_SIDEBAR * self.scale
        self.width = width - (LABEL_MARGIN + inset) * self.scale
        style = context.preferences.ui_styles[0]
        self.points = getattr(style, "widget_label", None) or style.widget
        self.points = self.points.points

    def inset(self, pixels):
        room = Room.__new__(Room)
        room.scale, room.points, room.width = self.scale, self.points, self.width - pixels * self.scale
        return room

    def text_width(self, text):
        if bpy.app.version >= (4, 0, 0):
            blf.size(0, self.points * self.scale)
        else:
            blf.size(0, self.points * self.scale, 72)
        return blf.dimensions(0, text)[0]

    def fits(self, text, icon=False):
        return self.text_width(text) + (ICON * self.scale if icon else 0) <= self.width

    def lines(self, text, icon=False):
        return wrap(text, lambda line: self.fits(line, icon))


def text_lines(layout, room, text, icon="NONE", alert=False):
    """A text as lines that fit; the icon on the first, room kept for it on the others."""
    col = layout.column(align=True)
    col.alert = alert
    with_icon = icon != "NONE"
    for i, line in enumerate(room.lines(text, icon=with_icon)):
        col.label(text=line, icon=(icon if i == 0 else "BLANK1") if with_icon else "NONE")
    return col


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


def draw_main(layout, owner, context, room):
    """The job, how far the shape may move, the boundary, the modifiers."""
    obj = context.active_object
    col = layout.column(align=True)
    col.label(text="Job")
    col.prop(owner, "preset", text="")
    col = layout.column(align=True)
    if owner.limit_in_edges:
        col.label(text="Shape may move (edge lengths)")
        col.prop(owner, "tolerance", text="")
        text_lines(col, room, "Set in Advanced", icon="INFO")
    else:
        col.label(text="Shape may move")
        col.prop(owner, "move_limit", text="", slider=True)
        if obj is not None and obj.type == "MESH":
            size = object_size(obj)
            if owner.move_limit > 0:
                text_lines(
                    col,
                    room,
                    "up to %s (%g %% of %s)"
                    % (
                        length_text(context, owner.move_limit / 100.0 * size),
                        owner.move_limit,
                        length_text(context, size),
                    ),
                )
            else:
                col.label(text="no limit")
    layout.prop(owner, "pin_boundary", text="Keep the boundary")
    if obj is not None and obj.type == "MESH":
        modifiers = mesh_io.shown_modifiers(obj)
        if modifiers:
            col = layout.column(align=True)
            text_lines(col, room, "%s has modifiers (%s); make developable:" % (obj.name, ", ".join(modifiers)))
            col.prop(owner, "modifiers", text="")


def draw_pins(layout, owner, obj):
    col = layout.column(align=True)
    col.label(text="Pin vertex group")
    if obj is not None and obj.type == "MESH":
        col.prop_search(owner, "pin_group", obj, "vertex_groups", text="")
    else:
        col.prop(owner, "pin_group", text="")
    col.prop(owner, "pin_selection", text="Pin selection (Edit mode)")
    col.prop(owner, "use_mls_weights", text="Soft falloff around pins")


def draw_advanced(layout, owner):
    """Every engine parameter, in words (the paper's symbols in the tooltips)."""
    col = layout.column(align=True)
    _labelled(col, owner, "omega", "Flattening strength")
    col.prop(owner, "limit_in_edges", text="Limit in edge lengths")
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
    row.prop(owner, "polish_smoothed_input", text="Polish smoothed mesh")
    col = layout.column(align=True)
    _labelled(col, owner, "max_iterations", "Max iterations")
    _labelled(col, owner, "stop_relative_change", "Stop below change")
    _labelled(col, owner, "developable_threshold", "Flat enough below 10^ rad")
    layout.prop(owner, "gauss_image", text="Build the Gauss image")


def draw_settings(layout, owner, context, in_redo=False):
    """All settings of `owner` (scene settings or the operator in the redo panel)."""
    layout.use_property_split = False
    layout.use_property_decorate = False
    draw_main(layout, owner, context, Room(context))
    if in_redo:
        wm = context.window_manager
        for name, text, draw in (
            ("developable_show_pins", "Pins", lambda box: draw_pins(box, owner, context.active_object)),
            ("developable_show_advanced", "Advanced", lambda box: draw_advanced(box, owner)),
        ):
            box = layout.box()
            shown = getattr(wm, name)
            box.prop(wm, name, text=text, emboss=False, icon="TRIA_DOWN" if shown else "TRIA_RIGHT")
            if shown:
                draw(box)


def _selected_meshes(context):
    obj = context.active_object
    meshes = [o for o in context.selected_objects if o.type == "MESH"]
    if obj is not None and obj.type == "MESH" and obj not in meshes:
        meshes.append(obj)
    return meshes


def draw_unwelded(layout, room, obj):
    """A warning and the Merge by Distance button when the object's mesh has
    unwelded seams (checked in Object mode, on meshes the panel can check
    quickly; larger ones are checked by the run)."""
    if obj.mode != "OBJECT" or len(obj.data.polygons) > LARGE_MESH_FACES:
        return
    count = len(mesh_io.unwelded(obj.data))
    if count:
        box = layout.box()
        text_lines(
            box,
            room.inset(BOX_MARGIN),
            "Unwelded seams: %s lie on another boundary vertex; the sides of each seam would be made "
            "developable and unfolded apart" % plural(count, "vertex", "vertices"),
            icon="ERROR",
        )
        box.operator(WELD, icon="AUTOMERGE_ON")


class VIEW3D_PT_developable(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_label = "Make Developable"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = False
        layout.use_property_decorate = False
        room = Room(context)
        obj = context.active_object
        lib, err = native.try_load()
        if lib is None:
            text_lines(layout, room, library_message(err), icon="ERROR", alert=True)
        settings = context.scene.developable
        draw_main(layout, settings, context, room)
        if obj is not None and obj.type == "MESH":
            draw_unwelded(layout, room, obj)
        row = layout.row()
        row.scale_y = 1.5
        row.enabled = lib is not None
        meshes = _selected_meshes(context)
        row.operator(MAKE_DEVELOPABLE, text="Run on %d meshes" % len(meshes) if len(meshes) > 1 else "Run", icon="PLAY")
        if obj is None or obj.type != "MESH":
            text_lines(layout, room, "Select a mesh object", icon="INFO")
        elif context.mode not in {"OBJECT", "EDIT_MESH"}:
            mode = context.mode.replace("_", " ").title()
            text_lines(layout, room, "Works in Object or Edit mode: leave %s mode first" % mode, icon="INFO")
        if context.mode == "EDIT_MESH" and settings.pin_selection:
            text_lines(layout, room, "Selected vertices stay put", icon="PINNED")
        if obj is not None and obj.type == "MESH":
            if obj.data.users > 1:
                text_lines(layout, room, "Mesh shared by %d objects" % obj.data.users, icon="LINKED")
            # triangles the engine will see: loop triangles when Blender has them,
            # else 2 per polygon (quads); never computed here, drawing must be cheap
            faces = len(obj.data.loop_triangles) or 2 * len(obj.data.polygons)
            if faces >= LARGE_MESH_FACES:
                shortest, longest = (
                    duration(t)
                    for t in expected_seconds(
                        faces,
                        boundary_edges(len(obj.data.edges), len(obj.data.loops)) == 0,
                        settings.mode,
                        settings.solver,
                        settings.segmentation,
                        0 if settings.auto_target_patches else settings.target_patches,
                        settings.max_iterations,
                        settings.polish,
                    )
                )
                expected = shortest if shortest == longest else "%s to %s" % (shortest, longest)
                text_lines(layout, room, "Large mesh: the run takes about %s" % expected, icon="TIME")


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


ICONS = {
    "IMPROVED": "CHECKMARK",
    "GATHERED": "INFO",
    "CRUMPLED": "ERROR",
    "WORSE": "ERROR",
    "UNCHANGED": "INFO",
    "DEVELOPABLE": "CHECKMARK",
}


def _without_name(text, name):
    prefix = name + ": "
    return text[len(prefix) :] if text.startswith(prefix) else text


def draw_figures(layout, context, room, rec):
    col = layout.column(align=True)
    if rec.verdict in ("UNCHANGED", "DEVELOPABLE"):  # the input came back: its own figures
        lines = ["Flat vertices: %s" % share(rec.flat_before), "Flat and ruled: %s" % share(rec.ruled_before)]
    else:
        lines = [
            "Flat vertices: %s \u2192 %s" % (share(rec.flat_before), share(rec.flat_after)),
            "Flat and ruled: %s \u2192 %s" % (share(rec.ruled_before), share(rec.ruled_after)),
            "Curvature: %s" % signed_percent(rec.change_percent),
            "Largest move: %s of size" % percent(rec.move_percent),
        ]
        moved = length_text(context, rec.largest_move)
        if rec.move_limit > 0:
            moved += " of %s allowed" % length_text(context, rec.move_limit)
        lines.append("(%s)" % moved)
    for line in lines:
        text_lines(col, room, line)
    col.label(text="Faces turned over: %d" % rec.faces_turned, icon="ERROR" if rec.faces_turned else "NONE")
    details = ["Time: %s" % milliseconds(rec.time_ms)]
    if rec.result_origin in ORIGIN_WORDS and rec.result_origin != "input":
        details.append("Made by %s" % ORIGIN_WORDS[rec.result_origin])
    if rec.verdict in ("WORSE", "UNCHANGED") and rec.stop_reason in STOP_WORDS:
        details.append("Stopped: %s" % STOP_WORDS[rec.stop_reason])
    details.append("Pieces: %d; pinned vertices: %d" % (rec.patches, rec.pinned))
    for line in details:
        text_lines(col, room, line)


def draw_result(layout, context, obj):
    rec = obj.developable
    room = Room(context)
    if rec.error:
        text_lines(layout.box(), room.inset(BOX_MARGIN), "The last try failed: " + rec.error, icon="ERROR")
        if not rec.has_result:
            return
        text_lines(layout, room, "The figures below are of the run before")
    col = layout.column(align=True)
    col.label(text=TITLES[rec.verdict], icon=ICONS[rec.verdict])
    if rec.verdict != "IMPROVED":
        text_lines(layout.box(), room.inset(BOX_MARGIN), _without_name(rec.message, obj.name))
    if rec.interior_vertices > 0:
        draw_figures(layout, context, room, rec)
    if rec.engine_result:
        text_lines(layout, room, "Engine says: " + designer_words(rec.engine_result))
    col = layout.column(align=True)
    if rec.shape_source:
        text_lines(col, room, "Made developable: " + rec.shape_source)
    if rec.world_space:
        text_lines(col, room, "In world space (the object's scale)", icon="OBJECT_ORIGIN")
    if obj.data.users > 1:
        text_lines(col, room, "Mesh shared with other objects", icon="LINKED")
    if rec.interior_vertices == 0:
        return
    keys = obj.data.shape_keys
    kb = keys.key_blocks.get(writeback.SHAPE_KEY) if keys else None
    if kb is not None:
        layout.prop(kb, "value", text="Developable", slider=True)
    col = layout.column(align=True)
    col.label(text="Curvature colours")
    col.prop(rec, "show_after", text="After" if rec.show_after else "Before", toggle=True, icon="HIDE_OFF")
    col.label(text="blue \u2212 / white 0 / red +")
    text_lines(col, room, "full colour at \u00b1%.2g rad" % rec.colour_scale)
    space = context.space_data
    shading = getattr(space, "shading", None) if space else None
    if shading is not None:
        if shading.type == "SOLID":
            col.prop(shading, "color_type", text="")
            if shading.color_type != "VERTEX":
                text_lines(col, room, "Pick Attribute to see them", icon="INFO")
        else:
            text_lines(col, room, "Colours show in Solid view", icon="INFO")
    if gauss_image.exists(obj):
        layout.prop(rec, "show_gauss_image", text="Show Gauss image")


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
        if not obj.developable.has_result and not obj.developable.error:
            keys = obj.data.shape_keys
            if keys and keys.key_blocks.get(writeback.SHAPE_KEY) and obj.data.users > 1:
                text_lines(
                    layout,
                    Room(context),
                    "This mesh is shared: it was made developable through another object, whose panel "
                    "has the figures",
                )
            else:
                layout.label(text="No run on this object yet")
            return
        draw_result(layout, context, obj)


def scale_text(scale):
    if scale <= 0:
        return "-"
    return ("%g:1" % scale) if scale >= 1 else ("1:%g" % round(1.0 / scale, 6))


class VIEW3D_PT_developable_pattern(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Flat Pattern"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = False
        layout.use_property_decorate = False
        room = Room(context)
        settings = context.scene.developable_pattern
        col = layout.column(align=True)
        _labelled(col, settings, "sheet", "Sheet")
        if settings.sheet == "CUSTOM":
            _labelled(col, settings, "sheet_width", "Width (mm)")
            _labelled(col, settings, "sheet_height", "Height (mm)")
        _labelled(col, settings, "margin", "Margin (mm)")
        _labelled(col, settings, "unit", "One Blender unit is")
        col = layout.column(align=True)
        col.prop(settings, "auto_scale", text="Fit scale")
        sub = col.column(align=True)
        sub.enabled = not settings.auto_scale
        _labelled(sub, settings, "scale", "Scale (paper : model)")
        col = layout.column(align=True)
        _labelled(col, settings, "seam_tolerance", "Seam tolerance")
        # One or the other: the set one greys the other out.
        sub = col.column(align=True)
        sub.enabled = settings.glue_tabs == 0.0
        _labelled(sub, settings, "seam_allowance", "Seam allowance (mm)")
        sub = col.column(align=True)
        sub.enabled = settings.seam_allowance == 0.0
        _labelled(sub, settings, "glue_tabs", "Glue tabs (mm)")
        col = layout.column(align=True)
        col.prop(settings, "export_svg", text="Export SVG")
        sub = col.row()
        sub.enabled = settings.export_svg
        sub.prop(settings, "filepath", text="")
        row = layout.row()
        row.scale_y = 1.3
        meshes = _selected_meshes(context)
        row.operator(
            UNFOLD_PATTERN, text="Unfold %d meshes" % len(meshes) if len(meshes) > 1 else "Unfold Pattern", icon="UV"
        )
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            return
        rec = obj.developable_pattern
        if rec.error:
            text_lines(layout.box(), room.inset(BOX_MARGIN), "The last unfolding failed: " + rec.error, icon="ERROR")
            if rec.has_result:
                text_lines(layout, room, "The figures below are of the unfolding before")
        if not rec.has_result:
            return
        if rec.warning:
            text_lines(layout.box(), room.inset(BOX_MARGIN), rec.warning, icon="ERROR")
        box = layout.box()
        inner = room.inset(BOX_MARGIN)
        for line in (
            "%s on %s" % (plural(rec.pieces, "piece", "pieces"), plural(rec.sheets, "sheet", "sheets")),
            "%s, scale %s" % (plural(rec.seams, "seam", "seams"), scale_text(rec.scale)),
            "Worst strain: %s" % percent(rec.worst_strain),
            "Mean strain: %s" % percent(rec.mean_strain),
            "From the %s" % rec.source,
        ):
            text_lines(box, inner, line)
        if rec.splits:
            text_lines(
                box,
                inner,
                "%s where a piece would overlap or stretch its seams" % plural(rec.splits, "split", "splits"),
                icon="INFO",
            )


classes = (
    VIEW3D_PT_developable,
    VIEW3D_PT_developable_result,
    VIEW3D_PT_developable_pins,
    VIEW3D_PT_developable_parameters,
    VIEW3D_PT_developable_pattern,
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

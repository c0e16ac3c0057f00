# SPDX-License-Identifier: GPL-3.0-or-later
"""The sidebar panel (3D viewport, N panel, tab "Developable")."""

import bpy
from bpy.types import Panel

from . import gauss_image, native, writeback
from .operators import MESH_OT_make_developable
from .properties import ENGINE_PARAMETERS, PIN_PARAMETERS

CATEGORY = "Developable"

# Expected run time on 2 cores, fitted to docs/benchmarks.md (10k-1M faces):
#   decoupled factorisation   faces * 3 us * (faces / 1e5)^0.35, once
#   one iteration             faces * 0.25 us on one patch, ~0.6 us segmented
#   iterations                ~60 on one patch (stall rule), ~300 segmented
#   coupled factorisation     faces * 30 us * (faces / 1e4)^0.4: once in paper
#                             mode, every iteration with the coupled solver
# max_iterations caps the iterations. Automatic segmentation is decided by the
# engine, so the panel gives the range between the one-patch and the
# segmented run.
LARGE_MESH_FACES = 100_000


def expected_seconds(faces, settings):
    """(shortest, longest) expected run time in seconds."""
    cap = int(settings.max_iterations)
    coupled = faces * 30e-6 * (faces / 1e4) ** 0.4
    if settings.mode == 'PAPER':
        return (coupled,) * 2
    decoupled = faces * 3e-6 * (faces / 1e5) ** 0.35

    def run(iterations, per_face):
        iterations = min(cap, iterations)
        if settings.solver == 'COUPLED':
            return iterations * (coupled + faces * per_face)
        return decoupled + iterations * faces * per_face

    one_patch, segmented = run(60, 0.25e-6), run(300, 0.6e-6)
    if settings.segmentation == 'OFF':
        return one_patch, one_patch
    if settings.segmentation == 'ON' or settings.target_patches > 1:
        return segmented, segmented
    return one_patch, segmented


def _duration_text(seconds):
    if seconds < 90:
        return "%.0f s" % max(seconds, 1)
    if seconds < 5400:
        return "%.0f min" % (seconds / 60)
    return "%.1f h" % (seconds / 3600)


def draw_parameters(layout, owner, obj):
    """Engine parameters and pins of `owner` (scene settings or the operator)."""
    # Labels inside the fields: the sidebar is narrow.
    layout.use_property_split = False
    layout.use_property_decorate = False
    col = layout.column(align=True)
    col.prop(owner, "omega")
    col.prop(owner, "tolerance")
    col.prop(owner, "max_iterations")
    layout.prop(owner, "mode")
    sub = layout.row()
    sub.active = owner.mode != 'PAPER'
    sub.prop(owner, "solver")
    col = layout.column(align=True)
    col.prop(owner, "stop_relative_change")
    col.prop(owner, "developable_threshold")
    col = layout.column(align=True)
    col.prop(owner, "segmentation")
    sub = col.column(align=True)
    sub.active = owner.segmentation != 'OFF'
    sub.prop(owner, "target_patches")
    sub.prop(owner, "segment_max_error")
    sub.prop(owner, "seams")
    sub.prop(owner, "target_smoothing")
    layout.prop(owner, "grid_resolution")
    box = layout.column(align=True)
    box.label(text="Pins", icon='PINNED')
    box.prop(owner, "pin_boundary", text="Boundary")
    if obj is not None and obj.type == 'MESH':
        box.prop_search(owner, "pin_group", obj, "vertex_groups", text="Vertex Group")
    else:
        box.prop(owner, "pin_group")
    box.prop(owner, "pin_selection", text="Selection (Edit mode)")
    box.prop(owner, "use_mls_weights")
    layout.prop(owner, "gauss_image")


class VIEW3D_PT_developable(Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = CATEGORY
    bl_label = "Make Developable"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        lib, err = native.try_load()
        if lib is None:
            col = layout.column(align=True)
            col.alert = True
            col.label(text="Engine library not available", icon='ERROR')
            for line in _wrap(err, 42):
                col.label(text=line)
        else:
            layout.label(text="Engine %s" % native.version(), icon='CHECKMARK')
        if obj is None or obj.type != 'MESH':
            layout.label(text="Select a mesh object", icon='INFO')
        settings = context.scene.developable
        row = layout.row()
        row.scale_y = 1.5
        row.enabled = lib is not None
        op = row.operator(MESH_OT_make_developable.bl_idname, text="Run", icon='PLAY')
        for name in ENGINE_PARAMETERS + PIN_PARAMETERS:
            setattr(op, name, getattr(settings, name))
        if context.mode == 'EDIT_MESH' and settings.pin_selection:
            layout.label(text="Selected vertices will be pinned", icon='PINNED')
        if obj is not None and obj.type == 'MESH':
            # triangles the engine will see: loop triangles when Blender has them,
            # else 2 per polygon (quads); never computed here, drawing must be cheap
            faces = len(obj.data.loop_triangles) or 2 * len(obj.data.polygons)
            if faces >= LARGE_MESH_FACES:
                shortest, longest = (_duration_text(t) for t in expected_seconds(faces, settings))
                expected = shortest if shortest == longest else "%s to %s" % (shortest, longest)
                layout.label(text="Large mesh: expect about %s" % expected, icon='TIME')


class VIEW3D_PT_developable_parameters(Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Parameters"

    def draw(self, context):
        draw_parameters(self.layout, context.scene.developable, context.active_object)


class VIEW3D_PT_developable_result(Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = CATEGORY
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Last Run"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if obj is None or obj.type != 'MESH' or not obj.developable.has_result:
            layout.label(text="No run on this object yet")
            return
        rec = obj.developable
        grid = layout.grid_flow(row_major=True, columns=2, even_columns=False, align=True)
        for label, value in (
                ("E before", "%.4g rad" % rec.e_before),
                ("E after", "%.4g rad" % rec.e_after),
                ("dE", "%+.1f %%" % rec.change_percent),
                ("Time", "%.0f ms" % rec.time_ms),
                ("t_D / t_I", "%.0f / %.0f ms" % (rec.time_decompose_ms, rec.time_iterate_ms)),
                ("Iterations", "%d (%s)" % (rec.iterations, rec.stop_reason)),
                ("Largest move", "%.4g" % rec.max_move),
                ("  in AE", "%.2f AE" % rec.max_move_ae),
                ("Patches", "%d, %d curves" % (rec.patches, rec.curves)),
                ("Pinned", "%d vertices" % rec.pinned)):
            grid.label(text=label)
            grid.label(text=value)

        keys = obj.data.shape_keys
        kb = keys.key_blocks.get(writeback.SHAPE_KEY) if keys else None
        if kb is not None:
            layout.prop(kb, "value", text="Developable", slider=True)

        col = layout.column(align=True)
        col.label(text="Defect colours")
        row = col.row(align=True)
        row.prop(rec, "show_after", text="After" if rec.show_after else "Before",
                 toggle=True, icon='HIDE_OFF')
        col.label(text="\u00b1%.3g rad, both states" % rec.colour_scale)
        col.label(text="blue \u2212 / white 0 / red +")
        if context.space_data and getattr(context.space_data, "shading", None):
            shading = context.space_data.shading
            if shading.type == 'SOLID':
                col.prop(shading, "color_type", text="")

        if gauss_image.exists(obj):
            layout.prop(rec, "show_gauss_image", text="Show Gauss Image")
        else:
            layout.label(text="Gauss image: tick 'Gauss Image' and run", icon='SPHERE')


def _wrap(text, width):
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


classes = (VIEW3D_PT_developable, VIEW3D_PT_developable_parameters, VIEW3D_PT_developable_result)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)

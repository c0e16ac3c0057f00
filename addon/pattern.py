# SPDX-License-Identifier: GPL-3.0-or-later
"""Unfold Pattern: the flat pieces of the "Developable" shape key (or of the
base mesh when there is none) through dev_unfold.

Writes, all undoable in one step, nothing to the base mesh's coordinates:
  - the UV map "Developable Pattern": one island per piece, laid out like the
    sheets (sheet k right of sheet k-1, one sheet height = 1 UV unit);
  - edge seams (use_seam) where the pattern is cut: patch borders, the cuts
    that open bands and tubes, the splits (added to the user's own seams);
  - the face attribute "pattern_strain": the largest relative edge-length
    change of the face's triangles in the flat map;
  - the SVG sheets (when the export is on) and the figures shown in the panel.

Settings (scene.developable_pattern), the per-object figures
(object.developable_pattern), the operator and the sub-panel of the
Developable panel live here."""

import os

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy.types import Operator, Panel, PropertyGroup

from . import checks, mesh_io, native, writeback

UV_MAP = "Developable Pattern"
STRAIN = "pattern_strain"
SHEET_GAP = 0.05  # UV units between two sheets side by side

SHEETS = [
    ("A4", "A4", "210 x 297 mm"),
    ("A3", "A3", "297 x 420 mm"),
    ("LETTER", "Letter", "8.5 x 11 in"),
    ("CUSTOM", "Custom", "Width and height below"),
]
UNITS = [
    ("SCENE", "Scene", "The scene's unit scale: one Blender unit is Unit Scale metres"),
    ("m", "m", "One Blender unit is a metre"),
    ("cm", "cm", "One Blender unit is a centimetre"),
    ("mm", "mm", "One Blender unit is a millimetre"),
    ("in", "in", "One Blender unit is an inch"),
]


class DevelopablePatternSettings(PropertyGroup):
    filepath: StringProperty(
        name="File",
        subtype="FILE_PATH",
        default="//pattern.svg",
        description="The SVG to write; more sheets go to name-1.svg, name-2.svg, ...",
    )
    export_svg: BoolProperty(name="Export SVG", default=True, description="Write the sheets as SVG at true scale")
    sheet: EnumProperty(name="Sheet", items=SHEETS, default="A4", description="Paper size, portrait")
    sheet_width: FloatProperty(
        name="Width", default=210.0, min=10.0, max=10000.0, unit="NONE", description="Custom sheet width, mm"
    )
    sheet_height: FloatProperty(
        name="Height", default=297.0, min=10.0, max=10000.0, description="Custom sheet height, mm"
    )
    margin: FloatProperty(
        name="Margin", default=10.0, min=0.0, max=100.0, description="Free margin on every side of a sheet, mm"
    )
    auto_scale: BoolProperty(
        name="Fit Scale",
        default=False,
        description="Use the largest of 1:1, 1:2, 1:5, 1:10, ... at which every piece fits",
    )
    scale: FloatProperty(
        name="Scale",
        default=1.0,
        min=1e-6,
        max=1e6,
        precision=4,
        description="Paper length per model length: 1 is 1:1, 0.1 is 1:10",
    )
    unit: EnumProperty(
        name="Model Unit", items=UNITS, default="SCENE", description="What one Blender unit is, for the true scale"
    )
    seam_tolerance: FloatProperty(
        name="Seam Tolerance",
        default=0.25,
        min=0.0,
        max=50.0,
        subtype="PERCENTAGE",
        description="Largest stretch of a piece's outline edge before the piece "
        "is split, so that both sides of a seam match within twice "
        "this; 0 splits only pieces that would overlap",
    )
    seam_allowance: FloatProperty(
        name="Seam Allowance",
        default=0.0,
        min=0.0,
        max=100.0,
        description="Cut every piece this far outside its outline on the sheet, "
        "mm, for sewing or gluing; the outline is drawn dashed as "
        "the seam line. 0 cuts on the outline",
    )
    glue_tabs: FloatProperty(
        name="Glue Tabs",
        default=0.0,
        min=0.0,
        max=100.0,
        description="A glue tab this high on one side of every seam, mm on the sheet, "
        "folded along the seam (papercraft); 0: none. Not with a seam "
        "allowance",
    )


class DevelopablePatternRecord(PropertyGroup):
    """Figures of the object's last unfolding (undone with it)."""

    has_result: BoolProperty(default=False)
    pieces: IntProperty(name="Pieces")
    sheets: IntProperty(name="Sheets")
    seams: IntProperty(name="Seams")
    splits: IntProperty(name="Splits")
    worst_strain: FloatProperty(name="Worst Strain", subtype="PERCENTAGE")
    mean_strain: FloatProperty(name="Mean Strain", subtype="PERCENTAGE")
    scale: FloatProperty(name="Scale")
    files: StringProperty(name="Files")
    source: StringProperty(name="Source")


def sheet_size(settings):
    if settings.sheet == "CUSTOM":
        return settings.sheet_width, settings.sheet_height
    return native.SHEETS_MM[settings.sheet.lower()]


def unit_of(settings, scene):
    """(mm per Blender unit, unit name)."""
    if settings.unit == "SCENE":
        metres = scene.unit_settings.scale_length if scene.unit_settings.scale_length > 0 else 1.0
        return 1000.0 * metres, ("m" if metres == 1.0 else "BU")
    return native.UNIT_MM[settings.unit], settings.unit


def pattern_params(settings, scene):
    width, height = sheet_size(settings)
    unit_mm, unit_name = unit_of(settings, scene)
    return {
        "sheet_width_mm": width,
        "sheet_height_mm": height,
        "margin_mm": settings.margin,
        "scale": 0.0 if settings.auto_scale else settings.scale,
        "unit_mm": unit_mm,
        "unit_name": unit_name,
        "seam_tolerance": settings.seam_tolerance / 100.0,
        "seam_allowance_mm": settings.seam_allowance,
        "glue_tabs_mm": settings.glue_tabs,
    }


def source_positions(obj):
    """(positions (n, 3) float64 in world units, name): what the viewport shows
    with the Developable key at full strength (the other keys' mix plus the
    key's offset from the reference), else the shown mix of the base mesh.
    Rotation and scale are applied so that the pattern is at true size; the
    translation is left out (it does not change the pieces)."""
    ref, mix = mesh_io.read_visible_positions(obj, exclude=(writeback.SHAPE_KEY,))
    keys = obj.data.shape_keys
    name = "base mesh"
    if keys is not None and writeback.SHAPE_KEY in keys.key_blocks:
        block = keys.key_blocks[writeback.SHAPE_KEY]
        co = np.empty(len(block.data) * 3, dtype=np.float32)
        block.data.foreach_get("co", co)
        mix = mix + (co.reshape(-1, 3).astype(np.float64) - ref)
        name = "shape key " + writeback.SHAPE_KEY
    return mix @ mesh_io.linear_part(obj).T, name


def triangle_patches(mesh, buffers):
    """Patch id per loop triangle from the face attribute of the last run, or None."""
    attr = mesh.attributes.get(writeback.PATCH_ID)
    if attr is None or attr.domain != "FACE" or attr.data_type != "INT":
        return None
    per_face = np.empty(len(mesh.polygons), dtype=np.int32)
    attr.data.foreach_get("value", per_face)
    return per_face[buffers.tri_polygon] if len(buffers.tri_polygon) else None


def write_uv_map(mesh, pattern, height_mm, width_mm):
    """One island per piece, as on the sheets, y up."""
    layer = mesh.uv_layers.get(UV_MAP) or mesh.uv_layers.new(name=UV_MAP)
    t = len(mesh.loop_triangles)
    loops = np.empty(t * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    sheet_of_piece = np.array([p["sheet"] for p in pattern.pieces], dtype=np.float64)
    sheet = np.repeat(sheet_of_piece[pattern.piece_ids], 3)
    corners = pattern.sheet_uvs.reshape(-1, 2)
    uv = np.zeros((len(mesh.loops), 2), dtype=np.float32)
    uv[loops, 0] = corners[:, 0] / height_mm + sheet * (width_mm / height_mm + SHEET_GAP)
    uv[loops, 1] = 1.0 - corners[:, 1] / height_mm
    layer.data.foreach_set("uv", uv.reshape(-1))
    mesh.uv_layers.active = layer
    return layer


def mark_seams(mesh, pattern):
    """use_seam on every mesh edge of a seam (triangulation diagonals inside a
    polygon are no mesh edges: skipped). Returns how many edges were marked."""
    if not pattern.seams:
        return 0
    n = len(mesh.vertices)
    ev = np.empty(len(mesh.edges) * 2, dtype=np.int64)
    mesh.edges.foreach_get("vertices", ev)
    ev = np.sort(ev.reshape(-1, 2), axis=1)
    pairs = np.sort(np.concatenate([s["vertices"] for s in pattern.seams]).astype(np.int64), axis=1)
    on_seam = np.isin(ev[:, 0] * n + ev[:, 1], pairs[:, 0] * n + pairs[:, 1])
    seams = np.empty(len(mesh.edges), dtype=bool)
    mesh.edges.foreach_get("use_seam", seams)
    mesh.edges.foreach_set("use_seam", seams | on_seam)
    return int(on_seam.sum())


def write_strain(mesh, pattern, buffers):
    per_face = np.zeros(len(mesh.polygons), dtype=np.float32)
    np.maximum.at(per_face, buffers.tri_polygon, pattern.face_strain.astype(np.float32))
    attr = mesh.attributes.get(STRAIN)
    if attr is not None and (attr.domain != "FACE" or attr.data_type != "FLOAT"):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(name=STRAIN, type="FLOAT", domain="FACE")
    attr.data.foreach_set("value", per_face)


class MESH_OT_unfold_pattern(Operator):
    """Unfold the developable patches into flat pieces: a UV map, seams, a strain attribute and SVG sheets at true scale"""

    bl_idname = "mesh.unfold_pattern"
    bl_label = "Unfold Pattern"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(
        name="File",
        subtype="FILE_PATH",
        default="",
        description="SVG to write instead of the one in the settings",
        options={"SKIP_SAVE"},
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def execute(self, context):
        obj = context.active_object
        settings = context.scene.developable_pattern
        lib, err = native.try_load()
        if lib is None:
            self.report({"ERROR"}, err)
            return {"CANCELLED"}
        path = ""
        if settings.export_svg or self.filepath:
            raw = self.filepath or settings.filepath
            if raw.startswith("//") and not bpy.data.filepath:
                self.report({"ERROR"}, "Save the .blend file first or choose an absolute path for the SVG")
                return {"CANCELLED"}
            path = os.path.abspath(bpy.path.abspath(raw))
            if not path.lower().endswith(".svg"):
                path += ".svg"
        was_edit = obj.mode == "EDIT"
        if was_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            mesh = obj.data
            buffers = mesh_io.read_mesh(mesh)
            if len(buffers.triangles) == 0:
                self.report({"ERROR"}, "The mesh has no faces")
                return {"CANCELLED"}
            try:
                positions, source = source_positions(obj)
            except mesh_io.MeshInputError as exc:
                self.report({"ERROR"}, str(exc))
                return {"CANCELLED"}
            try:
                # A polygon's triangles stay in one piece: one UV island per piece.
                pattern = native.unfold(
                    positions,
                    buffers.triangles,
                    triangle_patches(mesh, buffers),
                    pattern_params(settings, context.scene),
                    svg_path=path or None,
                    face_groups=buffers.tri_polygon,
                )
            except native.EngineError as exc:
                self.report({"ERROR"}, "Cannot unfold the pattern (%s): %s" % (exc.status_name, exc.message))
                return {"CANCELLED"}
            width, height = sheet_size(settings)
            write_uv_map(mesh, pattern, height, width)
            mark_seams(mesh, pattern)
            write_strain(mesh, pattern, buffers)
            mesh.update()
            st = pattern.stats
            rec = obj.developable_pattern
            rec.has_result = True
            rec.pieces = int(st["pieces"])
            rec.sheets = int(st["sheets"])
            rec.seams = int(st["seams"])
            rec.splits = int(st["splits"])
            rec.worst_strain = 100.0 * st["max_strain"]
            rec.mean_strain = 100.0 * st["mean_strain"]
            rec.scale = st["scale"]
            rec.files = "; ".join(pattern.files)
            rec.source = source
        finally:
            if was_edit:
                bpy.ops.object.mode_set(mode="EDIT")
        where = (
            (
                " to %s" % pattern.files[0]
                + (" and %d more" % (len(pattern.files) - 1) if len(pattern.files) > 1 else "")
            )
            if pattern.files
            else ""
        )
        pieces = checks.plural(st["pieces"], "piece", "pieces")
        sheets = checks.plural(st["sheets"], "sheet", "sheets")
        self.report(
            {"INFO"},
            "%s on %s from the %s, worst strain %.3g %%%s" % (pieces, sheets, source, 100.0 * st["max_strain"], where),
        )
        if st["glue_tabs_dropped"] > 0:
            self.report(
                {"WARNING"},
                "%s without a glue tab: none fitted on either side, not even at "
                "half the height" % checks.plural(st["glue_tabs_dropped"], "seam", "seams"),
            )
        if st["cut_lines_from_hull"] > 0:
            self.report(
                {"WARNING"},
                "The cut lines of %s follow the convex hull: the seam allowance is "
                "wider than asked in the hollows" % checks.plural(st["cut_lines_from_hull"], "piece", "pieces"),
            )
        return {"FINISHED"}


def scale_text(scale):
    if scale <= 0:
        return "-"
    return ("%g:1" % scale) if scale >= 1 else ("1:%g" % round(1.0 / scale, 6))


class VIEW3D_PT_developable_pattern(Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Developable"
    bl_parent_id = "VIEW3D_PT_developable"
    bl_label = "Flat Pattern"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.developable_pattern
        col = layout.column(align=True)
        col.prop(settings, "sheet")
        if settings.sheet == "CUSTOM":
            row = col.row(align=True)
            row.prop(settings, "sheet_width")
            row.prop(settings, "sheet_height")
        col.prop(settings, "margin")
        col.prop(settings, "unit")
        row = col.row(align=True)
        row.prop(settings, "auto_scale")
        sub = row.row(align=True)
        sub.enabled = not settings.auto_scale
        sub.prop(settings, "scale")
        col.prop(settings, "seam_tolerance")
        # One or the other: the set one greys the other out.
        row = col.row(align=True)
        row.enabled = settings.glue_tabs == 0.0
        row.prop(settings, "seam_allowance")
        row = col.row(align=True)
        row.enabled = settings.seam_allowance == 0.0
        row.prop(settings, "glue_tabs")
        col = layout.column(align=True)
        col.prop(settings, "export_svg")
        sub = col.row()
        sub.enabled = settings.export_svg
        sub.prop(settings, "filepath", text="")
        row = layout.row()
        row.scale_y = 1.3
        row.operator(MESH_OT_unfold_pattern.bl_idname, icon="UV")
        obj = context.active_object
        if obj is None or obj.type != "MESH" or not obj.developable_pattern.has_result:
            return
        rec = obj.developable_pattern
        box = layout.box()
        grid = box.grid_flow(columns=2, even_columns=True, align=True)
        for label, value in (
            ("Pieces", "%d" % rec.pieces),
            ("Sheets", "%d" % rec.sheets),
            ("Worst strain", "%.3g %%" % rec.worst_strain),
            ("Mean strain", "%.3g %%" % rec.mean_strain),
            ("Seams", "%d" % rec.seams),
            ("Scale", scale_text(rec.scale)),
        ):
            grid.label(text=label)
            grid.label(text=value)
        box.label(text="From the %s" % rec.source)
        if rec.splits:
            box.label(text="%d splits where a piece would overlap or stretch its seams" % rec.splits, icon="INFO")


classes = (DevelopablePatternSettings, DevelopablePatternRecord, MESH_OT_unfold_pattern, VIEW3D_PT_developable_pattern)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.developable_pattern = bpy.props.PointerProperty(type=DevelopablePatternSettings)
    bpy.types.Object.developable_pattern = bpy.props.PointerProperty(type=DevelopablePatternRecord)


def unregister():
    del bpy.types.Object.developable_pattern
    del bpy.types.Scene.developable_pattern
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)

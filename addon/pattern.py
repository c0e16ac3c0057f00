# SPDX-License-Identifier: GPL-3.0-or-later
"""Unfold Pattern: the flat pieces of the "Developable" shape key (or of the
base mesh when there is none) through dev_unfold, for every selected mesh.

Writes, all undoable in one step, nothing to the base mesh's coordinates:
  - the UV map "Developable Pattern": one island per piece, laid out like the
    sheets (sheet k right of sheet k-1, one sheet height = 1 UV unit);
  - edge seams (use_seam) where the pattern is cut: patch borders, the cuts
    that open bands and tubes, the splits (added to the user's own seams);
  - the face attribute "pattern_strain": the largest relative edge-length
    change of the face's triangles in the flat map;
  - the SVG sheets (when the export is on), one set per object, and the
    figures shown in the panel (object.developable_pattern).

Runs like Make Developable (modal.py): with a window on a worker thread with
the progress in the status bar, Esc cancelling. Nothing is written until
every object's unfolding is done (the SVG files go to a temporary folder and
are moved into place at the end), so a cancel leaves nothing behind, and a
failed object gets its error in its record, not the figures of an earlier
unfolding as if they were new. The sub-panel is drawn by panels.py."""

import os
import shutil
import tempfile

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy.types import Operator, PropertyGroup

from . import mesh_io, writeback
from .core import checks, native
from .core.jobs import Job
from .core.text import percent, plural
from .modal import ModalRun, Refused, cancelled_by_user, non_mesh_note, restore_mode

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
        name="Width (mm)", default=210.0, min=10.0, max=10000.0, description="Custom sheet width, mm"
    )
    sheet_height: FloatProperty(
        name="Height (mm)", default=297.0, min=10.0, max=10000.0, description="Custom sheet height, mm"
    )
    margin: FloatProperty(
        name="Margin (mm)", default=10.0, min=0.0, max=100.0, description="Free margin on every side of a sheet, mm"
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
        name="Seam Allowance (mm)",
        default=0.0,
        min=0.0,
        max=100.0,
        description="Cut every piece this far outside its outline on the sheet, "
        "mm, for sewing or gluing; the outline is drawn dashed as "
        "the seam line. 0 cuts on the outline",
    )
    glue_tabs: FloatProperty(
        name="Glue Tabs (mm)",
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
    error: StringProperty(name="Error", description="Why the last unfolding of this object failed (empty if none)")
    warning: StringProperty(name="Warning", description="What the last unfolding should make the user check")
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


class _Target:
    def __init__(self, name):
        self.name = name
        self.buffers = None
        self.source = ""
        self.svg = ""  # where the SVG goes in the end ("" for none)
        self.unwelded = 0
        self.modifiers = []
        self.pattern = None  # native.Pattern, once unfolded


def svg_paths(path, names):
    """Where each object's SVG goes: the path itself for one object, else one
    file per object named after it (pattern-Cube.svg)."""
    if not path:
        return {n: "" for n in names}
    if len(names) == 1:
        return {names[0]: path}
    stem = path[: -len(".svg")] if path.lower().endswith(".svg") else path
    safe = {n: "".join(c if c.isalnum() or c in "-_." else "_" for c in n) for n in names}
    return {n: "%s-%s.svg" % (stem, safe[n]) for n in names}


class MESH_OT_unfold_pattern(Operator, ModalRun):
    """Unfold the developable patches of the selected meshes into flat pieces: a UV map, seams, a \
strain attribute and SVG sheets at true scale"""

    bl_idname = "mesh.unfold_pattern"
    bl_label = "Unfold Pattern"
    bl_options = {"REGISTER", "UNDO"}
    status_label = "Unfold Pattern"

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

    def _begin(self, context, interactive):
        """Targets, paths; leaves Edit mode. Returns the targets or None (reported).
        interactive: no difference here (the pattern's settings are the scene's)."""
        lib, err = native.try_load()
        if lib is None:
            self.report({"ERROR"}, err)
            return None
        settings = context.scene.developable_pattern
        path = ""
        if settings.export_svg or self.filepath:
            raw = self.filepath or settings.filepath
            if raw.startswith("//") and not bpy.data.filepath:
                self.report({"ERROR"}, "Save the .blend file first or choose an absolute path for the SVG")
                return None
            path = os.path.abspath(bpy.path.abspath(raw))
            if not path.lower().endswith(".svg"):
                path += ".svg"
        active = context.active_object
        objs = [active] + [o for o in context.selected_objects if o.type == "MESH" and o != active]
        self._notes = []
        note = non_mesh_note(context)
        if note is not None:
            self._notes.append(note)
        seen, targets = set(), []
        for o in objs:
            if o.data.name in seen:
                self._notes.append(
                    ({"INFO"}, "%s shares its mesh with another selected object: unfolded once" % o.name)
                )
                continue
            seen.add(o.data.name)
            targets.append(_Target(o.name))
        for t, svg in zip(targets, svg_paths(path, [t.name for t in targets]).values()):
            t.svg = svg
        self._folder = tempfile.mkdtemp(prefix="developable-pattern-") if path else ""
        self._was_edit = active.mode == "EDIT"
        self._active_name = active.name
        self._select_errors = None
        if self._was_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        return targets

    def prepare(self, context, target):
        obj = bpy.data.objects.get(target.name)
        if obj is None or obj.type != "MESH":
            raise Refused("%s is gone; nothing was written" % target.name)
        mesh = obj.data
        buffers = mesh_io.read_mesh(mesh)
        if len(buffers.triangles) == 0:
            raise Refused("Cannot unfold %s: it has no faces" % obj.name)
        try:
            positions, target.source = source_positions(obj)
        except mesh_io.MeshInputError as exc:
            raise Refused("Cannot unfold %s: %s" % (obj.name, exc)) from None
        buffers.positions = positions
        target.buffers = buffers
        target.modifiers = mesh_io.shown_modifiers(obj)
        if np.isfinite(positions).all():
            on_boundary = checks.boundary_vertices(buffers.triangles, buffers.n_vertices)
            target.unwelded = len(checks.unwelded_vertices(positions, on_boundary))
        settings = context.scene.developable_pattern
        params = pattern_params(settings, context.scene)
        patches = triangle_patches(mesh, buffers)
        svg = os.path.join(self._folder, os.path.basename(target.svg)) if target.svg else None

        def work(progress):
            # A polygon's triangles stay in one piece: one UV island per piece.
            return native.unfold(
                positions,
                buffers.triangles,
                patches,
                params,
                svg_path=svg,
                face_groups=buffers.tri_polygon,
                progress=progress,
            )

        return Job(work, data=target)

    def finish_one(self, context, target, job):
        """Keeps the pattern until every object is done; returns (level, message)."""
        obj = bpy.data.objects.get(target.name)
        if job.error is None:
            target.pattern = job.result
            return {"INFO"}, ""
        exc = job.error
        if cancelled_by_user(job):
            return {"WARNING"}, "Cancelled: nothing was unfolded or written"
        text = "Cannot unfold %s: %s" % (target.name, exc)
        if isinstance(exc, native.EngineError) and obj is not None:
            buffers = target.buffers
            world = buffers.positions + np.array(obj.matrix_world, dtype=np.float64)[:3, 3]
            selection, text = checks.describe_problem(
                obj.name,
                "unfold %s" % obj.name,
                exc.status,
                exc.status_name,
                exc.message,
                world,
                buffers.triangles,
                buffers.tri_polygon,
            )
            if selection is not None and self._select_errors is None:
                self._select_errors = (obj.name, selection)
        if obj is not None:
            obj.developable_pattern.error = text
        return {"ERROR"}, text

    def _write(self, context, target, pattern):
        """One object's unfolding into its mesh, record and files; returns the report lines."""
        obj = bpy.data.objects[target.name]
        mesh = obj.data
        settings = context.scene.developable_pattern
        width, height = sheet_size(settings)
        write_uv_map(mesh, pattern, height, width)
        mark_seams(mesh, pattern)
        write_strain(mesh, pattern, target.buffers)
        mesh.update()
        files = []
        for temporary in pattern.files:
            final = os.path.join(os.path.dirname(target.svg), os.path.basename(temporary))
            os.makedirs(os.path.dirname(final), exist_ok=True)
            shutil.move(temporary, final)
            files.append(final)
        st = pattern.stats
        lines = []
        warnings = []
        if target.unwelded:
            warnings.append(
                "%s lie on another boundary vertex (seams never welded): its parts were unfolded apart; "
                "Merge by Distance (Developable panel) welds them" % plural(target.unwelded, "vertex", "vertices")
            )
        if target.modifiers:
            warnings.append(
                "unfolded without its modifiers (%s): apply them, or make the shape as shown developable "
                "first (Modifiers: As Shown)" % ", ".join(target.modifiers)
            )
        if st["glue_tabs_dropped"] > 0:
            warnings.append(
                "%s without a glue tab: none fitted on either side, not even at half the height"
                % plural(st["glue_tabs_dropped"], "seam", "seams")
            )
        if st["cut_lines_from_hull"] > 0:
            warnings.append(
                "the cut lines of %s follow the convex hull: the seam allowance is wider than asked in the "
                "hollows" % plural(st["cut_lines_from_hull"], "piece", "pieces")
            )
        rec = obj.developable_pattern
        rec.has_result = True
        rec.error = ""
        rec.warning = "; ".join(warnings)[:1000]
        rec.pieces = int(st["pieces"])
        rec.sheets = int(st["sheets"])
        rec.seams = int(st["seams"])
        rec.splits = int(st["splits"])
        rec.worst_strain = 100.0 * st["max_strain"]
        rec.mean_strain = 100.0 * st["mean_strain"]
        rec.scale = st["scale"]
        rec.files = "; ".join(files)
        rec.source = target.source
        where = ""
        if files:
            where = " to %s" % files[0] + (" and %d more" % (len(files) - 1) if len(files) > 1 else "")
        lines.append(
            (
                {"INFO"},
                "%s: %s on %s from the %s, worst strain %s%s"
                % (
                    obj.name,
                    plural(st["pieces"], "piece", "pieces"),
                    plural(st["sheets"], "sheet", "sheets"),
                    target.source,
                    percent(100.0 * st["max_strain"]),
                    where,
                ),
            )
        )
        lines += [({"WARNING"}, "%s: %s" % (obj.name, w)) for w in warnings]
        return lines

    def finish_all(self, context, results, cancelled):
        try:
            reports = list(self._notes)
            written = 0
            if not cancelled:
                for target, _, _ in results:
                    if target.pattern is not None:
                        reports += self._write(context, target, target.pattern)
                        written += 1
            reports += [(level, message) for _, level, message in results if message]
            for level, message in reports:
                self.report(level, message)
            return {"FINISHED"} if written else {"CANCELLED"}
        finally:
            if self._folder:
                shutil.rmtree(self._folder, ignore_errors=True)
            restore_mode(context, self._select_errors, self._was_edit, self._active_name)


classes = (DevelopablePatternSettings, DevelopablePatternRecord, MESH_OT_unfold_pattern)


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

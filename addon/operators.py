# SPDX-License-Identifier: GPL-3.0-or-later
"""MESH_OT_make_developable and MESH_OT_developable_weld.

One set of settings: every value the caller did not set comes from the scene
settings the sidebar shows (so Object > Make Developable and the Run button
run with the same values), and a run from Adjust Last Operation writes its
values back there.

What is deformed is what the user sees: the shape key mix (without the
add-on's own "Developable" key) in world space (the object's scale and
rotation applied), so the figures are those of the shape on screen. The result
goes into the "Developable" key, made so that the shown mix at value 1 is the
result. An object with modifiers shown in the viewport runs as the user chose
(settings 'modifiers'): the shape as shown into a new object, the shape as
shown with the modifiers applied, or the mesh beneath them. Every selected
mesh runs in turn (one progress, one undo step); a mesh shared by several
objects runs once, and the report says so.

The engine's judgement of the result is worded by core/verdict.py; the
operator only adds what it knows of the objects (modifiers, unwelded seams,
shared meshes). execute() runs synchronously (scripts, --background, the
redo panel), invoke() with a window modally (modal.py)."""

import bpy
import numpy as np
from bpy.types import Operator

from . import gauss_image, mesh_io, writeback
from .core import checks, native
from .core import verdict as verdicts
from .core.jobs import Job
from .core.text import library_message, plural
from .modal import ModalRun, Refused, cancelled_by_user, non_mesh_note, restore_mode
from .panels import draw_settings
from .properties import (
    AUTOMATIC,
    ENGINE_PARAMETERS,
    MODIFIER_WORDS,
    SETTINGS,
    all_property_definitions,
    apply_preset,
    copy_settings,
    engine_values,
    move_limit_words,
    set_quietly,
)

STATUS_NO_INTERIOR_VERTEX = 13


def error_text(exc, name):
    """An engine or library failure in one sentence naming the object."""
    if isinstance(exc, native.EngineError):
        if exc.status == native.STATUS_CANCELLED:
            return "Cancelled: %s was left unchanged" % name
        return "Cannot make %s developable (%s): %s" % (name, exc.status_name, exc.message)
    if isinstance(exc, native.LibraryError):
        print("Developable Mesh:", exc)
        return library_message(str(exc))
    return "Developable engine failed on %s: %r" % (name, exc)


class _Target:
    """What one run needs beyond the engine's buffers."""

    def __init__(self, name):
        self.name = name
        self.shared_with = []
        self.reference = None  # (n, 3) reference key / base coordinates, object space
        self.visible = None  # (n, 3) the shown mix, object space
        self.matrix = np.eye(3)  # linear part of matrix_world
        self.dropped = 0
        self.pinned_count = 0
        self.unwelded = np.zeros(0, dtype=np.int64)
        self.modifiers = []  # names of the modifiers shown in the viewport
        self.route = "BASE"  # MODIFIER_WORDS key: what is made developable
        self.pending = None  # name of the mesh as shown, before it is given an object


def _polygon_sets(mesh):
    start, total, loops = mesh_io.read_polygons(mesh)

    def vertex_set(p):
        return frozenset(loops[start[p] : start[p] + total[p]].tolist())

    return vertex_set


def _world(obj, positions):
    m = np.array(obj.matrix_world, dtype=np.float64)
    return positions @ m[:3, :3].T + m[:3, 3]


def _drop_pending(target):
    mesh = bpy.data.meshes.get(target.pending) if target.pending else None
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)
    target.pending = None


class MESH_OT_make_developable(Operator, ModalRun):
    """Deform the selected meshes towards developable surfaces (they can then be cut from a \
flat sheet). The result goes into the shape key "Developable"; the mesh itself is not changed"""

    bl_idname = "mesh.make_developable"
    bl_label = "Make Developable"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = all_property_definitions()
    status_label = "Make Developable"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            cls.poll_message_set("Select a mesh object (the active object is not a mesh)")
            return False
        if context.mode not in {"OBJECT", "EDIT_MESH"}:
            cls.poll_message_set(
                "Make Developable works in Object or Edit mode: leave %s mode "
                "first" % context.mode.replace("_", " ").title()
            )
            return False
        return True

    def draw(self, context):
        draw_settings(self.layout, self, context, in_redo=True)

    # -- one set of settings ---------------------------------------------------
    def _resolve_settings(self, context, write_back):
        settings = context.scene.developable
        props = self.properties
        repeat = self.options.is_repeat or self.options.is_repeat_last
        if not repeat:
            explicit = {n for n in SETTINGS if props.is_property_set(n)}
            copy_settings(settings, self, [n for n in SETTINGS if n not in explicit])
            if "preset" in explicit:  # a job named by a script sets what it did not set itself
                keep = {n: getattr(self, n) for n in explicit}
                apply_preset(self, self.preset)
                set_quietly(self, keep)
            implied = {}
            if "tolerance" in explicit and "limit_in_edges" not in explicit:
                implied["limit_in_edges"] = True
            for name in AUTOMATIC:
                if name in explicit and "auto_" + name not in explicit:
                    implied["auto_" + name] = False
            if (
                explicit - {"preset"}
                and "preset" not in explicit
                and explicit & set(ENGINE_PARAMETERS + ("move_limit", "limit_in_edges"))
            ):
                implied["preset"] = "CUSTOM"
            set_quietly(self, implied)
        if write_back or repeat:
            copy_settings(self, settings)

    # -- preparing ----------------------------------------------------------
    def _targets(self, context):
        """The objects to run, the active one first; a mesh shared by several
        objects once (the others listed in shared_with)."""
        active = context.active_object
        if context.mode == "EDIT_MESH":
            objs = list(getattr(context, "objects_in_mode", None) or [active])
        else:
            objs = [o for o in context.selected_objects if o.type == "MESH"]
            note = non_mesh_note(context)
            if note is not None:
                self._notes.append(note)
        if active is not None and active.type == "MESH":
            objs = [active] + [o for o in objs if o != active]
        targets, by_mesh = [], {}
        for o in objs:
            if o.data.name in by_mesh:
                continue
            t = _Target(o.name)
            t.shared_with = sorted(u.name for u in bpy.data.objects if u.data == o.data and u != o)
            by_mesh[o.data.name] = t
            targets.append(t)
        return targets

    def _begin(self, context, interactive):
        """Library, settings, targets; leaves Edit mode. Returns the targets or None.
        interactive: the settings are written back to the scene (see _resolve_settings)."""
        lib, err = native.try_load()
        if lib is None:
            self.report({"ERROR"}, error_text(native.LibraryError(err), ""))
            return None
        self._notes = []
        self._resolve_settings(context, interactive)
        targets = self._targets(context)
        self._active_name = context.active_object.name
        self._was_edit = context.mode == "EDIT_MESH"
        self._select_errors = None
        if self._was_edit:
            bpy.ops.object.mode_set(mode="OBJECT")  # flush the edit mesh; restored at the end
        return targets

    def _shape(self, obj, target):
        """(mesh to read, reference, visible) of what is made developable."""
        target.modifiers = mesh_io.shown_modifiers(obj)
        target.route = self.modifiers if target.modifiers else "BASE"
        if target.route == "BASE":
            try:
                reference, visible = mesh_io.read_visible_positions(obj, exclude=(writeback.SHAPE_KEY,))
            except mesh_io.MeshInputError as exc:
                raise Refused("Cannot make %s developable: %s" % (obj.name, exc)) from None
            return obj.data, reference, visible
        mesh = mesh_io.mesh_as_shown(obj, obj.data.name + " developable")
        target.pending = mesh.name
        positions = mesh_io.read_positions(mesh)
        return mesh, positions, positions

    def prepare(self, context, target):
        """Reads one object; returns a Job (raises Refused)."""
        obj = bpy.data.objects.get(target.name)
        if obj is None or obj.type != "MESH":
            raise Refused("%s is gone; nothing was written" % target.name)
        matrix = mesh_io.linear_part(obj)
        det = float(np.linalg.det(matrix))
        if not np.isfinite(det) or abs(det) < 1e-30:
            raise Refused(
                "Cannot make %s developable: its scale is zero along an axis; set a "
                "non-zero scale (Object > Transform)" % obj.name
            )
        mesh, reference, visible = self._shape(obj, target)
        buffers = mesh_io.read_mesh(mesh)
        buffers.positions = visible @ matrix.T  # world space: the shape as shown
        if len(buffers.triangles):
            tris, tri_poly, dropped = checks.drop_shared_triangles(
                buffers.triangles, buffers.tri_polygon, _polygon_sets(mesh)
            )
            buffers.triangles, buffers.tri_polygon = tris.astype(np.int32), tri_poly.astype(np.int32)
            target.dropped = dropped
        pinned = np.zeros(buffers.n_vertices, dtype=bool)
        if self._was_edit and self.pin_selection and target.route == "BASE":
            pinned |= mesh_io.read_selection(mesh)
        if self.pin_group:
            if self.pin_group not in obj.vertex_groups:
                _drop_pending(target)
                raise Refused("Pin group '%s' is not a vertex group of %s" % (self.pin_group, obj.name))
            pinned |= mesh_io.read_vertex_group(obj, self.pin_group, mesh) > 0.0
        target.pinned_count = int(pinned.sum())
        target.reference, target.visible, target.matrix = reference, visible, matrix
        if np.isfinite(buffers.positions).all():
            on_boundary = checks.boundary_vertices(buffers.triangles, buffers.n_vertices)
            target.unwelded = checks.unwelded_vertices(buffers.positions, on_boundary)
        positions, triangles, params = buffers.positions, buffers.triangles, engine_values(self)
        pins = pinned if pinned.any() else None

        def work(progress):
            return native.run(positions, triangles, pins, params, progress)

        return Job(work, data=buffers)

    # -- finishing ----------------------------------------------------------
    def _figures(self, target, buffers):
        return {
            "size": checks.diagonal(buffers.positions),
            "move_percent": 0.0,
            "pinned": target.pinned_count,
            "unwelded": len(target.unwelded),
            "world_space": not np.allclose(np.linalg.svd(target.matrix, compute_uv=False), 1.0, rtol=1e-6),
            "job": self.preset,
            "shape_source": MODIFIER_WORDS[target.route] if target.modifiers else "",
        }

    def _failed(self, context, target, job, obj):
        """(level, message) of a run that returned no result."""
        exc, buffers = job.error, job.data
        name = obj.name if obj is not None else target.name
        _drop_pending(target)
        if cancelled_by_user(job):
            return {"WARNING"}, error_text(exc, name)
        if isinstance(exc, native.EngineError) and exc.status == STATUS_NO_INTERIOR_VERTEX and obj is not None:
            if len(target.unwelded):
                text = (
                    "Cannot make %s developable (%s): its faces are not joined (%s lie on another vertex, "
                    "a polygon soup). Weld them first: Merge by Distance in the Developable panel, or "
                    "Mesh > Clean Up > Merge by Distance"
                    % (name, exc.status_name, plural(len(target.unwelded), "vertex", "vertices"))
                )
                obj.developable.error = text
                return {"ERROR"}, text
            normals = checks.face_normals(buffers.positions, buffers.triangles)
            flat = bool(len(normals)) and np.abs(normals @ normals[0]).min() > np.cos(1e-3)
            text = "%s: nothing to do, it is already developable: %s" % (
                name,
                "it is flat"
                if flat
                else "every vertex is on its border, so it unfolds without stretching as it stands",
            )
            writeback.store_nothing_to_do(obj, text + ".", self._figures(target, buffers))
            return {"INFO"}, text + "."
        if isinstance(exc, native.EngineError) and exc.status in checks.MESH_PROBLEMS and obj is not None:
            mesh_positions = buffers.positions @ np.linalg.inv(target.matrix).T
            selection, text = checks.describe_problem(
                name,
                "make %s developable" % name,
                exc.status,
                exc.status_name,
                exc.message,
                _world(obj, mesh_positions),
                buffers.triangles,
                buffers.tri_polygon,
            )
            if target.route != "BASE":
                text = text.replace(" Selected in Edit mode", "") + " (in the shape as shown, with its modifiers)"
            elif selection is not None and self._select_errors is None:
                self._select_errors = (obj.name, selection)
            obj.developable.error = text
            return {"ERROR"}, text
        text = error_text(exc, name)
        if obj is not None:
            obj.developable.error = text
        return {"ERROR"}, text

    def _place(self, context, target, obj):
        """The object the result goes to: for the shape as shown, a new object
        beside this one, or this one with its modifiers applied."""
        mesh = bpy.data.meshes.get(target.pending)
        target.pending = None
        if target.route == "APPLY":
            obj.data = mesh
            obj.modifiers.clear()
            return obj
        new = bpy.data.objects.new(obj.name + " developable", mesh)
        for collection in obj.users_collection:
            collection.objects.link(new)
        new.matrix_world = obj.matrix_world
        for group in obj.vertex_groups:
            if group.name not in new.vertex_groups:
                new.vertex_groups.new(name=group.name)
        obj.select_set(False)
        obj.hide_set(True)
        new.select_set(True)
        if context.view_layer.objects.active in (obj, None) or self._active_name == obj.name:
            context.view_layer.objects.active = new
            self._active_name = new.name
        return new

    def finish_one(self, context, target, job):
        """Writes one result; returns (level, message)."""
        obj = bpy.data.objects.get(target.name)
        if job.error is not None:
            return self._failed(context, target, job, obj)
        buffers, result = job.data, job.result
        if (
            obj is None
            or obj.type != "MESH"
            or (target.route == "BASE" and len(obj.data.vertices) != buffers.n_vertices)
        ):
            _drop_pending(target)
            return {"ERROR"}, "%s changed during the run; nothing was written" % target.name
        original = obj.name
        s = result.stats
        closed = bool(result.interior[np.unique(buffers.triangles)].all()) if len(buffers.triangles) else False
        flat_faces = 0
        if s["result"] == native.RESULT_UNCHANGED and verdicts.nothing_to_do(s["unchanged_reason"], 1.0) is None:
            flat_faces = checks.flat_faced(buffers.positions, buffers.triangles, s["flat_threshold"])
        facts = verdicts.Facts(
            closed=closed,
            sheet=checks.sheet_like(buffers.triangles),
            job=self.preset,
            segmentation=self.segmentation,
            keep_boundary=self.pin_boundary,
            move_limit=move_limit_words(self),
            flat_faces=flat_faces,
            size=checks.diagonal(buffers.positions),
            polish=self.polish,
        )
        v = verdicts.verdict(obj.name, s, facts)
        notes, level = [], {v.level}
        # The engine ran a one-sided or inconsistently wound mesh on faces turned to agree; its result
        # says what it turned, and the user is told (the faces themselves are left as they are).
        turned = s["orientation_note"]
        if turned:
            notes.append(turned[0].upper() + turned[1:] + ".")
        if target.dropped:
            notes.append(
                "(%s lying on another face ignored, as Blender's Validate does)"
                % plural(target.dropped, "triangle", "triangles")
            )
        if target.shared_with:
            notes.append("Its mesh is shared with %s, which changed too." % ", ".join(target.shared_with))
        if target.route == "APPLY":
            notes.append("Its modifiers (%s) were applied first." % ", ".join(target.modifiers))
        elif target.route == "BASE" and target.modifiers:
            level = {"WARNING"}
            notes.append(
                "The mesh beneath its modifiers (%s) was made developable, not the shape shown; the modifiers stay "
                "on top of the result, and its shape keys now stop Blender from applying them: to keep their "
                "shape, choose Modifiers: As Shown and run again." % ", ".join(target.modifiers)
            )
        if len(target.unwelded):
            level = {"WARNING"} if level == {"INFO"} else level
            notes.append(
                "%s lie on another boundary vertex: seams never welded, whose sides were made developable "
                "apart and may open. Merge by Distance (Developable panel) welds them."
                % plural(len(target.unwelded), "vertex", "vertices")
            )
        if target.route != "BASE":
            obj = self._place(context, target, obj)
            if target.route == "NEW_OBJECT":
                notes.append(
                    "Made from the shape as shown (%s) as the new object %s; %s is hidden (Alt+H shows it)."
                    % (", ".join(target.modifiers), obj.name, original)
                )
        v.text = " ".join([v.text] + notes)
        local = result.positions @ np.linalg.inv(target.matrix).T
        key = local - target.visible + target.reference
        scale = writeback.write_result(obj, key, buffers.tri_polygon, buffers.n_polygons, result, v.key_value)
        figures = self._figures(target, buffers)
        figures["move_percent"] = 100.0 * s["max_vertex_move"] / figures["size"] if figures["size"] > 0 else 0.0
        for name in [obj.name] + target.shared_with:
            other = bpy.data.objects.get(name)
            if other is not None:
                writeback.store_record(other, result, figures, v, scale)
        if self.gauss_image:
            gauss_image.build(obj, buffers.positions, result.positions, buffers.triangles, result.curves)
        return level, v.report()

    def finish_all(self, context, results, cancelled):
        try:
            for level, message in self._notes + [(level, message) for _, level, message in results]:
                self.report(level, message)
            if any(
                level == {"INFO"} or (level == {"WARNING"} and not m.startswith("Cancelled")) for _, level, m in results
            ):
                writeback.use_attribute_shading(context)
                return {"FINISHED"}
            return {"CANCELLED"}
        finally:
            restore_mode(context, self._select_errors, self._was_edit, self._active_name)


class MESH_OT_developable_weld(Operator):
    """Weld the seams that were never welded: merge every boundary vertex with the boundary \
vertices lying on it (within a millionth of the object's size), as Merge by Distance does"""

    bl_idname = "mesh.developable_weld"
    bl_label = "Merge by Distance"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and context.mode == "OBJECT"

    def execute(self, context):
        import bmesh

        obj = context.active_object
        mesh = obj.data
        positions = mesh_io.read_positions(mesh)
        unwelded = checks.unwelded_vertices(positions, mesh_io.boundary_mask(mesh))
        if len(unwelded) == 0:
            self.report({"INFO"}, "%s has no unwelded seam" % obj.name)
            return {"CANCELLED"}
        before = len(mesh.vertices)
        bm = bmesh.new()
        bm.from_mesh(mesh)
        bm.verts.ensure_lookup_table()
        distance = 2.0 * checks.WELD_DISTANCE * checks.diagonal(positions)
        bmesh.ops.remove_doubles(bm, verts=[bm.verts[int(i)] for i in unwelded], dist=distance)
        bm.to_mesh(mesh)
        bm.free()
        mesh.update()
        self.report({"INFO"}, "%s: %s merged" % (obj.name, plural(before - len(mesh.vertices), "vertex", "vertices")))
        return {"FINISHED"}


classes = (MESH_OT_make_developable, MESH_OT_developable_weld)


def menu_func(self, context):
    self.layout.operator(MESH_OT_make_developable.bl_idname, icon="MOD_SMOOTH")


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_object.append(menu_func)
    bpy.types.VIEW3D_MT_edit_mesh.append(menu_func)


def unregister():
    bpy.types.VIEW3D_MT_edit_mesh.remove(menu_func)
    bpy.types.VIEW3D_MT_object.remove(menu_func)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)

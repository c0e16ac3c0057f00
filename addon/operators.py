# SPDX-License-Identifier: GPL-3.0-or-later
"""MESH_OT_make_developable.

One set of settings: every value the caller did not set comes from the scene
settings the sidebar shows (so Object > Make Developable and the Run button
run with the same values), and a run from Adjust Last Operation writes its
values back there.

What is deformed is what the user sees: the shape key mix (without the
add-on's own "Developable" key) in world space (the object's scale and
rotation applied), so the figures are those of the shape on screen. The result
goes into the "Developable" key, made so that the shown mix at value 1 is the
result. Every selected mesh runs in turn (one progress, one undo step); a mesh
shared by several objects runs once, and the report says so.

execute(): synchronous (scripts, --background, the redo panel; with a
window the cursor shows the progress). invoke() with a window: the engine
runs on a worker thread (ctypes releases the GIL during dev_run) while
modal() shows the progress; Esc cancels and nothing more is written."""

import re
import threading
import time

import bpy
import numpy as np
from bpy.types import Operator

from . import checks, gauss_image, mesh_io, native, writeback
from .properties import (
    AUTOMATIC,
    ENGINE_PARAMETERS,
    PIN_PARAMETERS,
    SETTINGS,
    all_property_definitions,
    apply_preset,
    copy_settings,
    engine_values,
    set_quietly,
)


class Job:
    """One engine run on captured buffers; usable synchronously or on a thread."""

    def __init__(self, buffers, pinned, params):
        self.buffers = buffers
        self.pinned = pinned
        self.params = params
        self.fraction = 0.0
        self.stage = "starting"
        self.result = None
        self.error = None  # native.EngineError / LibraryError / other Exception
        self.done = False
        self.on_progress = None  # callable(fraction) on the calling thread (execute only)
        self._cancel = threading.Event()
        self._thread = None
        self.started = time.perf_counter()

    def cancel(self):
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def _progress(self, fraction, stage):
        self.fraction = fraction
        self.stage = stage
        if self.on_progress is not None:
            self.on_progress(fraction)
        return not self._cancel.is_set()

    def run(self):
        try:
            self.result = native.run(
                self.buffers.positions, self.buffers.triangles, self.pinned, self.params, self._progress
            )
        except Exception as exc:  # reported by the operator, never raised into Blender
            self.error = exc
        finally:
            self.done = True

    def start(self):
        self._thread = threading.Thread(target=self.run, name="developable-engine", daemon=True)
        self._thread.start()

    def join(self, timeout=None):
        if self._thread is not None:
            self._thread.join(timeout)


_NAVIGATION = {
    "MIDDLEMOUSE",
    "WHEELUPMOUSE",
    "WHEELDOWNMOUSE",
    "TRACKPADPAN",
    "TRACKPADZOOM",
    "MOUSEMOVE",
    "INBETWEEN_MOUSEMOVE",
    "NDOF_MOTION",
}

_MESH_PROBLEMS = {4, 5, 6}  # DEGENERATE_TRIANGLE, DUPLICATE_TRIANGLE, NON_MANIFOLD


def library_message(err):
    """The missing/mismatched library in one short sentence (the full text,
    with the paths looked at, goes to the console)."""
    abi = re.search(r"ABI version (\d+) but this add-on needs (\d+)", err)
    if abi:
        return (
            "The engine library has ABI version %s but this add-on needs %s: install the "
            "add-on and its library from the same zip" % abi.groups()
        )
    if "not found" in err:
        return (
            "Engine library not found: reinstall the add-on from its zip, or point "
            "DEVELOPABLE_LIBRARY at libdevelopable.so (details in the console)"
        )
    return "The engine library could not be loaded: reinstall the add-on (details in the console)"


def _error_text(exc):
    if isinstance(exc, native.EngineError):
        if exc.status == native.STATUS_CANCELLED:
            return "Cancelled: the mesh was left unchanged"
        return "Cannot make the mesh developable (%s): %s" % (exc.status_name, exc.message)
    if isinstance(exc, native.LibraryError):
        print("Developable Mesh:", exc)
        return library_message(str(exc))
    return "Developable engine failed: %r" % (exc,)


class _Refused(Exception):
    """The object cannot run; the message is the report."""


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


def _polygon_sets(mesh):
    start, total, loops = mesh_io.read_polygons(mesh)

    def vertex_set(p):
        return frozenset(loops[start[p] : start[p] + total[p]].tolist())

    return vertex_set


def _where(obj, vertices):
    """World position (x, y, z) of the mean of the given vertices, as text."""
    idx = np.asarray(vertices, dtype=np.int64).reshape(-1)
    if idx.size == 0:
        return ""
    co = mesh_io.read_positions(obj.data)[idx].mean(axis=0)
    m = np.array(obj.matrix_world, dtype=np.float64)
    w = m[:3, :3] @ co + m[:3, 3]
    return "near (%.3g, %.3g, %.3g)" % tuple(w)


def describe_mesh_problem(obj, buffers, exc):
    """For a mesh the engine refused: (what to select as (vertices, edges,
    polygons), a message in the user's terms naming Blender's own elements)."""
    positions, tris, tri_poly = buffers.positions, buffers.triangles, buffers.tri_polygon
    status = exc.status_name
    head = "Cannot make %s developable (%s): " % (obj.name, status)
    tail = " Selected in Edit mode"
    if exc.status == 6:
        many, flipped = checks.bad_edges(tris)
        if len(many):
            return (many.reshape(-1), many, ()), head + (
                "%s shared by more than two faces (a non-manifold edge), %s.%s; "
                "Select > Select All by Trait > Non Manifold shows them all."
                % (checks.plural(len(many), "edge is", "edges are"), _where(obj, many[0]), tail)
            )
        if len(flipped):
            return (flipped.reshape(-1), flipped, ()), head + (
                "%s between faces of opposite direction (inconsistent orientation), %s.%s; "
                "Mesh > Normals > Recalculate Outside fixes it."
                % (checks.plural(len(flipped), "edge lies", "edges lie"), _where(obj, flipped[0]), tail)
            )
        vertex = re.search(r"vertex (\d+) is non-manifold", exc.message)
        if vertex:
            v = int(vertex.group(1))
            return ([v], (), ()), head + (
                "vertex %d is non-manifold: the surface touches itself there, %s.%s; "
                "Vertex > Rip or Separate fixes it." % (v, _where(obj, [v]), tail)
            )
    if exc.status == 4:
        bad = np.unique(tri_poly[checks.degenerate_triangles(positions, tris)])
        if len(bad):
            return ((), (), bad), head + (
                "%s zero area (e.g. face %d), %s.%s; Mesh > Clean Up > Degenerate Dissolve "
                "removes them."
                % (
                    checks.plural(len(bad), "face has", "faces have"),
                    bad[0],
                    _where(obj, tris[tri_poly == bad[0]].reshape(-1)),
                    tail,
                )
            )
    if exc.status == 5:
        pairs = checks.duplicate_polygons(tris, tri_poly)
        if pairs:
            later, earlier = pairs[0]
            faces = sorted({p for pair in pairs for p in pair})
            return ((), (), faces), head + (
                "face %d repeats the vertices of face %d (%s), %s.%s; delete one of them."
                % (
                    later,
                    earlier,
                    checks.plural(len(pairs), "pair", "pairs"),
                    _where(obj, tris[tri_poly == later].reshape(-1)),
                    tail,
                )
            )
    return None, head + exc.message


class MESH_OT_make_developable(Operator):
    """Deform the selected meshes towards developable surfaces (they can then be cut from a \
flat sheet). The result goes into the shape key "Developable"; the mesh itself is not changed"""

    bl_idname = "mesh.make_developable"
    bl_label = "Make Developable"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = all_property_definitions()

    _job = None
    _timer = None

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
        from .panels import draw_settings

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
        """Names of the objects to run, the active one first; a mesh shared by
        several objects once (the others listed in shared_with)."""
        active = context.active_object
        if context.mode == "EDIT_MESH":
            objs = list(getattr(context, "objects_in_mode", None) or [active])
        else:
            objs = [o for o in context.selected_objects if o.type == "MESH"]
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

    def _begin(self, context, write_back):
        """Library, settings, targets; leaves Edit mode. Returns the targets or None."""
        lib, err = native.try_load()
        if lib is None:
            self.report({"ERROR"}, _error_text(native.LibraryError(err)))
            return None
        self._resolve_settings(context, write_back)
        self._targets_list = self._targets(context)
        self._active_name = context.active_object.name
        self._was_edit = context.mode == "EDIT_MESH"
        self._select_errors = None
        self._reports = []
        if self._was_edit:
            self._edit_selection = {}
            bpy.ops.object.mode_set(mode="OBJECT")  # flush the edit mesh; restored at the end
        return self._targets_list

    def _prepare(self, context, target):
        """Reads one object; returns a Job (raises _Refused)."""
        obj = bpy.data.objects.get(target.name)
        if obj is None or obj.type != "MESH":
            raise _Refused("%s is gone; nothing was written" % target.name)
        mesh = obj.data
        try:
            reference, visible = mesh_io.read_visible_positions(obj, exclude=(writeback.SHAPE_KEY,))
        except mesh_io.MeshInputError as exc:
            raise _Refused("Cannot make %s developable: %s" % (obj.name, exc)) from None
        matrix = mesh_io.linear_part(obj)
        det = float(np.linalg.det(matrix))
        if not np.isfinite(det) or abs(det) < 1e-30:
            raise _Refused(
                "Cannot make %s developable: its scale is zero along an axis; set a "
                "non-zero scale (Object > Transform)" % obj.name
            )
        buffers = mesh_io.read_mesh(mesh)
        buffers.positions = visible @ matrix.T  # world space: the shape as shown
        if len(buffers.triangles):
            tris, tri_poly, dropped = checks.drop_shared_triangles(
                buffers.triangles, buffers.tri_polygon, _polygon_sets(mesh)
            )
            buffers.triangles, buffers.tri_polygon = tris.astype(np.int32), tri_poly.astype(np.int32)
            target.dropped = dropped
        pinned = np.zeros(buffers.n_vertices, dtype=bool)
        if self._was_edit and self.pin_selection:
            pinned |= mesh_io.read_selection(mesh)
        if self.pin_group:
            if self.pin_group not in obj.vertex_groups:
                raise _Refused("Pin group '%s' is not a vertex group of %s" % (self.pin_group, obj.name))
            pinned |= mesh_io.read_vertex_group(obj, self.pin_group) > 0.0
        target.pinned_count = int(pinned.sum())
        target.reference, target.visible, target.matrix = reference, visible, matrix
        size = checks.diagonal(buffers.positions)
        edge = (
            checks.average_edge_length(buffers.positions, buffers.triangles)
            if np.isfinite(buffers.positions).all()
            else 0.0
        )
        params = engine_values(self, size=size, average_edge=edge)
        return Job(buffers, pinned if pinned.any() else None, params)

    def _restore_mode(self, context):
        sel = self._select_errors
        if sel is not None:  # show the bad elements of a refused mesh
            obj = bpy.data.objects.get(sel[0])
            if obj is not None:
                context.view_layer.objects.active = obj
                obj.select_set(True)
                vertices, edges, polygons = sel[1]
                context.tool_settings.mesh_select_mode = (
                    len(polygons) == 0 and len(edges) == 0,
                    len(edges) > 0,
                    len(polygons) > 0,
                )
                mesh_io.select_in_edit_mode(obj, vertices, edges, polygons)
            return
        if getattr(self, "_was_edit", False):
            obj = bpy.data.objects.get(self._active_name)
            if obj is not None and context.view_layer.objects.active == obj:
                bpy.ops.object.mode_set(mode="EDIT")

    # -- finishing ----------------------------------------------------------
    def _finish_one(self, context, target, job):
        """Writes one result; returns (level, message)."""
        obj = bpy.data.objects.get(target.name)
        if job.error is not None:
            exc = job.error
            if isinstance(exc, native.EngineError) and exc.status == native.STATUS_CANCELLED:
                return {"WARNING"}, _error_text(exc)
            if isinstance(exc, native.EngineError) and exc.status in _MESH_PROBLEMS and obj:
                selection, text = describe_mesh_problem(obj, job.buffers, exc)
                if selection is not None and self._select_errors is None:
                    self._select_errors = (obj.name, selection)
                return {"ERROR"}, text
            text = _error_text(exc)
            if isinstance(exc, native.EngineError) and obj is not None:
                text = text.replace("the mesh", obj.name, 1)
                if exc.status == 13 and "Merge by Distance" not in text:
                    # the shown shape (a key mix) parted vertices that the mesh itself
                    # has in one place: the engine cannot see that the mesh is a soup
                    same = len(target.reference) - len(np.unique(target.reference, axis=0))
                    if same:
                        text += (
                            "; %d vertices of the mesh share a position with another "
                            "(a polygon soup?): weld them first (Merge by Distance)" % same
                        )
            return {"ERROR"}, text
        if obj is None or obj.type != "MESH" or len(obj.data.vertices) != job.buffers.n_vertices:
            return {"ERROR"}, "%s changed during the run; nothing was written" % target.name
        result = job.result
        s = dict(result.stats)
        if isinstance(s.get("result_message"), bytes):
            s["result_message"] = s["result_message"].decode("utf-8", "replace")
        fig = checks.figures(
            job.buffers.positions,
            result.positions,
            job.buffers.triangles,
            result.interior,
            result.defect_before,
            result.defect_after,
        )
        # the engine's own result check, when the library has it, as it is
        for ours, theirs in (
            ("flat_before", "flat_share_before"),
            ("flat_after", "flat_share_after"),
            ("faces_turned", "faces_turned_over"),
        ):
            if theirs in s:
                fig[ours] = s[theirs]
        engine_result = ""
        if "result" in s:
            engine_result = native.RESULT_NAMES.get(s["result"], str(s["result"]))
            if s.get("result_message"):
                engine_result += ": " + s["result_message"]
        level, verdict, message = checks.verdict(obj.name, s, fig)
        level = {level}
        if target.dropped:
            message += " (%s lying on another face ignored, as Blender's Validate does)" % checks.plural(
                target.dropped, "triangle", "triangles"
            )
        if target.shared_with:
            message += " Its mesh is shared with %s, which changed too." % ", ".join(target.shared_with)
        local = result.positions @ np.linalg.inv(target.matrix).T
        key = local - target.visible + target.reference
        value = 0.0 if verdict == "WORSE" else 1.0
        scale = writeback.write_result(obj, key, job.buffers.tri_polygon, job.buffers.n_polygons, result, value)
        # scaled (not just rotated): the figures are world-space, unlike the mesh's own
        world = not np.allclose(np.linalg.svd(target.matrix, compute_uv=False), 1.0, rtol=1e-6)
        for name in [target.name] + target.shared_with:
            other = bpy.data.objects.get(name)
            if other is not None:
                writeback.store_stats(
                    other, result, scale, target.pinned_count, fig, verdict, message, engine_result, world
                )
        if self.gauss_image:
            gauss_image.build(obj, job.buffers.positions, result.positions, job.buffers.triangles, result.curves)
        return level, message

    def _report_all(self, results):
        """One report per object; the worst level decides the return value."""
        for level, message in results:
            self.report(level, message)

    def _finish(self, context, results):
        try:
            self._report_all(results)
            if any(level == {"INFO"} or (level == {"WARNING"} and "Cancelled" not in m) for level, m in results):
                writeback.use_attribute_shading(context)
                return {"FINISHED"}
            return {"CANCELLED"}
        finally:
            self._restore_mode(context)

    # -- entry points ---------------------------------------------------------
    def execute(self, context):
        targets = self._begin(context, write_back=False)
        if targets is None:
            return {"CANCELLED"}
        wm = context.window_manager
        show = context.window is not None and not bpy.app.background
        if show:
            wm.progress_begin(0, 100)
        results = []
        try:
            for i, target in enumerate(targets):
                try:
                    job = self._prepare(context, target)
                except _Refused as exc:
                    results.append(({"ERROR"}, str(exc)))
                    continue
                if show:
                    job.on_progress = lambda f, i=i: wm.progress_update(
                        int(100 * (i + min(max(f, 0.0), 1.0)) / len(targets))
                    )
                job.run()
                results.append(self._finish_one(context, target, job))
                if job.cancelled:
                    break
        finally:
            if show:
                wm.progress_end()
        return self._finish(context, results)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        targets = self._begin(context, write_back=True)
        if targets is None:
            return {"CANCELLED"}
        self._queue = list(targets)
        self._count = len(targets)
        self._results = []
        if not self._next_job(context):
            return self._finish(context, self._results)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        self._status(context)
        return {"RUNNING_MODAL"}

    def _next_job(self, context):
        """Starts the next object's run; False when none is left."""
        while self._queue:
            target = self._queue.pop(0)
            try:
                job = self._prepare(context, target)
            except _Refused as exc:
                self._results.append(({"ERROR"}, str(exc)))
                continue
            self._job, self._target = job, target
            job.start()
            return True
        self._job = None
        return False

    def _status(self, context):
        job = self._job
        done = self._count - len(self._queue) - 1
        fraction = (done + min(max(job.fraction, 0.0), 1.0)) / self._count
        which = " %s (%d of %d)" % (self._target.name, done + 1, self._count) if self._count > 1 else ""
        text = "Make Developable%s: %s %3.0f %%  (%.1f s)  Esc to cancel" % (
            which,
            job.stage or "",
            100.0 * job.fraction,
            time.perf_counter() - job.started,
        )
        if job.cancelled:
            text = "Make Developable: cancelling..."
        if context.workspace is not None:
            context.workspace.status_text_set(text)
        context.window_manager.progress_update(int(100 * fraction))

    def _end_modal(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
        if job.done:
            job.join()
            self._results.append(self._finish_one(context, self._target, job))
            if not job.cancelled and self._next_job(context):
                return {"RUNNING_MODAL"}
            self._end_modal(context)
            result = self._finish(context, self._results)
            self._job = None
            for area in context.screen.areas if context.screen else ():
                area.tag_redraw()
            return result
        if event.type == "TIMER":
            self._status(context)
        if event.type in _NAVIGATION:
            return {"PASS_THROUGH"}  # the view may be orbited/zoomed meanwhile
        # Block other input (edits) while the engine works on the captured mesh.
        return {"RUNNING_MODAL"}


classes = (MESH_OT_make_developable,)


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


__all__ = ["MESH_OT_make_developable", "Job", "ENGINE_PARAMETERS", "PIN_PARAMETERS"]

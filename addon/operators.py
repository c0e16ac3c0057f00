# SPDX-License-Identifier: GPL-3.0-or-later
"""MESH_OT_make_developable.

execute(): synchronous (scripts, --background, the redo panel).
invoke() with a window: the engine runs on a worker thread (ctypes releases
the GIL during dev_run) while modal() shows the progress; Esc makes the
progress callback return 0, the engine returns DEV_STATUS_CANCELLED and
nothing is written. Results are written only after the engine returned OK."""

import threading
import time

import bpy
import numpy as np
from bpy.types import Operator

from . import gauss_image, mesh_io, native, writeback
from .properties import (ENGINE_PARAMETERS, PIN_PARAMETERS, engine_property_definitions,
                         engine_values, pin_property_definitions)


class Job:
    """One engine run on captured buffers; usable synchronously or on a thread."""

    def __init__(self, buffers, pinned, params):
        self.buffers = buffers
        self.pinned = pinned
        self.params = params
        self.fraction = 0.0
        self.stage = "starting"
        self.result = None
        self.error = None          # native.EngineError / LibraryError / other Exception
        self.done = False
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
        return not self._cancel.is_set()

    def run(self):
        try:
            self.result = native.run(self.buffers.positions, self.buffers.triangles,
                                     self.pinned, self.params, self._progress)
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


_NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'TRACKPADPAN', 'TRACKPADZOOM',
               'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE', 'NDOF_MOTION'}


def _error_text(exc):
    if isinstance(exc, native.EngineError):
        if exc.status == native.STATUS_CANCELLED:
            return "Cancelled: the mesh was left unchanged"
        return "Cannot make the mesh developable (%s): %s" % (exc.status_name, exc.message)
    if isinstance(exc, native.LibraryError):
        return str(exc)
    return "Developable engine failed: %r" % (exc,)


class MESH_OT_make_developable(Operator):
    """Deform the active mesh towards a developable surface (normal-guided deformation). \
The result goes into the shape key "Developable"; the base mesh is not changed"""
    bl_idname = "mesh.make_developable"
    bl_label = "Make Developable"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = dict(engine_property_definitions(), **pin_property_definitions())

    _job = None
    _timer = None

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH' and context.mode in {'OBJECT', 'EDIT_MESH'}

    def draw(self, context):
        from .panels import draw_parameters
        draw_parameters(self.layout, self, context.active_object)

    # -- preparing ----------------------------------------------------------
    def _prepare(self, context):
        """Reads everything from the object; returns a Job or None (reported)."""
        lib, err = native.try_load()
        if lib is None:
            self.report({'ERROR'}, err)
            return None
        obj = context.active_object
        self._obj_name = obj.name
        self._was_edit = obj.mode == 'EDIT'
        if self._was_edit:
            bpy.ops.object.mode_set(mode='OBJECT')  # flush the edit mesh; restored at the end
        mesh = obj.data
        buffers = mesh_io.read_mesh(mesh)
        pinned = np.zeros(buffers.n_vertices, dtype=bool)
        if self._was_edit and self.pin_selection:
            pinned |= mesh_io.read_selection(mesh)
        if self.pin_group:
            if self.pin_group not in obj.vertex_groups:
                self.report({'ERROR'}, "Pin group '%s' is not a vertex group of %s"
                            % (self.pin_group, obj.name))
                self._restore_mode()
                return None
            pinned |= mesh_io.read_vertex_group(obj, self.pin_group) > 0.0
        self._pinned_count = int(pinned.sum())
        params = engine_values(self)
        return Job(buffers, pinned if pinned.any() else None, params)

    def _restore_mode(self):
        if getattr(self, "_was_edit", False):
            obj = bpy.data.objects.get(self._obj_name)
            if obj is not None and bpy.context.view_layer.objects.active == obj:
                bpy.ops.object.mode_set(mode='EDIT')

    # -- finishing ----------------------------------------------------------
    def _finish(self, context, job):
        obj = bpy.data.objects.get(self._obj_name)
        try:
            if job.error is not None:
                level = {'WARNING'} if (isinstance(job.error, native.EngineError)
                                         and job.error.status == native.STATUS_CANCELLED) else {'ERROR'}
                self.report(level, _error_text(job.error))
                return {'CANCELLED'}
            if obj is None or obj.type != 'MESH' or len(obj.data.vertices) != job.buffers.n_vertices:
                self.report({'ERROR'}, "The mesh changed during the run; nothing was written")
                return {'CANCELLED'}
            writeback.write_result(obj, job.buffers, job.result, self._pinned_count)
            if self.gauss_image:
                gauss_image.build(obj, job.buffers.positions, job.result.positions,
                                  job.buffers.triangles, job.result.curves)
            writeback.use_attribute_shading(context)
            s = job.result.stats
            self.report({'INFO'}, "Developable: E %.3g -> %.3g rad (%+.1f %%), %d iterations, "
                        "%.0f ms" % (s["mean_defect_before"], s["mean_defect_after"],
                                     s["change_percent"], s["iterations"], s["time_total_ms"]))
            return {'FINISHED'}
        finally:
            self._restore_mode()

    # -- entry points ---------------------------------------------------------
    def execute(self, context):
        job = self._prepare(context)
        if job is None:
            return {'CANCELLED'}
        job.run()
        return self._finish(context, job)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        job = self._prepare(context)
        if job is None:
            return {'CANCELLED'}
        self._job = job
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        job.start()
        self._status(context)
        return {'RUNNING_MODAL'}

    def _status(self, context):
        job = self._job
        text = "Make Developable: %s %3.0f %%  (%.1f s)  Esc to cancel" % (
            job.stage or "", 100.0 * job.fraction, time.perf_counter() - job.started)
        if job.cancelled:
            text = "Make Developable: cancelling..."
        if context.workspace is not None:
            context.workspace.status_text_set(text)
        context.window_manager.progress_update(int(100 * min(max(job.fraction, 0.0), 1.0)))

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
        if event.type == 'ESC' and event.value == 'PRESS':
            job.cancel()
        if job.done:
            job.join()
            self._end_modal(context)
            result = self._finish(context, job)
            self._job = None
            for area in context.screen.areas if context.screen else ():
                area.tag_redraw()
            return result
        if event.type == 'TIMER':
            self._status(context)
        if event.type in _NAVIGATION:
            return {'PASS_THROUGH'}  # the view may be orbited/zoomed meanwhile
        # Block other input (edits) while the engine works on the captured mesh.
        return {'RUNNING_MODAL'}


classes = (MESH_OT_make_developable,)


def menu_func(self, context):
    self.layout.operator(MESH_OT_make_developable.bl_idname, icon='MOD_SMOOTH')


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

# SPDX-License-Identifier: GPL-3.0-or-later
"""The run loop shared by Make Developable and Unfold Pattern: the objects one
after another, each an engine call (core.jobs.Job).

With a window, invoke() runs each call on a worker thread (ctypes releases
the GIL) while modal() shows the progress in the status bar and the cursor;
Esc cancels (the engine answers CANCELLED and writes nothing) and the view
can still be orbited and zoomed. Without one (scripts, --background, the
redo panel) the calls run in turn on Blender's thread, the cursor showing
the progress when there is a window.

An operator using it defines:
  status_label                the name in the status bar
  _begin(context, interactive) -> the targets, or None (reported); interactive:
                              invoked from a window (not a script or the redo panel)
  prepare(context, target)    -> a Job, or raises Refused (the message is the report)
  finish_one(context, target, job) -> (level set, message)
  finish_all(context, results, cancelled) -> the operator's return set, with
                              results [(target, level set, message)] in order"""

import bpy

from . import mesh_io
from .core import native
from .core.text import plural


class Refused(Exception):
    """The object cannot run; the message is the report."""


# Events passed to Blender during a modal run: the view may be orbited and zoomed.
NAVIGATION = {
    "MIDDLEMOUSE",
    "WHEELUPMOUSE",
    "WHEELDOWNMOUSE",
    "TRACKPADPAN",
    "TRACKPADZOOM",
    "MOUSEMOVE",
    "INBETWEEN_MOUSEMOVE",
    "NDOF_MOTION",
}


def cancelled_by_user(job):
    exc = job.error
    return isinstance(exc, native.EngineError) and exc.status == native.STATUS_CANCELLED


def non_mesh_note(context):
    """(level set, message) naming the selected objects that are not meshes, or None."""
    others = sorted(o.name for o in context.selected_objects if o.type != "MESH")
    if not others:
        return None
    return {"INFO"}, "%s not a mesh, left out: %s" % (
        plural(len(others), "object is", "objects are"),
        ", ".join(others),
    )


class ModalRun:
    status_label = "Developable"
    _timer = None
    _job = None

    # -- entry points ------------------------------------------------------------
    def execute(self, context):
        targets = self._begin(context, interactive=False)
        if targets is None:
            return {"CANCELLED"}
        return self.run_all(context, targets)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        targets = self._begin(context, interactive=True)
        if targets is None:
            return {"CANCELLED"}
        return self.run_modal(context, targets)

    # -- synchronous -------------------------------------------------------------
    def run_all(self, context, targets):
        wm = context.window_manager
        show = context.window is not None and not bpy.app.background
        if show:
            wm.progress_begin(0, 100)
        results, cancelled = [], False
        try:
            for i, target in enumerate(targets):
                try:
                    job = self.prepare(context, target)
                except Refused as exc:
                    results.append((target, {"ERROR"}, str(exc)))
                    continue
                if show:
                    job.on_progress = lambda f, i=i: wm.progress_update(
                        int(100 * (i + min(max(f, 0.0), 1.0)) / len(targets))
                    )
                job.run()
                cancelled = cancelled_by_user(job)
                results.append((target,) + tuple(self.finish_one(context, target, job)))
                if cancelled:
                    break
        finally:
            if show:
                wm.progress_end()
        return self.finish_all(context, results, cancelled)

    # -- modal -------------------------------------------------------------------
    def run_modal(self, context, targets):
        self._queue = list(targets)
        self._count = len(targets)
        self._results = []
        if not self._next_job(context):
            return self.finish_all(context, self._results, False)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        self._status(context)
        return {"RUNNING_MODAL"}

    def _next_job(self, context):
        """Starts the next object's call; False when none is left."""
        while self._queue:
            target = self._queue.pop(0)
            try:
                job = self.prepare(context, target)
            except Refused as exc:
                self._results.append((target, {"ERROR"}, str(exc)))
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
        text = "%s%s: %s %3.0f %%  (%.1f s)  Esc to cancel" % (
            self.status_label,
            which,
            job.stage or "",
            100.0 * job.fraction,
            job.seconds,
        )
        if job.cancelled:
            text = "%s: cancelling..." % self.status_label
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
            cancelled = cancelled_by_user(job)
            self._results.append((self._target,) + tuple(self.finish_one(context, self._target, job)))
            if not cancelled and self._next_job(context):
                return {"RUNNING_MODAL"}
            self._end_modal(context)
            self._job = None
            result = self.finish_all(context, self._results, cancelled)
            for area in context.screen.areas if context.screen else ():
                area.tag_redraw()
            return result
        if event.type == "TIMER":
            self._status(context)
        if event.type in NAVIGATION:
            return {"PASS_THROUGH"}
        # Block other input (edits) while the engine works on the captured mesh.
        return {"RUNNING_MODAL"}


def restore_mode(context, select_errors, was_edit, active_name):
    """After a run: a refused mesh in Edit mode with its bad elements selected
    (select_errors: (object name, (vertices, edges, polygons))), as the
    3D-Print Toolbox shows what is wrong; else Edit mode again if the run
    started there."""
    if select_errors is not None:
        obj = bpy.data.objects.get(select_errors[0])
        if obj is not None:
            context.view_layer.objects.active = obj
            obj.select_set(True)
            vertices, edges, polygons = select_errors[1]
            context.tool_settings.mesh_select_mode = (
                len(polygons) == 0 and len(edges) == 0,
                len(edges) > 0,
                len(polygons) > 0,
            )
            mesh_io.select_in_edit_mode(obj, vertices, edges, polygons)
        return
    if was_edit:
        obj = bpy.data.objects.get(active_name)
        if obj is not None and context.view_layer.objects.active == obj:
            bpy.ops.object.mode_set(mode="EDIT")

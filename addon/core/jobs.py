# SPDX-License-Identifier: GPL-3.0-or-later
"""One engine call on captured buffers (no bpy), run synchronously or on a
worker thread: ctypes releases the GIL during dev_run and dev_unfold, so
Blender's window keeps going while a modal operator polls the job's
fraction and stage. cancel() makes the next progress report answer "stop"
(what Esc does); the engine then returns CANCELLED and writes nothing."""

import threading
import time


class Job:
    """work: callable(progress) -> result, where progress(fraction, stage) ->
    bool is the engine's progress callback (False cancels). `data` is
    whatever the caller keeps with the job (the buffers, the object's name)."""

    def __init__(self, work, data=None):
        self.work = work
        self.data = data
        self.fraction = 0.0
        self.stage = "starting"
        self.result = None
        self.error = None  # native.EngineError / LibraryError / other Exception
        self.done = False
        self.on_progress = None  # callable(fraction) on the calling thread (synchronous runs)
        self._cancel = threading.Event()
        self._thread = None
        self.started = time.perf_counter()

    def cancel(self):
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def progress(self, fraction, stage):
        self.fraction = fraction
        self.stage = stage
        if self.on_progress is not None:
            self.on_progress(fraction)
        return not self._cancel.is_set()

    def run(self):
        try:
            self.result = self.work(self.progress)
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

    @property
    def seconds(self):
        return time.perf_counter() - self.started

"""Blender-side test scenarios for the add-on (run by tests/test_addon_*.py):

  blender -b --factory-startup --python scenarios.py -- NAME [ARGS]
  blender -b --factory-startup --python scenarios.py -- several "NAME [ARGS]" ...

Each prints RESULT {json}; "several" runs background scenarios one after
another in one Blender start-up (each starts from fresh objects). The add-on module is "developable_mesh" (installed
from the zip into BLENDER_USER_SCRIPTS by the pytest fixture)."""
import importlib
import json
import os
import pathlib
import sys
import traceback

import addon_utils
import bpy
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2]))  # the repository: devkit
from devkit import blender as dk_blender, meshes as dk_meshes
from devkit.measures import angle_defects

MODULE = "developable_mesh"
ARGS = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []


def emit(d):
    print("RESULT " + json.dumps(d))
    sys.stdout.flush()


def enable():
    """The add-on under its installed name: developable_mesh (legacy add-on) or
    bl_ext.<repository>.developable_mesh (4.2+ extension)."""
    names = [m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == MODULE] or [MODULE]
    mod = addon_utils.enable(names[0], default_set=True)
    assert mod is not None, "add-on %s could not be enabled" % names[0]
    return mod


PKG = enable()


def sub(name):
    return importlib.import_module(PKG.__name__ + "." + name)


writeback, native, operators = sub("writeback"), sub("core.native"), sub("operators")


class EngineWatch:
    """Watches the add-on's engine runs from outside (the add-on has no test
    hooks): wraps the add-on's native.run to count the progress reports, to
    answer "stop" after `cancel_after` of them (what Esc does; -1 never) and
    to record how the run ended, and the operator's modal() to note when a
    modal run has finished (written back or not)."""

    def __init__(self, cancel_after=-1):
        self.cancel_after = cancel_after
        self.progress_calls = 0
        self.status = None  # "OK" or the engine's status name, once native.run returned
        self.modal_finished = False
        self._run = native.run
        self._modal = operators.MESH_OT_make_developable.modal

    def __enter__(self):
        watch = self

        def run(positions, triangles, pinned=None, params=None, progress=None):
            def counting(fraction, stage):
                watch.progress_calls += 1
                go_on = progress(fraction, stage) if progress else True
                return go_on and not 0 <= watch.cancel_after < watch.progress_calls

            try:
                result = watch._run(positions, triangles, pinned, params, counting)
            except native.EngineError as error:
                watch.status = error.status_name
                raise
            watch.status = "OK"
            return result

        def modal(op, context, event):
            result = watch._modal(op, context, event)
            if not result & {"RUNNING_MODAL", "PASS_THROUGH"}:
                watch.modal_finished = True
            return result

        native.run = run
        operators.MESH_OT_make_developable.modal = modal
        return self

    def __exit__(self, *exc):
        native.run = self._run
        operators.MESH_OT_make_developable.modal = self._modal

    def outcome(self):
        return {"status": self.status, "progress_calls": self.progress_calls}


# -- geometry helpers (independent of the add-on) ---------------------------------


def fresh(kind="cone_band", name=None):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    v, f = dk_meshes.DEMOS[kind]()
    ob = dk_blender.object_from_arrays(name or kind, v, f)
    return ob


def coords(mesh):
    a = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", a)
    return a.reshape(-1, 3)


def key_coords(ob, name="Developable"):
    kb = ob.data.shape_keys.key_blocks[name]
    a = np.empty(len(kb.data) * 3, dtype=np.float32)
    kb.data.foreach_get("co", a)
    return a.reshape(-1, 3)


def attr_values(mesh, name):
    at = mesh.attributes.get(name)
    if at is None:
        return None
    width = 4 if at.data_type in {"FLOAT_COLOR", "BYTE_COLOR"} else 1
    prop = "color" if width == 4 else "value"
    dtype = np.int32 if at.data_type == "INT" else np.float32
    a = np.empty(len(at.data) * width, dtype=dtype)
    at.data.foreach_get(prop, a)
    return a.reshape(-1, width) if width > 1 else a


def triangles(mesh):
    mesh.calc_loop_triangles()
    t = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", t)
    return t.reshape(-1, 3)


def state(ob):
    """Everything the add-on may have written, for before/after comparisons."""
    me = ob.data
    return {
        "keys": [k.name for k in me.shape_keys.key_blocks] if me.shape_keys else [],
        # built-in ones ("position" on 4.x: is_required) are not the add-on's
        "attributes": sorted(
            a.name for a in me.attributes if not a.name.startswith(".") and not getattr(a, "is_required", False)
        ),
        "has_result": bool(ob.developable.has_result),
        "collections": sorted(c.name for c in bpy.data.collections),
        "vertices": len(me.vertices),
        "polygons": len(me.polygons),
    }


def run_op(*args, **kw):
    """(operator result, error text or '')."""
    try:
        return sorted(bpy.ops.mesh.make_developable(*args, **kw)), ""
    except RuntimeError as exc:
        return ["CANCELLED"], str(exc)


# -- scenarios ---------------------------------------------------------------------


def s_install():
    lib, err = native.try_load()
    defaults = native.default_params() if lib else {}
    op_props = bpy.ops.mesh.make_developable.get_rna_type().properties
    props = operators.MESH_OT_make_developable
    rna = bpy.context.scene.developable
    from_props = sub("properties").engine_values(rna)
    emit(
        {
            "module": PKG.__name__,
            "file": PKG.__file__,
            "library": native.library_path(),
            "library_error": err,
            "version": native.version() if lib else "",
            # an extension (4.2+) is described by its manifest; Blender drops bl_info then
            "bl_info": {k: list(v) if isinstance(v, tuple) else v for k, v in getattr(PKG, "bl_info", {}).items()},
            "param_names": list(native.PARAM_NAMES),
            "operator_properties": [p.identifier for p in op_props],
            "defaults": defaults,
            "property_defaults": from_props,
            "panels": [
                c
                for c in ("VIEW3D_PT_developable", "VIEW3D_PT_developable_parameters", "VIEW3D_PT_developable_result")
                if hasattr(bpy.types, c)
            ],
            "has_operator": hasattr(bpy.types, props.__name__),
        }
    )


def s_run():
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    res, err = run_op()
    me = ob.data
    tris = triangles(me)
    d_before, interior = angle_defects(base.astype(np.float64), tris)
    d_after, _ = angle_defects(key_coords(ob).astype(np.float64), tris)
    stored_b = attr_values(me, "defect_before")
    stored_a = attr_values(me, "defect_after")
    col_b = attr_values(me, "Defect Before")
    col_a = attr_values(me, "Defect After")
    rec = ob.developable
    scale = rec.colour_scale
    exp_b = writeback.defect_colours(stored_b.astype(np.float64), interior, scale)
    exp_a = writeback.defect_colours(stored_a.astype(np.float64), interior, scale)
    patch = attr_values(me, "patch_id")
    at = me.attributes
    emit(
        {
            "result": res,
            "error": err,
            "state": state(ob),
            "base_unchanged": bool(np.array_equal(coords(me), base)),
            "mean_defect_before": float(np.abs(d_before[interior]).mean()),
            "mean_defect_after": float(np.abs(d_after[interior]).mean()),
            "stored_before_err": float(np.abs(stored_b - d_before)[interior].max()),
            "stored_after_err": float(np.abs(stored_a - d_after)[interior].max()),
            "stored_boundary_zero": bool((stored_b[~interior] == 0).all() and (stored_a[~interior] == 0).all()),
            "colours_finite": bool(np.isfinite(col_b).all() and np.isfinite(col_a).all()),
            "colours_same_scale_err": float(max(np.abs(col_b - exp_b).max(), np.abs(col_a - exp_a).max())),
            "colour_domains": [
                at["Defect Before"].domain,
                at["Defect Before"].data_type,
                at["Defect After"].domain,
                at["Defect After"].data_type,
            ],
            "defect_domains": [at["defect_before"].domain, at["defect_before"].data_type],
            "patch_domain": [
                at["patch_id"].domain,
                at["patch_id"].data_type,
                len(patch),
                int(patch.min()),
                int(patch.max()),
            ],
            "active_colour": me.color_attributes.active_color.name,
            "scale": scale,
            "stats": {
                k: getattr(rec, k)
                for k in ("e_before", "e_after", "change_percent", "time_ms", "iterations", "largest_move", "patches")
            },
            "key_value": ob.data.shape_keys.key_blocks["Developable"].value,
            "moved": float(np.linalg.norm(key_coords(ob) - base, axis=1).max()),
        }
    )


def s_rerun():
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    r1, _ = run_op(omega=5.0)
    k1 = key_coords(ob).copy()
    # Without the polish: other parameters, another result (with it, both
    # runs may return the same polish of the input, the least motion).
    r2, _ = run_op(omega=20.0, max_iterations=5, polish="OFF")
    k2 = key_coords(ob).copy()
    r3, _ = run_op(omega=5.0)
    k3 = key_coords(ob).copy()
    emit(
        {
            "results": [r1, r2, r3],
            "keys": state(ob)["keys"],
            "base_unchanged": bool(np.array_equal(coords(ob.data), base)),
            "second_differs": float(np.abs(k2 - k1).max()),
            "third_repeats": float(np.abs(k3 - k1).max()),
        }
    )


def s_cancel():
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    before = state(ob)
    with EngineWatch(cancel_after=int(ARGS[1]) if len(ARGS) > 1 else 0) as watch:
        res, err = run_op()
    emit(
        {
            "result": res,
            "error": err,
            "state_before": before,
            "state_after": state(ob),
            "last_run": watch.outcome(),
            "base_unchanged": bool(np.array_equal(coords(ob.data), base)),
        }
    )


def s_pins():
    out = {}
    # vertex group: one whole ruling plus a few interior vertices
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    vg = ob.vertex_groups.new(name="hold")
    held = list(range(0, 9)) + [300, 301, 302, 400, 500]
    vg.add(held, 1.0, "REPLACE")
    res, err = run_op(pin_group="hold")
    k = key_coords(ob)
    free = np.setdiff1d(np.arange(len(base)), held)
    out["group"] = {
        "result": res,
        "error": err,
        "pinned": ob.developable.pinned,
        "pinned_move": float(np.abs(k[held] - base[held]).max()),
        "free_move": float(np.abs(k[free] - base[free]).max()),
    }
    # boundary
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    _, interior = angle_defects(base.astype(np.float64), triangles(ob.data))
    res, err = run_op(pin_boundary=True)
    k = key_coords(ob)
    out["boundary"] = {
        "result": res,
        "error": err,
        "pinned_move": float(np.abs(k[~interior] - base[~interior]).max()),
        "free_move": float(np.abs(k[interior] - base[interior]).max()),
    }
    # edit-mode selection
    ob = fresh("cone_band")
    base = coords(ob.data).copy()
    sel = np.zeros(len(base), dtype=bool)
    sel[[100, 200, 250, 333, 444, 555]] = True
    # deselect all, then select six vertices one by one: foreach_set("select") on a
    # mesh that has no selection attribute yet crashes Blender 5.0
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bpy.ops.object.mode_set(mode="OBJECT")
    for i in np.nonzero(sel)[0]:
        ob.data.vertices[int(i)].select = True
    bpy.ops.object.mode_set(mode="EDIT")
    res, err = run_op(pin_selection=True)
    mode_after = ob.mode
    bpy.ops.object.mode_set(mode="OBJECT")
    k = key_coords(ob)
    out["selection"] = {
        "result": res,
        "error": err,
        "mode_after": mode_after,
        "pinned": ob.developable.pinned,
        "pinned_move": float(np.abs(k[sel] - base[sel]).max()),
        "free_move": float(np.abs(k[~sel] - base[~sel]).max()),
        "base_unchanged": bool(np.array_equal(coords(ob.data), base)),
    }
    emit(out)


def _bad_mesh(kind):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    if kind == "no_faces":
        v, f = np.random.default_rng(0).normal(size=(10, 3)), np.zeros((0, 3))
    elif kind == "loose_edges":
        me = bpy.data.meshes.new(kind)
        me.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 1)], [(0, 1), (1, 2), (2, 3)], [])
        ob = bpy.data.objects.new(kind, me)
        bpy.context.scene.collection.objects.link(ob)
        bpy.context.view_layer.objects.active = ob
        return ob
    elif kind == "nan":
        # set after creation: Mesh.validate() would zero a NaN coordinate
        ob = dk_blender.object_from_arrays(kind, *dk_meshes.half_cylinder())
        co = np.empty(len(ob.data.vertices) * 3, dtype=np.float32)
        ob.data.vertices.foreach_get("co", co)
        co[17 * 3 + 1] = np.nan
        ob.data.vertices.foreach_set("co", co)
        return ob
    elif kind == "non_manifold":
        # three triangles (plus a strip) sharing the edge 0-1
        v = np.array(
            [[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1], [1.5, 1, 0.2], [1.5, -1, 0.1]], dtype=float
        )
        f = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 5, 2], [1, 3, 6]])
    else:
        raise SystemExit("unknown bad mesh " + kind)
    return dk_blender.object_from_arrays(kind, v, f)


def s_bad():
    out = {}
    for kind in ("no_faces", "loose_edges", "nan", "non_manifold"):
        ob = _bad_mesh(kind)
        before = state(ob)
        base = coords(ob.data).copy()
        res, err = run_op()
        out[kind] = {
            "result": res,
            "error": err,
            "state_before": before,
            "state_after": state(ob),
            "base_unchanged": bool(np.array_equal(coords(ob.data), base, equal_nan=True)),
        }
    emit(out)


def s_expect_error():
    """Library missing / of another ABI: a report, no traceback, nothing written."""
    ob = fresh("half_cylinder")
    before = state(ob)
    res, err = run_op()
    emit({"result": res, "error": err, "state_before": before, "state_after": state(ob)})


# -- scenarios needing a window (xvfb-run, no --background) ----------------------


def _window_override():
    wm = bpy.context.window_manager
    win = wm.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return dict(window=win, screen=win.screen, area=area, region=region)


def _finish(payload):
    emit(payload)
    os._exit(0)


def _in_window(fn):
    def timer():
        try:
            fn()
        except Exception:
            traceback.print_exc()
            _finish({"exception": traceback.format_exc()})
        return None

    bpy.app.timers.register(timer, first_interval=1.0)


def s_undo():
    def go():
        with bpy.context.temp_override(**_window_override()):
            ob = fresh("cone_band")
            base = coords(ob.data).copy()
            bpy.ops.ed.undo_push(message="cone band added")
            # undo=True: push an undo step as a call from the UI does (Python
            # calls skip the push by default)
            res, err = run_op("EXEC_DEFAULT", True)
            after_run = state(bpy.data.objects["cone_band"])
            bpy.ops.ed.undo()
            ob = bpy.data.objects["cone_band"]
            after_undo = state(ob)
            undo_base = bool(np.array_equal(coords(ob.data), base))
            bpy.ops.ed.redo()
            after_redo = state(bpy.data.objects["cone_band"])
        _finish(
            {
                "result": res,
                "error": err,
                "after_run": after_run,
                "after_undo": after_undo,
                "after_redo": after_redo,
                "undo_base_unchanged": undo_base,
            }
        )

    _in_window(go)


def modal_run(watch, prepare, report):
    """In a window: prepare() (inside a window override; returns what report
    needs), start the operator INVOKE_DEFAULT with `watch` on (until the
    process ends), wait until its modal run has finished (up to a minute),
    then emit report(started, prepared) and exit."""

    def go():
        with bpy.context.temp_override(**_window_override()):
            prepared = prepare()
            watch.__enter__()
            started = sorted(bpy.ops.mesh.make_developable("INVOKE_DEFAULT"))
        waited = [0]

        def poll():
            waited[0] += 1
            if not watch.modal_finished and waited[0] < 600:
                return 0.1
            _finish(report(started, prepared))

        bpy.app.timers.register(poll, first_interval=0.1)

    _in_window(go)


def s_modal():
    """The interactive path: INVOKE_DEFAULT -> worker thread + modal progress."""
    watch = EngineWatch(cancel_after=int(ARGS[1]) if len(ARGS) > 1 else -1)

    def prepare():
        ob = fresh("cone_band")
        return coords(ob.data).copy(), state(ob)

    def report(started, prepared):
        base, before = prepared
        ob = bpy.data.objects["cone_band"]
        return {
            "started": started,
            "last_run": watch.outcome(),
            "state_before": before,
            "state_after": state(ob),
            "base_unchanged": bool(np.array_equal(coords(ob.data), base)),
        }

    modal_run(watch, prepare, report)


SCENARIOS = {name[2:]: fn for name, fn in globals().items() if name.startswith("s_")}

if __name__ == "__main__":
    if ARGS[0] == "several":
        # Background scenarios one after another in this one Blender (one
        # start-up), one RESULT each, in order:  -- several run "cancel 3" ...
        for spec in ARGS[1:]:
            ARGS[:] = spec.split()
            SCENARIOS[ARGS[0]]()
    else:
        SCENARIOS[ARGS[0]]()

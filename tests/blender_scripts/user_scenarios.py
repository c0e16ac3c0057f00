"""The add-on as its users meet it (tests/test_addon_user.py), run in a real
Blender (Debian's 3.4, or a bpy module through bpy_main.py):

  blender -b --factory-startup --python user_scenarios.py -- NAME
  blender -b --factory-startup --python user_scenarios.py -- batch NAME NAME ...

Each prints RESULT {json}. "batch" runs background scenarios one after
another in one Blender start-up, each in a fresh factory-startup file (the
scene's settings back to their defaults), with a line "SCENARIO NAME" on
stderr before each so that a test can read each one's messages apart; an
exception in one is its RESULT ({"exception": traceback}) and the next one
runs. Meshes are generated with numpy (seeded), here or by devkit/meshes.py,
so nothing depends on the add-on's own helpers."""
import importlib
import json
import pathlib
import sys
import traceback

import addon_utils
import bpy
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2]))  # the repository: devkit
from devkit import meshes

ARGS = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []


def emit(d):
    print("RESULT " + json.dumps(d))
    sys.stdout.flush()


def enable():
    names = [m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == "developable_mesh"] or [
        "developable_mesh"
    ]
    mod = addon_utils.enable(names[0], default_set=True)
    assert mod is not None, names
    return mod


PKG = enable()


def sub(name):
    return importlib.import_module(PKG.__name__ + "." + name)


properties, writeback, gauss_image = sub("properties"), sub("writeback"), sub("gauss_image")


# -- meshes -------------------------------------------------------------------------


def clear():
    if bpy.context.object is not None and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    for c in list(bpy.data.collections):
        bpy.data.collections.remove(c)


def make_object(name, verts, faces, select=True):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(map(float, v)) for v in verts], [], [tuple(map(int, f)) for f in faces])
    me.update()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(select)
    return ob


def noisy_sheet(nu=24, nv=16, noise=0.01, seed=3):
    """A half-cylinder sheet with noise along z (quads)."""
    rng = np.random.default_rng(seed)
    u = np.linspace(0.0, np.pi, nu)
    v = np.linspace(0.0, 2.0, nv)
    U, V = np.meshgrid(u, v, indexing="ij")
    pts = np.stack([np.cos(U), V, np.sin(U)], axis=-1) + rng.normal(scale=noise, size=(nu, nv, 3))
    idx = np.arange(nu * nv).reshape(nu, nv)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1)
    return pts.reshape(-1, 3), quads.reshape(-1, 4)


def coords(me):
    a = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", a)
    return a.reshape(-1, 3).astype(np.float64)


def triangles(me):
    me.calc_loop_triangles()
    t = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
    me.loop_triangles.foreach_get("vertices", t)
    return t.reshape(-1, 3)


def mean_defect(p, tris):
    """Mean |2 pi - sum of angles| over interior vertices (independent of the add-on)."""
    n = len(p)
    total = np.zeros(n)
    for k in range(3):
        a, b, c = tris[:, k], tris[:, (k + 1) % 3], tris[:, (k + 2) % 3]
        u, v = p[b] - p[a], p[c] - p[a]
        cos = (u * v).sum(1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        np.add.at(total, a, np.arccos(np.clip(cos, -1, 1)))
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(edges, axis=0, return_counts=True)
    interior = np.ones(n, dtype=bool)
    interior[uniq[count == 1].ravel()] = False
    return float(np.abs(2 * np.pi - total)[interior].mean())


def shown(ob):
    """World coordinates of the shape the viewport shows (shape keys mixed)."""
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = ob.evaluated_get(dg)
    me = ev.to_mesh()
    try:
        p = coords(me)
    finally:
        ev.to_mesh_clear()
    m = np.array(ob.matrix_world)
    return p @ m[:3, :3].T + m[:3, 3]


def run(*args, **kw):
    """(result, error text)."""
    try:
        return sorted(bpy.ops.mesh.make_developable(*args, **kw)), ""
    except RuntimeError as exc:
        return ["CANCELLED"], str(exc)


def record(ob):
    rec = ob.developable
    return {
        k: getattr(rec, k)
        for k in (
            "has_result",
            "e_before",
            "e_after",
            "flat_before",
            "flat_after",
            "faces_turned",
            "move_percent",
            "largest_move",
            "move_limit",
            "size",
            "iterations",
            "verdict",
            "message",
            "world_space",
            "patches",
            "engine_result",
        )
    }


# -- scenarios ----------------------------------------------------------------------


def same(a, b):
    if isinstance(b, float):
        return abs(a - b) <= 1e-6 * max(1.0, abs(b))  # float properties are float32
    return a == b


def s_presets():
    settings = bpy.context.scene.developable
    out = {}
    for key, values in properties.PRESETS.items():
        if values is None:
            continue
        settings.preset = key
        want = dict(properties.GENERAL, **values)
        out[key] = {
            "preset": settings.preset,
            "mismatch": {n: [getattr(settings, n), v] for n, v in want.items() if not same(getattr(settings, n), v)},
        }
    settings.preset = "SHEET"
    settings.omega = 7.0  # by hand: no longer the preset
    out["after_edit"] = settings.preset
    # a script naming a job gets the job's values for what it does not set itself
    clear()
    ob = make_object("sheet", *noisy_sheet())
    settings.preset = "GENERAL"
    res, err = run(preset="OBJECT", max_iterations=40)
    out["script_preset"] = {
        "result": res,
        "error": err,
        "patches": ob.developable.patches,
        "scene_preset_kept": settings.preset,
    }
    emit(out)


def s_worse():
    clear()
    # A closed torus: its total curvature is 0 but cannot leave it
    # (Gauss-Bonnet). Every other ring turned: aligned, it would be a stack of
    # cone frusta, developable piecewise, which the engine says. Within 0.1 %
    # of its size nothing better is found (at the default 1 % its thinned
    # pieces, split where still curved inside, gather its curvature on their
    # seams: 12.5 -> 52 % of its vertices flat and ruled).
    bpy.context.scene.developable.move_limit = 0.1
    ob = make_object("torus", *meshes.ring_torus_quads(48, 16, 0.35, stagger=1.0))
    res, err = run()
    kb = ob.data.shape_keys.key_blocks.get("Developable") if ob.data.shape_keys else None
    emit({"result": res, "error": err, "record": record(ob), "key_value": kb.value if kb else None})


def s_better():
    clear()
    ob = make_object("sheet", *noisy_sheet())
    res, err = run()
    kb = ob.data.shape_keys.key_blocks["Developable"]
    emit({"result": res, "error": err, "record": record(ob), "key_value": kb.value})


def s_developable():
    """Meshes with nothing to do: a flat grid and a box without its bottom."""
    out = {}
    x, y = np.meshgrid(np.linspace(0, 2, 7), np.linspace(0, 1.5, 6), indexing="ij")
    k = np.arange(x.size).reshape(x.shape)
    plane = (
        np.c_[x.ravel(), y.ravel(), np.zeros(x.size)],
        np.stack([k[:-1, :-1], k[1:, :-1], k[1:, 1:], k[:-1, 1:]], -1).reshape(-1, 4),
    )
    shapes = {"plane": plane, "box": meshes.open_box(np.random.default_rng(1))}
    for name, (verts, faces) in shapes.items():
        clear()
        ob = make_object(name, verts, faces)
        res, err = run()
        kb = ob.data.shape_keys.key_blocks.get("Developable") if ob.data.shape_keys else None
        out[name] = {"result": res, "error": err, "record": record(ob), "key_value": kb.value if kb else None}
    emit(out)


def s_blender_torus():
    """Blender's own torus (Add > Mesh > Torus, 48 x 12 quads) with General:
    its top and bottom rings are flat and ruled as they stand, and the polish
    of the input bought a lower mean curvature by zigzagging them (16.7 % -> 0
    flat and ruled) until the rule held a whole object's flat-and-ruled share."""
    clear()
    bpy.ops.mesh.primitive_torus_add()
    ob = bpy.context.object
    res, err = run()
    rec = dict(record(ob), ruled_before=ob.developable.ruled_before, ruled_after=ob.developable.ruled_after)
    kb = ob.data.shape_keys.key_blocks.get("Developable") if ob.data.shape_keys else None
    emit({"result": res, "error": err, "record": rec, "key_value": kb.value if kb else None})


def s_menu_uses_panel():
    """Object > Make Developable (the menu calls the operator with no values)."""
    clear()
    ob = make_object("sheet", *noisy_sheet())
    settings = bpy.context.scene.developable
    settings.max_iterations = 3
    settings.move_limit = 0.5
    settings.segmentation = "OFF"
    res, err = run("INVOKE_DEFAULT")
    rec = ob.developable
    menu_ops = []

    class Probe:  # what the menu entry draws: the operator, no values set
        def operator(self, idname, **kw):
            menu_ops.append([idname, sorted(kw)])

    sub("operators").menu_func(type("M", (), {"layout": Probe()})(), bpy.context)
    emit(
        {
            "result": res,
            "error": err,
            "iterations": rec.iterations,
            "move_percent": rec.move_percent,
            "patches": rec.patches,
            "menu": menu_ops,
            "scene_after": [settings.max_iterations, settings.move_limit, settings.segmentation],
        }
    )


def s_shape_key():
    clear()
    v, f = noisy_sheet(noise=0.0)
    ob = make_object("sheet", v, f)
    ob.shape_key_add(name="Basis", from_mix=False)
    bulge = ob.shape_key_add(name="Bulge", from_mix=False)
    co = coords(ob.data)
    co_b = co.copy()  # the radius swells along the axis: curved both ways
    co_b[:, [0, 2]] *= (1.0 + 0.15 * np.sin(np.pi * co[:, 1] / 2.0) ** 2)[:, None]
    bulge.data.foreach_set("co", co_b.astype(np.float32).reshape(-1))
    bulge.value = 1.0
    tris = triangles(ob.data)
    seen_before = mean_defect(shown(ob), tris)
    basis_defect = mean_defect(co, tris)
    res, err = run()
    kb = ob.data.shape_keys.key_blocks["Developable"]
    value = kb.value
    kb.value = 0.0
    at_zero = mean_defect(shown(ob), tris)
    kb.value = 1.0
    at_one = mean_defect(shown(ob), tris)
    emit(
        {
            "result": res,
            "error": err,
            "record": record(ob),
            "key_value": value,
            "shown_before": seen_before,
            "basis_defect": basis_defect,
            "shown_at_zero": at_zero,
            "shown_at_one": at_one,
            "keys": [k.name for k in ob.data.shape_keys.key_blocks],
        }
    )


def s_scaled():
    clear()
    ob = make_object("sheet", *noisy_sheet())
    ob.scale = (1.0, 1.0, 0.25)
    bpy.context.view_layer.update()
    tris = triangles(ob.data)
    world = mean_defect(shown(ob), tris)
    local = mean_defect(coords(ob.data), tris)
    res, err = run()
    ob.data.shape_keys.key_blocks["Developable"].value = 1.0
    emit(
        {
            "result": res,
            "error": err,
            "record": record(ob),
            "world_defect": world,
            "local_defect": local,
            "world_after": mean_defect(shown(ob), tris),
        }
    )


def s_non_manifold():
    clear()
    v, f = noisy_sheet(nu=10, nv=8)
    v = np.vstack([v, [[0.0, 1.0, 2.0]]])  # a fin on the edge between vertices a and b
    a, b = 4 * 8 + 3, 4 * 8 + 4
    ob = make_object("fin", v, list(map(tuple, f)) + [(a, b, len(v) - 1)])
    res, err = run()
    mode = ob.mode
    active = bpy.context.view_layer.objects.active.name
    bpy.ops.object.mode_set(mode="OBJECT")
    me = ob.data
    ev = np.empty(len(me.edges) * 2, dtype=np.int32)
    me.edges.foreach_get("vertices", ev)
    esel = np.zeros(len(me.edges), dtype=bool)
    me.edges.foreach_get("select", esel)
    selected = sorted(sorted(map(int, e)) for e in ev.reshape(-1, 2)[esel])
    emit(
        {
            "result": res,
            "error": err,
            "mode": mode,
            "active": active,
            "selected_edges": selected,
            "bad_edge": sorted([a, b]),
            "keys": bool(me.shape_keys),
            "has_result": ob.developable.has_result,
        }
    )


def s_shared_triangle():
    """A triangle lying on a quad of the sheet: validate() accepts it, so do we."""
    clear()
    v, f = noisy_sheet(nu=10, nv=8)
    q = f[20]
    ob = make_object("extra", v, list(map(tuple, f)) + [(q[0], q[1], q[2])])
    ob.data.calc_loop_triangles()
    valid_changed = ob.data.validate(verbose=False)
    res, err = run()
    emit(
        {
            "result": res,
            "error": err,
            "validate_changed": bool(valid_changed),
            "message": ob.developable.message,
            "has_result": ob.developable.has_result,
        }
    )


def s_several():
    clear()
    a = make_object("a", *noisy_sheet(seed=1))
    b = make_object("b", *noisy_sheet(seed=2))
    b.location = (4, 0, 0)
    a.select_set(True)
    b.select_set(True)
    shared = make_object("c", [], [])
    shared.data = a.data  # a linked duplicate of a
    shared.location = (0, 4, 0)
    shared.select_set(False)
    bpy.context.view_layer.objects.active = a
    res, err = run()
    emit(
        {
            "result": res,
            "error": err,
            "has_result": {o.name: o.developable.has_result for o in (a, b, shared)},
            "message_a": a.developable.message,
        }
    )


def s_gauss():
    clear()
    v, f = noisy_sheet(nu=90, nv=60)
    ob = make_object("big", v, f)
    res, err = run(gauss_image=True, max_iterations=5)
    first = gauss_image.collection_of(ob).name
    ob.name = "renamed"
    found_after_rename = gauss_image.collection_of(ob) is not None
    res2, err2 = run(gauss_image=True, max_iterations=5)
    coll = gauss_image.collection_of(ob)
    clouds = [o for o in coll.objects if o.instance_type == "VERTS"]
    dots = [o for o in coll.objects if o.parent in clouds]
    emit(
        {
            "result": [res, res2],
            "error": err + err2,
            "first": first,
            "found_after_rename": found_after_rename,
            "gauss_collections": sorted(c.name for c in bpy.data.collections if c.name.startswith(gauss_image.PREFIX)),
            "collection": coll.name,
            "cloud_sizes": sorted(len(o.data.vertices) for o in clouds),
            "faces": len(ob.data.polygons) * 2,
            "dot_colour_attributes": [bool(o.data.color_attributes) for o in dots],
            "legend": sorted(o.data.body for o in coll.objects if o.type == "FONT"),
        }
    )


def s_redo_reaches_the_sidebar():
    """Needs a window (xvfb-run): a run from the UI, then the last operation
    repeated with another value (what Adjust Last Operation and Repeat Last
    do): the sidebar shows the value that ran."""
    import os

    def go():
        win = bpy.context.window_manager.windows[0]
        area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
        region = next(r for r in area.regions if r.type == "WINDOW")
        out = {}
        try:
            with bpy.context.temp_override(window=win, screen=win.screen, area=area, region=region):
                clear()
                ob = make_object("sheet", *noisy_sheet())
                settings = bpy.context.scene.developable
                settings.max_iterations = 7
                bpy.ops.ed.undo_push(message="sheet")
                out["first"] = sorted(bpy.ops.mesh.make_developable("EXEC_DEFAULT", True))
                out["first_iterations"] = ob.developable.iterations
                last = bpy.context.window_manager.operators[-1]
                out["last"] = last.bl_idname
                last.properties.max_iterations = 4
                out["repeat"] = sorted(bpy.ops.screen.repeat_last())
                ob = bpy.data.objects["sheet"]
                out["iterations"] = ob.developable.iterations
                out["sidebar"] = bpy.context.scene.developable.max_iterations
        except Exception:  # reported, not a hang
            import traceback

            out["exception"] = traceback.format_exc()
        emit(out)
        os._exit(0)

    bpy.app.timers.register(go, first_interval=1.0)


SCENARIOS = {name[2:]: fn for name, fn in globals().items() if name.startswith("s_")}

if __name__ == "__main__":
    if ARGS[0] == "batch":
        for name in ARGS[1:]:
            bpy.ops.wm.read_homefile(use_factory_startup=True)
            print("SCENARIO " + name, file=sys.stderr, flush=True)
            try:
                SCENARIOS[name]()
            except Exception:
                emit({"exception": traceback.format_exc()})
    else:
        SCENARIOS[ARGS[0]]()

"""Blender-side scenarios of the Unfold Pattern operator (run by
tests/test_addon_pattern.py):

  blender [-b] --factory-startup --python pattern_scenarios.py -- NAME OUT_DIR

Each prints RESULT {json}. The checks read Blender's data directly (UV map,
edge seams, the face attribute, files), not the add-on's own figures."""
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

MODULE = "developable_mesh"
ARGS = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
PKG = addon_utils.enable(MODULE, default_set=True)
pattern_module = importlib.import_module(PKG.__name__ + ".pattern")


def emit(d):
    print("RESULT " + json.dumps(d))
    sys.stdout.flush()


def fresh():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    v, f = dk_meshes.DEMOS["cone_band"]()
    ob = dk_blender.object_from_arrays("cone_band", v, f)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob


def coords(mesh):
    a = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", a)
    return a.reshape(-1, 3)


def uv_islands(mesh, name):
    """Polygons joined across an edge where both loops agree on the UVs."""
    layer = mesh.uv_layers.get(name)
    if layer is None:
        return 0
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    uv = uv.reshape(-1, 2)
    parent = list(range(len(mesh.polygons)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    corner = {}  # (polygon, vertex) -> uv
    edge_polys = {}
    for p in mesh.polygons:
        vs = list(p.vertices)
        for i, li in enumerate(p.loop_indices):
            corner[(p.index, vs[i])] = uv[li]
            e = tuple(sorted((vs[i], vs[(i + 1) % len(vs)])))
            edge_polys.setdefault(e, []).append(p.index)
    for (a, b), polys in edge_polys.items():
        if len(polys) == 2:
            p, q = polys
            if (
                np.abs(corner[(p, a)] - corner[(q, a)]).max() < 1e-6
                and np.abs(corner[(p, b)] - corner[(q, b)]).max() < 1e-6
            ):
                parent[find(p)] = find(q)
    return len({find(p) for p in range(len(mesh.polygons))})


def state(ob):
    me = ob.data
    seams = np.empty(len(me.edges), dtype=bool)
    me.edges.foreach_get("use_seam", seams)
    strain = me.attributes.get("pattern_strain")
    values = None
    if strain is not None:
        values = np.empty(len(strain.data), dtype=np.float32)
        strain.data.foreach_get("value", values)
    return {
        "uv_maps": [u.name for u in me.uv_layers],
        "active_uv": me.uv_layers.active.name if me.uv_layers.active else "",
        "islands": uv_islands(me, "Developable Pattern"),
        "seams": int(seams.sum()),
        "strain": None
        if strain is None
        else [strain.domain, strain.data_type, len(strain.data), float(values.min()), float(values.max())],
        "keys": [k.name for k in me.shape_keys.key_blocks] if me.shape_keys else [],
        "record": {
            "has_result": ob.developable_pattern.has_result,
            "pieces": ob.developable_pattern.pieces,
            "sheets": ob.developable_pattern.sheets,
            "worst_strain": ob.developable_pattern.worst_strain,
            "source": ob.developable_pattern.source,
        },
    }


def unfold(path, undo=False):
    try:
        return sorted(bpy.ops.mesh.unfold_pattern("EXEC_DEFAULT", undo, filepath=path)), ""
    except RuntimeError as exc:
        return ["CANCELLED"], str(exc)


def s_headless():
    """--background: base mesh first, then the Developable shape key."""
    out = pathlib.Path(ARGS[1])
    ob = fresh()
    base = coords(ob.data).copy()
    bpy.context.scene.developable_pattern.auto_scale = True
    res_base, err_base = unfold(str(out / "base.svg"))
    on_base = state(ob)
    res_run = sorted(bpy.ops.mesh.make_developable("EXEC_DEFAULT"))
    res_key, err_key = unfold(str(out / "key.svg"))
    on_key = state(ob)
    too_big = bpy.context.scene.developable_pattern
    too_big.auto_scale = False
    too_big.scale = 1.0
    too_big.sheet = "CUSTOM"
    too_big.sheet_width = too_big.sheet_height = 50.0
    res_big, err_big = unfold(str(out / "big.svg"))
    emit(
        {
            "base": [res_base, err_base, on_base],
            "run": res_run,
            "key": [res_key, err_key, on_key],
            "too_big": [res_big, err_big, state(ob)],
            "files": sorted(p.name for p in out.iterdir()),
            "base_unchanged": bool(np.array_equal(coords(ob.data), base)),
        }
    )


def _window_override():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return dict(window=win, screen=win.screen, area=area, region=region)


def _finish(payload):
    emit(payload)
    os._exit(0)


def s_undo():
    """Under xvfb: Unfold Pattern with an undo step, undone, redone; optionally
    a screenshot of the UV editor with the islands of the developable result
    (ARGS[2]; start Blender on a saved .blend then, which has no splash)."""
    out = pathlib.Path(ARGS[1])
    shot = ARGS[2] if len(ARGS) > 2 else ""

    def go():
        try:
            with bpy.context.temp_override(**_window_override()):
                ob = fresh()  # the noisy band itself: several pieces, seams between them
                bpy.context.scene.developable_pattern.auto_scale = True
                bpy.ops.ed.undo_push(message="developable")
                base = coords(ob.data).copy()
                before = state(ob)
                res, err = unfold(str(out / "undo.svg"), undo=True)
                after = state(bpy.data.objects["cone_band"])
                bpy.ops.ed.undo()
                ob = bpy.data.objects["cone_band"]
                after_undo = state(ob)
                undo_base = bool(np.array_equal(coords(ob.data), base))
                bpy.ops.ed.redo()
                after_redo = state(bpy.data.objects["cone_band"])
            payload = {
                "result": res,
                "error": err,
                "before": before,
                "after": after,
                "after_undo": after_undo,
                "after_redo": after_redo,
                "undo_base_unchanged": undo_base,
                "files": sorted(p.name for p in out.iterdir()),
            }
            if shot:  # the pattern of the developable result, for docs/pattern.md
                with bpy.context.temp_override(**_window_override()):
                    bpy.ops.mesh.make_developable("EXEC_DEFAULT")
                    unfold(str(out / "shot.svg"))
                screenshot(bpy.data.objects["cone_band"], shot, lambda: _finish(payload))
            else:
                _finish(payload)
        except Exception:
            _finish({"exception": traceback.format_exc()})
        return None

    bpy.app.timers.register(go, first_interval=1.0)


def screenshot(ob, path, then):
    """The 3D view turned into a UV editor, all faces selected in Edit mode."""
    win = bpy.context.window_manager.windows[0]
    area = max(win.screen.areas, key=lambda a: a.width * a.height)
    area.type = "IMAGE_EDITOR"
    area.ui_type = "UV"
    with bpy.context.temp_override(window=win, area=area, active_object=ob, object=ob):
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
    space = area.spaces.active
    space.uv_editor.show_stretch = True
    space.uv_editor.display_stretch_type = "AREA"

    def shoot():
        region = next(r for r in area.regions if r.type == "WINDOW")
        with bpy.context.temp_override(window=win, area=area, region=region):
            bpy.ops.image.view_all(fit_view=True)
        with bpy.context.temp_override(window=win, area=area):
            bpy.ops.screen.screenshot(filepath=path)
        then()
        return None

    bpy.app.timers.register(shoot, first_interval=1.0)


def s_true_size():
    """What is unfolded is what the viewport shows, at world size: a 10 x 5 cm
    plane (metres) at object scale 2 with a visible "Stretch" key (x doubled,
    at 0.5), then with a Developable key that lifts it by 1 m."""
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    n, m = 11, 6
    x, y = np.meshgrid(np.linspace(0, 0.1, n), np.linspace(0, 0.05, m), indexing="ij")
    v = np.stack([x.ravel(), y.ravel(), np.zeros(n * m)], axis=1)
    idx = np.arange(n * m).reshape(n, m)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    f = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    ob = dk_blender.object_from_arrays("plane", v, f)
    ob.scale = (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    ob.shape_key_add(name="Basis", from_mix=False)
    stretch = ob.shape_key_add(name="Stretch", from_mix=False)
    co = v.copy()
    co[:, 0] *= 2.0
    stretch.data.foreach_set("co", co.astype(np.float32).ravel())
    stretch.value = 0.5

    def area(p):
        t = p[f]
        return float(0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum())

    shown, source = pattern_module.source_positions(ob)
    key = ob.shape_key_add(name="Developable", from_mix=False)
    lifted = v.copy()
    lifted[:, 2] += 1.0
    key.data.foreach_set("co", lifted.astype(np.float32).ravel())
    key.value = 0.0  # the pattern is of the key at full strength, whatever its slider
    keyed, key_source = pattern_module.source_positions(ob)
    emit(
        {
            "area": area(shown),
            "source": source,
            "key_area": area(keyed),
            "key_source": key_source,
            "key_z": [float(keyed[:, 2].min()), float(keyed[:, 2].max())],
        }
    )


SCENARIOS = {name[2:]: fn for name, fn in globals().items() if name.startswith("s_")}

if __name__ == "__main__":
    SCENARIOS[ARGS[0]]()

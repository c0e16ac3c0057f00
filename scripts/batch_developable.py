# SPDX-License-Identifier: GPL-3.0-or-later
"""Batch processing with the Developable Mesh add-on, in Blender without a window:

  blender -b -P scripts/batch_developable.py -- IN OUT [options]

IN   .obj / .ply / .stl / .blend, or demo:cone_band / demo:half_cylinder
     (a generated noisy mesh from the repository's devkit/meshes.py)
OUT  .blend (the object with the "Developable" shape key, the defect colours and
     attributes) or .obj / .ply / .stl (the deformed mesh: shape key applied)

Every setting of the add-on is an option (--preset OBJECT --move-limit 2
--omega 5 --tolerance 10 --mode PAPER
--pin-boundary --no-use-mls-weights ...); see --help. Also --pin-group NAME,
--object NAME (which object of a .blend), --gauss-image, --render PREFIX
(writes PREFIX_before.png and PREFIX_after.png: Workbench, defect colours),
--pattern OUT.svg (then Unfold Pattern: the flat pieces as SVG sheets, the UV
map "Developable Pattern", seams and strain; --sheet a4|a3|letter|WxH,
--pattern-scale X|auto, --unit scene|m|cm|mm|in, --seam-tolerance PERCENT,
--seam-allowance MM, --glue-tabs MM).

The add-on is taken from, in order: --addon-module NAME; an installed add-on or
extension whose module ends with "developable_mesh"; the repository's addon/
package next to this script (development; the library from build/lib or
$DEVELOPABLE_LIBRARY). The last line printed is DEVELOPABLE_RESULT {json}.
Exit code 0 on success, 1 when the engine refused the mesh or failed.
"""

import argparse
import importlib
import json
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def script_args():
    argv = sys.argv
    return argv[argv.index("--") + 1 :] if "--" in argv else []


def load_addon(module_name=None):
    """Enables the add-on; returns its Python package."""
    import addon_utils

    names = [module_name] if module_name else []
    if not module_name:
        names += [m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == "developable_mesh"]
    for name in names:
        mod = addon_utils.enable(name, default_set=False, persistent=True)
        if mod is not None and hasattr(bpy.types, "MESH_OT_make_developable"):
            return mod
        if module_name:
            raise SystemExit("could not enable add-on module %r" % module_name)
    if REPO not in sys.path:
        sys.path.insert(0, REPO)
    mod = importlib.import_module("addon")
    if not hasattr(bpy.types, "MESH_OT_make_developable"):
        mod.register()
    return mod


def _op_exists(path):
    group, name = path.split(".")
    try:
        getattr(getattr(bpy.ops, group), name).get_rna_type()
        return True
    except (AttributeError, KeyError):
        return False


def _first_available(*paths):
    for p in paths:
        if _op_exists(p):
            group, name = p.split(".")
            return getattr(getattr(bpy.ops, group), name)
    raise SystemExit("none of the operators %s exists in this Blender" % (paths,))


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)


def demo_object(kind):
    """A generated noisy mesh from the repository's development kit (not part
    of the add-on: a user brings their own mesh)."""
    if REPO not in sys.path:
        sys.path.insert(0, REPO)
    from devkit import blender, meshes

    if kind not in meshes.DEMOS:
        raise SystemExit("unknown demo mesh %r (%s)" % (kind, ", ".join(sorted(meshes.DEMOS))))
    clear_scene()
    return blender.object_from_arrays(kind, *meshes.DEMOS[kind]())


def import_mesh(path, object_name):
    ext = os.path.splitext(path)[1].lower()
    if path.startswith("demo:"):
        return demo_object(path.split(":", 1)[1] or "cone_band")
    if not os.path.isfile(path):
        raise SystemExit("input file not found: %s" % path)
    if ext == ".blend":
        bpy.ops.wm.open_mainfile(filepath=path)
        ob = bpy.data.objects.get(object_name) if object_name else bpy.context.view_layer.objects.active
        if ob is None or ob.type != "MESH":
            ob = next((o for o in bpy.context.scene.objects if o.type == "MESH"), None)
    else:
        clear_scene()
        if ext == ".obj":
            _first_available("wm.obj_import", "import_scene.obj")(filepath=path)
        elif ext == ".ply":
            _first_available("wm.ply_import", "import_mesh.ply")(filepath=path)
        elif ext == ".stl":
            _first_available("wm.stl_import", "import_mesh.stl")(filepath=path)
        else:
            raise SystemExit("unsupported input format %s" % ext)
        meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
        ob = meshes[0] if meshes else None
    if ob is None:
        raise SystemExit("no mesh object in %s" % path)
    for o in bpy.context.scene.objects:
        o.select_set(o == ob)
    bpy.context.view_layer.objects.active = ob
    return ob


def export(ob, path):
    ext = os.path.splitext(path)[1].lower()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    if ext == ".blend":
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(path), check_existing=False)
        return
    for o in bpy.context.scene.objects:
        o.select_set(o == ob)
    bpy.context.view_layer.objects.active = ob
    if ext == ".obj":
        if _op_exists("wm.obj_export"):
            bpy.ops.wm.obj_export(filepath=path, export_selected_objects=True)
        else:
            bpy.ops.export_scene.obj(filepath=path, use_selection=True)
    elif ext == ".ply":
        if _op_exists("wm.ply_export"):
            bpy.ops.wm.ply_export(filepath=path, export_selected_objects=True)
        else:
            bpy.ops.export_mesh.ply(filepath=path, use_selection=True)
    elif ext == ".stl":
        if _op_exists("wm.stl_export"):
            bpy.ops.wm.stl_export(filepath=path, export_selected_objects=True)
        else:
            bpy.ops.export_mesh.stl(filepath=path, use_selection=True)
    else:
        raise SystemExit("unsupported output format %s" % ext)


def render_before_after(ob, prefix, addon):
    """Two Workbench renders coloured by the defect (same colour scale)."""
    from mathutils import Vector

    if REPO not in sys.path:
        sys.path.insert(0, REPO)
    from devkit.blender import workbench_scene

    scene = bpy.context.scene
    workbench_scene(scene, 1024, 768, (0.05, 0.05, 0.06))

    corners = [ob.matrix_world @ Vector(c) for c in ob.bound_box]
    centre = sum(corners, Vector()) / 8.0
    size = max((max(c[i] for c in corners) - min(c[i] for c in corners)) for i in range(3))
    cam_data = bpy.data.cameras.new("Developable Camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = size * 1.45
    cam = bpy.data.objects.new("Developable Camera", cam_data)
    scene.collection.objects.link(cam)
    direction = Vector((0.9, -1.3, 1.0)).normalized()
    cam.location = centre + direction * size * 3.0
    cam.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    cam_data.clip_end = size * 10.0
    scene.camera = cam

    rec = ob.developable
    txt_data = bpy.data.curves.new("Developable Legend", "FONT")
    txt_data.size = cam_data.ortho_scale * 0.028
    txt = bpy.data.objects.new("Developable Legend", txt_data)
    scene.collection.objects.link(txt)
    txt.parent = cam
    half_w = cam_data.ortho_scale / 2.0
    half_h = half_w * 768 / 1024
    txt.location = (-half_w * 0.95, -half_h * 0.85, -size)

    gauss = importlib.import_module(addon.__name__ + ".gauss_image")
    gauss_shown = gauss.set_visible(ob, False)  # the picture is of the mesh only
    keys = ob.data.shape_keys.key_blocks
    kb = keys[addon.writeback.SHAPE_KEY]
    paths = []
    for label, after in (("before", False), ("after", True)):
        kb.value = 1.0 if after else 0.0
        rec.show_after = after
        e = rec.e_after if after else rec.e_before
        txt_data.body = (
            "%s: mean curvature (angle defect) E = %.3g rad\n"
            "colour: blue -%.3g .. white 0 .. red +%.3g rad (same scale both)"
            % (label.capitalize(), e, rec.colour_scale, rec.colour_scale)
        )
        scene.render.filepath = os.path.abspath("%s_%s.png" % (prefix, label))
        bpy.ops.render.render(write_still=True)
        paths.append(scene.render.filepath)
    kb.value = 1.0
    rec.show_after = True
    bpy.data.objects.remove(txt, do_unlink=True)
    if gauss_shown:
        gauss.set_visible(ob, True)
    return paths


def build_parser(addon):
    props = addon.properties
    p = argparse.ArgumentParser(prog="blender -b -P batch_developable.py --", description=__doc__.split("\n\n")[0])
    p.add_argument("input")
    p.add_argument("output")
    p.add_argument("--object", default="", help="object name in a .blend input")
    p.add_argument("--render", default="", metavar="PREFIX", help="write PREFIX_before.png / PREFIX_after.png")
    p.add_argument("--addon-module", default="", help=argparse.SUPPRESS)
    p.add_argument(
        "--pattern",
        default="",
        metavar="OUT.svg",
        help="unfold the result into flat pieces and write them as SVG sheets",
    )
    p.add_argument("--sheet", default="a4", help="pattern sheet: a4, a3, letter or WxH in mm")
    p.add_argument(
        "--pattern-scale", default="1", metavar="X|auto", help="paper length per model length (1 = 1:1) or auto"
    )
    p.add_argument(
        "--unit",
        default="scene",
        choices=["scene", "m", "cm", "mm", "in"],
        help="what one Blender unit is (default: the scene's unit scale)",
    )
    p.add_argument(
        "--seam-tolerance",
        type=float,
        default=None,
        metavar="PERCENT",
        help="largest stretch of a piece's outline edge before it is split",
    )
    p.add_argument(
        "--seam-allowance",
        type=float,
        default=None,
        metavar="MM",
        help="cut every piece this far outside its outline on the sheet (sewing, gluing)",
    )
    p.add_argument(
        "--glue-tabs",
        type=float,
        default=None,
        metavar="MM",
        help="a glue tab this high on one side of every seam (papercraft)",
    )
    defs = props.all_property_definitions()
    for name, prop in defs.items():
        kw = prop.keywords if hasattr(prop, "keywords") else prop[1]
        flag = "--" + name.replace("_", "-")
        fn = getattr(prop, "function", None) or prop[0]
        kind = fn.__name__
        help_text = kw.get("description", "").replace("%", "%%")
        if kind == "BoolProperty":
            p.add_argument(flag, dest=name, action="store_true", default=None, help=help_text)
            p.add_argument("--no-" + name.replace("_", "-"), dest=name, action="store_false")
        elif kind == "EnumProperty":
            p.add_argument(flag, dest=name, choices=[i[0] for i in kw["items"]], help=help_text)
        elif kind == "IntProperty":
            p.add_argument(flag, dest=name, type=int, help=help_text)
        elif kind == "FloatProperty":
            p.add_argument(flag, dest=name, type=float, help=help_text)
        else:
            p.add_argument(flag, dest=name, help=help_text)
    return p, list(defs)


def unfold_pattern(ob, args):
    """Unfold Pattern with the options; its figures, or {"error": ...}."""
    settings = bpy.context.scene.developable_pattern
    sheet = args.sheet.lower()
    if sheet in ("a4", "a3", "letter"):
        settings.sheet = sheet.upper()
    else:
        try:
            width, height = (float(x) for x in sheet.split("x"))
        except ValueError:
            return {"error": "--sheet needs a4, a3, letter or WxH in mm, got %r" % args.sheet}
        settings.sheet = "CUSTOM"
        settings.sheet_width, settings.sheet_height = width, height
    if args.pattern_scale == "auto":
        settings.auto_scale = True
    else:
        settings.auto_scale = False
        settings.scale = float(args.pattern_scale)
    settings.unit = "SCENE" if args.unit == "scene" else args.unit
    if args.seam_tolerance is not None:
        settings.seam_tolerance = args.seam_tolerance
    if args.seam_allowance is not None:
        settings.seam_allowance = args.seam_allowance
    if args.glue_tabs is not None:
        settings.glue_tabs = args.glue_tabs
    settings.export_svg = True
    bpy.context.view_layer.objects.active = ob
    try:
        bpy.ops.mesh.unfold_pattern(filepath=os.path.abspath(args.pattern))
    except RuntimeError as exc:
        print(str(exc).strip())
        return {"error": str(exc).strip()}
    rec = ob.developable_pattern
    return {
        "pieces": rec.pieces,
        "sheets": rec.sheets,
        "seams": rec.seams,
        "worst_strain_percent": rec.worst_strain,
        "mean_strain_percent": rec.mean_strain,
        "scale": rec.scale,
        "files": rec.files.split("; ") if rec.files else [],
    }


def main():
    args_list = script_args()
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--addon-module", default="")
    known, _ = pre.parse_known_args(args_list)
    addon = load_addon(known.addon_module or None)
    # the package's submodules (writeback, properties) by relative name
    for sub in ("writeback", "properties"):
        setattr(addon, sub, importlib.import_module(addon.__name__ + "." + sub))
    parser, names = build_parser(addon)
    args = parser.parse_args(args_list)

    ob = import_mesh(args.input, args.object)
    # a .blend may have reset the add-on state: make sure the operator is there
    if not hasattr(bpy.types, "MESH_OT_make_developable"):
        addon = load_addon(known.addon_module or None)
    options = {n: getattr(args, n) for n in names if getattr(args, n) is not None}
    if bpy.context.object is not None and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    try:
        result = bpy.ops.mesh.make_developable(**options)
        error = ""
    except RuntimeError as exc:  # the operator's ERROR report (bad mesh, no library)
        result, error = {"CANCELLED"}, str(exc).strip()
        print(error)
    summary = {
        "input": args.input,
        "output": args.output,
        "object": ob.name,
        "operator": sorted(result),
        "error": error,
    }
    if "FINISHED" not in result:
        print("DEVELOPABLE_RESULT " + json.dumps(summary))
        sys.stdout.flush()
        raise SystemExit(1)
    rec = ob.developable
    summary.update(
        {
            k: getattr(rec, k)
            for k in (
                "e_before",
                "e_after",
                "change_percent",
                "time_ms",
                "iterations",
                "largest_move",
                "move_limit",
                "patches",
                "curves",
                "pinned",
                "colour_scale",
                "stop_reason",
                "flat_before",
                "flat_after",
                "ruled_before",
                "ruled_after",
                "crumpled_after",
                "move_percent",
                "faces_turned",
                "verdict",
                "message",
                "engine_result",
            )
        }
    )
    if args.pattern:
        summary["pattern"] = unfold_pattern(ob, args)
        if "error" in summary["pattern"]:
            print("DEVELOPABLE_RESULT " + json.dumps(summary))
            sys.stdout.flush()
            raise SystemExit(1)
    if args.render:
        summary["renders"] = render_before_after(ob, args.render, addon)
    export(ob, args.output)
    print("DEVELOPABLE_RESULT " + json.dumps(summary))
    sys.stdout.flush()


if __name__ == "__main__":
    main()

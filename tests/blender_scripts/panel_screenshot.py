"""Screenshots of the sidebar panel in a real Blender window, at the default
sidebar width (the pictures of docs/addon.md):

  xvfb-run -a -s "-screen 0 1600x1400x24" blender --factory-startup --enable-event-simulate \\
      --window-geometry 0 0 1600 1400 START.blend \\
      --python tests/blender_scripts/panel_screenshot.py -- OUT.png STATE

STATE (the scene is built here, from the add-on's own operators):
  run        the demo cone band after Run (docs/addon-panel.png)
  advanced   the same with the collapsed sub-panels (Pins, Advanced) open
  pattern    the cone band unfolded, Flat Pattern open with its figures
  warnings   a plate with modifiers and an unwelded seam, before any run
  closed     Blender's default cube after Run: already developable piecewise
  crumpled   a noisy square-to-round duct after Run with the General job
  pieces     a rounded box (devkit/objects.py, seed 101) after Run: pieces
             meeting at seams, curvature painted

The add-on must be installed (BLENDER_USER_SCRIPTS, as scripts/run.sh does).
Opening a .blend (any, e.g. an empty scene saved once) avoids the splash
screen; a simulated click opens the "Developable" tab of the sidebar. The
picture is cropped to the sidebar and, but for advanced and pattern, the part
of the viewport beside it.
It prints the sidebar's width and the texts the add-on's own measure finds
cut (panel_recorder.py), which should be none."""
import os
import pathlib
import sys
import tempfile

import addon_utils
import bpy
import numpy as np
from mathutils import Euler, Vector

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2]))  # devkit
import panel_recorder
import shapes
from devkit import meshes, objects

ARGS = sys.argv[sys.argv.index("--") + 1 :]
OUT = os.path.abspath(ARGS[0])
STATE = ARGS[1] if len(ARGS) > 1 else "run"
names = [m.__name__ for m in addon_utils.modules() if m.__name__.endswith("developable_mesh")]
addon_utils.enable(names[0] if names else "developable_mesh", default_set=True)

OPEN = {
    "advanced": ("VIEW3D_PT_developable_pins", "VIEW3D_PT_developable_parameters"),
    "pattern": ("VIEW3D_PT_developable_pattern",),
}
CLOSED = {"advanced": ("VIEW3D_PT_developable_result",), "pattern": ("VIEW3D_PT_developable_result",)}
for name in OPEN.get(STATE, ()) + CLOSED.get(STATE, ()):
    cls = getattr(bpy.types, name)
    bpy.utils.unregister_class(cls)
    cls.bl_options = {"DEFAULT_CLOSED"} if name in CLOSED.get(STATE, ()) else set()
    bpy.utils.register_class(cls)


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width)
    return win, area


def make(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(map(float, v)) for v in verts], [], [tuple(map(int, f)) for f in faces])
    me.update()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    for o in bpy.context.scene.objects:
        o.select_set(o == ob)
    bpy.context.view_layer.objects.active = ob
    return ob


def build():
    """The scene of STATE; returns (object, where the view looks from)."""
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    if STATE in ("run", "advanced", "pattern"):
        ob = make("cone_band", *meshes.cone_band())
        bpy.ops.mesh.make_developable()
        if STATE == "pattern":
            settings = bpy.context.scene.developable_pattern
            settings.auto_scale = True
            bpy.ops.mesh.unfold_pattern(filepath=os.path.join(tempfile.mkdtemp(), "cone_band.svg"))
        return ob, (Vector((0.0, 0.0, 0.3)), 6.5)
    if STATE == "warnings":
        v, f = shapes.unwelded_sheet(nu=24, nv=12, seam=12)
        ob = make("plate", v, f)
        bend = ob.modifiers.new("Bend", "SIMPLE_DEFORM")
        bend.deform_method, bend.deform_axis, bend.angle = "BEND", "Z", 1.0
        return ob, (Vector((0.5, 0.3, 0.1)), 2.2)
    if STATE == "closed":
        bpy.ops.mesh.primitive_cube_add()
        bpy.ops.mesh.make_developable()
        return bpy.context.active_object, (Vector((0.0, 0.0, 0.0)), 8.0)
    if STATE == "crumpled":
        ob = make("duct", *shapes.duct(noise=0.0005))
        bpy.ops.mesh.make_developable()
        return ob, (Vector((0.0, 0.0, 0.15)), 1.1)
    if STATE == "pieces":
        box = objects.make("rounded_box", faces=3000, seed=101)
        ob = make("rounded_box", box.positions, box.triangles)
        bpy.ops.mesh.make_developable()
        return ob, (Vector(box.positions.mean(axis=0)), 2.5 * float(np.ptp(box.positions, axis=0).max()))
    raise SystemExit("unknown state %r" % STATE)


def setup():
    win, area = view3d()
    space = area.spaces[0]
    with bpy.context.temp_override(window=win, screen=win.screen, area=area):
        ob, (centre, distance) = build()
    space.show_region_ui = True
    space.shading.type = "SOLID"
    space.shading.color_type = "VERTEX"
    space.overlay.show_floor = True
    rv3d = space.region_3d
    rv3d.view_perspective = "PERSP"
    rv3d.view_rotation = Euler((1.25, 0.0, 0.25)).to_quaternion()
    # the object beside the sidebar, in the part of the viewport the picture keeps
    rv3d.view_location = centre - rv3d.view_rotation @ Vector((0.33 * distance, 0.0, 0.0))
    rv3d.view_distance = distance
    bpy.app.timers.register(click_tab, first_interval=1.0)


def click_tab():
    """Clicks the "Developable" tab (the sidebar keeps its default width)."""
    win, area = view3d()
    ui = next(r for r in area.regions if r.type == "UI")
    x = ui.x + ui.width - 10
    y = ui.y + ui.height - 176
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=area.x + 300, y=area.y + 300)
    bpy.app.timers.register(shoot, first_interval=1.5)


def shoot():
    win, area = view3d()
    ui = next(r for r in area.regions if r.type == "UI")
    with bpy.context.temp_override(window=win, screen=win.screen, area=area, region=ui):
        cut = panel_recorder.check_panels(panel_recorder.Context(ui.width, ui))
        bpy.ops.screen.screenshot(filepath=OUT)
    top = area.y + area.height
    beside = {"advanced": 0, "pattern": 0}.get(STATE, 330)  # the viewport beside the sidebar, pixels
    crop(OUT, x0=max(0, ui.x - beside), x1=ui.x + ui.width, y0=max(area.y, top - 1150), y1=top)
    print("wrote", OUT, "sidebar width", ui.width)
    print("cut", {name: c["cut"] for name, c in cut.items() if c["cut"]})
    sys.stdout.flush()
    os._exit(0)


def crop(path, x0, x1, y0, y1):
    """Keeps the window rectangle [x0, x1) x [y0, y1) (Blender's bottom-up pixels)."""
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    px = px.reshape(h, w, 4)[y0:y1, x0:x1].copy()
    out = bpy.data.images.new("crop", width=px.shape[1], height=px.shape[0], alpha=True)
    out.pixels.foreach_set(px.reshape(-1))
    out.filepath_raw = path
    out.file_format = "PNG"
    out.save()


bpy.app.timers.register(setup, first_interval=1.0)

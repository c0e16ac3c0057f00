"""Screenshots of the sidebar panel in a real Blender window, at the default
sidebar width (docs/addon-panel.png, docs/addon-panel-advanced.png):

  blender -b -P scripts/batch_developable.py -- demo:cone_band /tmp/cone.blend --gauss-image
  xvfb-run -a -s "-screen 0 1600x1400x24" blender --factory-startup --enable-event-simulate \
      --window-geometry 0 0 1600 1400 /tmp/cone.blend \
      --python tests/blender_scripts/panel_screenshot.py -- docs/addon-panel.png [advanced]

The add-on must be installed (BLENDER_USER_SCRIPTS, as scripts/run.sh does).
Opening a .blend avoids the splash screen; a simulated click opens the
"Developable" tab of the sidebar. With "advanced", the collapsed sub-panels
(Pins, Advanced) are registered open, so their labels can be checked too. The
picture is cropped to the right part of the window (viewport and sidebar)."""
import os
import sys

import addon_utils
import bpy
import numpy as np
from mathutils import Euler, Vector

ARGS = sys.argv[sys.argv.index("--") + 1 :]
OUT = os.path.abspath(ARGS[0])
ADVANCED = "advanced" in ARGS[1:]
names = [m.__name__ for m in addon_utils.modules() if m.__name__.endswith("developable_mesh")]
addon_utils.enable(names[0] if names else "developable_mesh", default_set=True)

if ADVANCED:
    for name in ("VIEW3D_PT_developable_pins", "VIEW3D_PT_developable_parameters", "VIEW3D_PT_developable_result"):
        cls = getattr(bpy.types, name)
        bpy.utils.unregister_class(cls)
        cls.bl_options = set()
        if name == "VIEW3D_PT_developable_result":
            cls.bl_options = {"DEFAULT_CLOSED"}
        bpy.utils.register_class(cls)


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width)
    return win, area


def setup():
    win, area = view3d()
    space = area.spaces[0]
    ob = next(o for o in bpy.data.objects if o.type == "MESH" and o.developable.has_result)
    bpy.context.view_layer.objects.active = ob
    for o in bpy.context.scene.objects:
        o.select_set(o == ob)
    space.show_region_ui = True
    space.shading.type = "SOLID"
    space.shading.color_type = "VERTEX"
    space.overlay.show_floor = True
    rv3d = space.region_3d
    rv3d.view_perspective = "PERSP"
    rv3d.view_location = Vector((2.6, 0.0, 0.4))
    rv3d.view_rotation = Euler((1.25, 0.0, 0.25)).to_quaternion()
    rv3d.view_distance = 8.0
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
    with bpy.context.temp_override(window=win, screen=win.screen, area=area):
        bpy.ops.screen.screenshot(filepath=OUT)
    top = area.y + area.height
    crop(OUT, x0=max(0, ui.x - 620), x1=ui.x + ui.width, y0=max(area.y, top - 1150), y1=top)
    print("wrote", OUT, "sidebar width", ui.width)
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

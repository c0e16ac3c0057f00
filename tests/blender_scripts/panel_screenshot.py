"""Screenshot of the sidebar panel in a real Blender window (docs/addon-panel.png).

  blender -b -P scripts/batch_developable.py -- demo:cone_band /tmp/cone.blend --gauss-image
  xvfb-run -a -s "-screen 0 1600x1200x24" blender --factory-startup --enable-event-simulate \
      --window-geometry 0 0 1600 1200 /tmp/cone.blend \
      --python tests/blender_scripts/panel_screenshot.py -- docs/addon-panel.png

The add-on must be installed (BLENDER_USER_SCRIPTS, as scripts/run.sh does).
Opening a .blend avoids the splash screen; a simulated click opens the
"Developable" tab of the sidebar."""
import os
import sys

import addon_utils
import bpy
from mathutils import Euler, Vector

OUT = os.path.abspath(sys.argv[sys.argv.index("--") + 1])
addon_utils.enable("developable_mesh", default_set=True)


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == 'VIEW_3D'), key=lambda a: a.width)
    return win, area


def setup():
    win, area = view3d()
    space = area.spaces[0]
    ob = next(o for o in bpy.data.objects if o.type == 'MESH' and o.developable.has_result)
    bpy.context.view_layer.objects.active = ob
    for o in bpy.context.scene.objects:
        o.select_set(o == ob)
    space.show_region_ui = True
    space.shading.type = 'SOLID'
    space.shading.color_type = 'VERTEX'
    space.overlay.show_floor = True
    rv3d = space.region_3d
    rv3d.view_perspective = 'PERSP'
    rv3d.view_location = Vector((1.2, 0.0, 0.6))
    rv3d.view_rotation = Euler((1.05, 0.0, 0.6)).to_quaternion()
    rv3d.view_distance = 9.0
    bpy.app.timers.register(click_tab, first_interval=1.0)


def click_tab():
    win, area = view3d()
    ui = next(r for r in area.regions if r.type == 'UI')
    # widen the sidebar: drag its left edge
    ey = ui.y + ui.height // 2
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', x=ui.x + 1, y=ey)
    win.event_simulate(type='LEFTMOUSE', value='PRESS', x=ui.x + 1, y=ey)
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', x=ui.x - 60, y=ey)
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', x=ui.x - 120, y=ey)
    win.event_simulate(type='LEFTMOUSE', value='RELEASE', x=ui.x - 120, y=ey)
    bpy.app.timers.register(click_tab2, first_interval=0.5)


def click_tab2():
    win, area = view3d()
    ui = next(r for r in area.regions if r.type == 'UI')
    x = ui.x + ui.width - 10
    y = ui.y + ui.height - 176
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', x=x, y=y)
    win.event_simulate(type='LEFTMOUSE', value='PRESS', x=x, y=y)
    win.event_simulate(type='LEFTMOUSE', value='RELEASE', x=x, y=y)
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', x=area.x + 300, y=area.y + 300)
    bpy.app.timers.register(shoot, first_interval=1.5)


def shoot():
    win, area = view3d()
    with bpy.context.temp_override(window=win, screen=win.screen, area=area):
        bpy.ops.screen.screenshot(filepath=OUT)
    print("wrote", OUT)
    sys.stdout.flush()
    os._exit(0)


bpy.app.timers.register(setup, first_interval=1.0)

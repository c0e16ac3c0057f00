"""Blender as a Python module (the `bpy` wheel) driven like the blender
command line, for the add-on tests on the Blenders of scripts/setup_bpy.sh:

  python bpy_main.py [FILE.blend] (--python SCRIPT | --python-expr CODE) [-- ARGS]

Opens FILE, enables the installed extension (..developable_mesh), runs the
script with sys.argv ending in "-- ARGS" as Blender would give it, and exits
1 when it raises (as `blender -b --python-exit-code 1` does).

It leaves with os._exit: the bpy module (4.2, 5.0) crashes in its own teardown
once a property with an update callback was registered on bpy.types.Object
(seen with a six-line PropertyGroup, no add-on code involved), which would
turn every run into exit code 139."""
import os
import runpy
import sys
import traceback

argv = sys.argv[1:]
tail = argv[argv.index("--") :] if "--" in argv else []
head = argv[: len(argv) - len(tail)]
blend = script = expr = None
i = 0
while i < len(head):
    if head[i] == "--python":
        script, i = head[i + 1], i + 2
    elif head[i] == "--python-expr":
        expr, i = head[i + 1], i + 2
    elif head[i].endswith(".blend"):
        blend, i = head[i], i + 1
    else:
        raise SystemExit("bpy_main.py: unknown argument %r" % head[i])

import bpy
import addon_utils

if blend:
    bpy.ops.wm.open_mainfile(filepath=blend)
for mod in addon_utils.modules():
    if mod.__name__.split(".")[-1] == "developable_mesh":
        addon_utils.enable(mod.__name__, default_set=True)
sys.argv = ["blender", "--background"] + (["--python", script] if script else []) + tail
code = 0
try:
    if script:
        runpy.run_path(script, run_name="__main__")
    else:
        exec(compile(expr, "<python-expr>", "exec"), {"__name__": "__main__"})
except SystemExit as exc:
    code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
except BaseException:
    traceback.print_exc()
    code = 1
sys.stdout.flush()
sys.stderr.flush()
os._exit(code)

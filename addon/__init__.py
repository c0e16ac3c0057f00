# SPDX-License-Identifier: GPL-3.0-or-later
"""Developable Mesh: make a mesh (nearly) developable by normal-guided deformation.

The package imports nothing from bpy until Blender calls register(), so that
its core (core/: the engine's binding and every figure and check in numpy)
can be imported from any Python: `from addon.core import native`. The
Blender parts, each importing only the ones listed before it:
  mesh_io     mesh <-> numpy buffers (foreach_get/foreach_set), the shape shown,
              the unwelded-seam check the panel shows
  writeback   shape key, attributes, colours, the record of a run
  gauss_image the Gauss image objects
  properties  the settings (scene and operators), the records of a run
  panels      the sidebar tab "Developable" and the redo panel's layout (draws only)
  modal       the modal loop shared by the operators (worker thread, status bar, Esc)
  operators   mesh.make_developable, mesh.developable_weld
  pattern     mesh.unfold_pattern (flat pieces, SVG)

Works as a legacy add-on (bl_info, Blender 3.x) and as a 4.2+ extension
(blender_manifest.toml beside this file); the package name is never assumed.
"""

bl_info = {
    "name": "Developable Mesh",
    "author": "Developable Mesh contributors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Developable; Object/Mesh menu > Make Developable",
    "description": "Make a mesh developable by normal-guided deformation (result as shape key)",
    "category": "Mesh",
    "doc_url": "",
}

# The modules in import order (each imports only those before it); register()
# registers the Blender ones in this order, unregister() in reverse.
CORE_MODULES = (
    "core.text",
    "core.native",
    "core.checks",
    "core.colours",
    "core.presets",
    "core.verdict",
    "core.estimate",
    "core.jobs",
)
BLENDER_MODULES = ("mesh_io", "writeback", "gauss_image", "properties", "panels", "modal", "operators", "pattern")

# importlib.reload (F8, or the add-on enabled again) keeps the old namespace:
# then register() reloads the modules too, so that edited files take effect.
_reloaded = "register" in globals()


def _modules():
    import importlib
    import sys

    modules = []
    for name in CORE_MODULES + BLENDER_MODULES:
        full = "%s.%s" % (__name__, name)
        module = sys.modules.get(full)
        if module is not None and _reloaded:
            module = importlib.reload(module)
        modules.append(module or importlib.import_module(full))
    return modules[len(CORE_MODULES) :]


def register():
    global _reloaded
    modules = _modules()
    _reloaded = False
    for module in modules:
        if hasattr(module, "register"):
            module.register()


def unregister():
    import importlib

    for name in reversed(BLENDER_MODULES):
        module = importlib.import_module("%s.%s" % (__name__, name))
        if hasattr(module, "unregister"):
            module.unregister()

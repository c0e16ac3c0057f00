# SPDX-License-Identifier: GPL-3.0-or-later
"""Developable Mesh: make a mesh (nearly) developable by normal-guided deformation.

Registration only; the parts live in their own modules:
  native      ctypes binding of the C++ engine (libdevelopable.so)
  checks      the add-on's own checks and figures (numpy, no bpy)
  mesh_io     mesh <-> numpy buffers (foreach_get/foreach_set)
  properties  engine parameters, pins, per-object record of the last run
  operators   mesh.make_developable (synchronous execute, modal invoke)
  writeback   shape key, attributes, colours, stats
  gauss_image the Gauss image objects
  panels      the sidebar tab "Developable"
  pattern     mesh.unfold_pattern, its settings and sub-panel (flat pieces, SVG)

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

if "bpy" in locals():  # script reload (F8 / addon_utils)
    import importlib

    for _m in (
        native,
        checks,
        mesh_io,
        properties,
        writeback,
        gauss_image,
        operators,
        panels,  # noqa: F821
        pattern,
    ):  # noqa: F821
        importlib.reload(_m)

import bpy

from . import native, checks, mesh_io, properties, writeback, gauss_image
from . import operators, panels, pattern

# pattern after panels: its sub-panel's parent
_modules = (properties, operators, panels, pattern, gauss_image)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()

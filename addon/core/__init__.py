# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's core, without bpy: importable and testable from any Python with
numpy (from a checkout, with the repository on sys.path:
`from addon.core import native, checks, verdict`).

  native    the ctypes binding of the engine's C ABI (native/api/developable.h)
  checks    checks of a mesh: what to hand the engine, what is wrong with a
            refused mesh in Blender's terms, one-sided parts, unwelded seams,
            flat faces
  colours   the curvature colours (blue - / white 0 / red +) and their scale
  presets   the jobs and the settings each implies
  verdict   what a run's result means for the user, from the engine's report
  text      figures and words as a designer reads them
  estimate  the expected run time shown for large meshes
  jobs      one engine call on a worker thread, with progress and cancel"""

"""Blender helper: one Workbench picture of meshes before and after, a row per mesh.

    blender --background --factory-startup --python-exit-code 1 \\
        --python bench/render_pairs.py -- OUT.png INPUT.obj,RESULT.obj[,y] ...

Each row shows INPUT (left) and RESULT (right), grey, flat-shaded (every
facet shows, so crumpling and cone points can be read), from one three-quarter
view, scaled to the input's bounding box; `y` marks a mesh modelled Y-up (the
OBJ convention; devkit's generators are Z-up). 350 x 350 per mesh."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # devkit
from devkit.blender import object_from_arrays, workbench_scene
from devkit.obj import read_obj

CELL = 350
BACKGROUND = (0.05, 0.05, 0.06)
Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # rows: x, y, z of Z-up from Y-up


def view(positions, centre, size, y_up):
    """The mesh centred, scaled to unit diagonal, Z-up, turned to a three-quarter view
    (35 degrees about the vertical, then tipped 20 degrees toward the camera)."""
    q = (positions - centre) / size
    if y_up:
        q = q @ Y_UP.T
    turn, tip = math.radians(35.0), math.radians(20.0)
    about_z = np.array([[math.cos(turn), -math.sin(turn), 0.0], [math.sin(turn), math.cos(turn), 0.0], [0, 0, 1.0]])
    about_x = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(tip), -math.sin(tip)], [0.0, math.sin(tip), math.cos(tip)]])
    return q @ about_z.T @ about_x.T


def main(argv):
    out, specs = argv[0], [spec.split(",") for spec in argv[1:]]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    workbench_scene(scene, 2 * CELL, CELL * len(specs), BACKGROUND)
    scene.display.shading.color_type = "SINGLE"
    scene.render.image_settings.compression = 100  # a picture for docs/: smallest file
    for row, spec in enumerate(specs):
        before, _ = read_obj(spec[0])
        centre = (before.max(0) + before.min(0)) / 2
        size = np.linalg.norm(before.max(0) - before.min(0))
        for column, path in enumerate(spec[:2]):
            positions, triangles = read_obj(path)
            q = view(positions, centre, size, len(spec) > 2 and spec[2] == "y")
            object_from_arrays("m%d_%d" % (row, column), q + np.array([column * 1.0, 0.0, -row * 1.0]), triangles)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = max(2.0, float(len(specs)))
    camera.location = (0.5, -5.0, -(len(specs) - 1) / 2)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


main(sys.argv[sys.argv.index("--") + 1 :])

"""Blender helper of bench/human_woman.py: four Workbench pictures of one run.

    blender --background --factory-startup --python-exit-code 1 \\
        --python bench/render_human_woman.py -- RUN.npz OUT_DIR

RUN.npz holds positions, triangles, patch_ids, defect_before, defect_after,
interior and after (the deformed positions), as bench/human_woman.py saves
them. Writes OUT_DIR/human-woman-patches.png (input shape, one colour per
patch, neighbours never alike, numbers on the patches that face the camera),
OUT_DIR/human-woman-defect-before.png (input shape) and
OUT_DIR/human-woman-defect-after.png (deformed shape) and
OUT_DIR/human-woman-closeup.png (head and left hand, before | after), the last
three coloured by the angle defect on one log scale: white at |defect| <= 1e-4 rad, full colour
at >= 1e-1 rad, red positive, blue negative (the add-on's "Defect Before/After"
map, addon/writeback.py, on a log scale). Front view (the mesh is Y-up and
faces +Z), one orthographic camera for the first three, 800 x 800."""
import colorsys
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # devkit
from devkit.blender import workbench_scene

SIZE = 800
LOW, HIGH = 1e-4, 1e-1  # rad: the ends of the log colour scale
BOUNDARY = (0.55, 0.55, 0.55)  # the add-on's colour where the defect is undefined
BACKGROUND = (0.05, 0.05, 0.06)


def defect_colours(defect, interior):
    """(n, 3) linear RGB: white at |d| <= LOW, red (+) / blue (-) at |d| >= HIGH."""
    a = np.abs(defect)
    t = np.clip(np.log10(np.maximum(a, 1e-300) / LOW) / np.log10(HIGH / LOW), 0.0, 1.0)
    rgb = np.ones((len(defect), 3))
    pos = defect > 0
    rgb[pos, 1] = rgb[pos, 2] = 1.0 - t[pos]
    rgb[~pos, 0] = rgb[~pos, 1] = 1.0 - t[~pos]
    rgb[~interior] = BOUNDARY
    return rgb


def patch_colours(triangles, patch_ids):
    """One light colour per patch from a palette of well separated hues; each
    patch takes the palette colour farthest from its already coloured
    neighbours, so adjacent patches never look alike."""
    k = int(patch_ids.max()) + 1
    palette = []
    for i in range(k):
        h = (i * 0.618033988749895) % 1.0
        s = (0.55, 0.35, 0.75)[i % 3]
        v = (0.95, 0.8, 0.9)[(i // 3) % 3]
        palette.append(colorsys.hsv_to_rgb(h, s, v))
    palette = np.array(palette)
    # patch adjacency through shared vertices
    n = int(triangles.max()) + 1
    owners = [set() for _ in range(n)]
    for t, p in zip(triangles.tolist(), patch_ids.tolist()):
        for v in t:
            owners[v].add(p)
    neighbours = [set() for _ in range(k)]
    for s in owners:
        for p in s:
            neighbours[p] |= s - {p}
    colour = np.full(k, -1)
    free = list(range(k))
    for p in sorted(range(k), key=lambda q: -len(neighbours[q])):
        used = [palette[colour[q]] for q in neighbours[p] if colour[q] >= 0]
        if used:
            used = np.array(used)
            score = [np.min(np.linalg.norm(used - palette[c], axis=1)) for c in free]
            pick = free[int(np.argmax(score))]
        else:
            pick = free[0]
        colour[p] = pick
        free.remove(pick)
    return palette[colour]


def srgb_to_linear(c):
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def make_mesh(name, positions, triangles, corner_rgb):
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(positions))
    me.vertices.foreach_set("co", np.asarray(positions, dtype=np.float32).reshape(-1))
    m = len(triangles)
    me.loops.add(3 * m)
    me.loops.foreach_set("vertex_index", np.asarray(triangles, dtype=np.int32).reshape(-1))
    me.polygons.add(m)
    me.polygons.foreach_set("loop_start", np.arange(0, 3 * m, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(m, 3, dtype=np.int32))
    me.update(calc_edges=True)
    me.validate()
    rgba = np.ones((3 * m, 4), dtype=np.float32)
    rgba[:, :3] = corner_rgb
    attr = me.color_attributes.new(name="Colour", type="FLOAT_COLOR", domain="CORNER")
    attr.data.foreach_set("color", rgba.reshape(-1))
    me.color_attributes.active_color = attr
    if hasattr(me.color_attributes, "render_color_index"):
        me.color_attributes.render_color_index = 0
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def text_mesh(body, location, size, rgb, align="LEFT"):
    """A text converted to a flat mesh facing +Z, coloured through a colour
    attribute so that Workbench's attribute colouring shows it."""
    curve = bpy.data.curves.new("label", "FONT")
    curve.body = body
    curve.size = size
    curve.align_x = align
    curve.align_y = "CENTER"
    tmp = bpy.data.objects.new("label", curve)
    bpy.context.scene.collection.objects.link(tmp)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    me = bpy.data.meshes.new_from_object(tmp.evaluated_get(depsgraph))
    bpy.data.objects.remove(tmp, do_unlink=True)
    bpy.data.curves.remove(curve)
    attr = me.color_attributes.new(name="Colour", type="FLOAT_COLOR", domain="CORNER")
    rgba = np.tile(np.array(list(rgb) + [1.0], dtype=np.float32), len(me.loops))
    attr.data.foreach_set("color", rgba)
    me.color_attributes.active_color = attr
    ob = bpy.data.objects.new("label", me)
    ob.location = location
    bpy.context.scene.collection.objects.link(ob)
    return ob


def colour_bar(x0, y0, width, height, z):
    """A horizontal strip with the defect colour scale: blue (negative) on the
    left, white in the middle, red (positive) on the right."""
    steps = 60
    d = np.concatenate(
        [
            -np.logspace(np.log10(HIGH), np.log10(LOW), steps // 2),
            np.logspace(np.log10(LOW), np.log10(HIGH), steps // 2),
        ]
    )
    rgb = defect_colours(d, np.ones(steps, dtype=bool))
    xs = x0 + width * np.arange(steps + 1) / steps
    verts = np.array([(x, y, z) for x in xs for y in (y0, y0 + height)])
    quads = np.array([(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1) for i in range(steps)])
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    corner = np.repeat(np.concatenate([rgb, rgb]), 3, axis=0)
    make_mesh("colour bar", verts, tris, corner)
    return xs


def setup_scene(centre, span, front_z):
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    workbench_scene(scene, SIZE, SIZE, BACKGROUND)
    scene.render.image_settings.compression = 100
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = span
    cam_data.clip_start = 0.01
    cam_data.clip_end = 100.0
    cam = bpy.data.objects.new("camera", cam_data)
    cam.location = (centre[0], centre[1], front_z + 5.0)
    cam.rotation_euler = (0.0, 0.0, 0.0)  # looks along -Z, up +Y
    scene.collection.objects.link(cam)
    scene.camera = cam


def render(path):
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    print("wrote", path)


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :]
    data = np.load(argv[0])
    out = argv[1]
    positions, triangles = data["positions"], data["triangles"]
    patch_ids, interior = data["patch_ids"], data["interior"].astype(bool)
    after = data["after"]

    both = np.concatenate([positions, after])
    lo, hi = both.min(axis=0), both.max(axis=0)
    centre = (lo + hi) / 2
    span = 1.1 * max(hi[0] - lo[0], hi[1] - lo[1])
    front = float(hi[2]) + 0.05
    left, bottom = centre[0] - span / 2, centre[1] - span / 2
    top = centre[1] + span / 2
    small = span * 0.02
    white = (1.0, 1.0, 1.0)

    # (a) patches
    setup_scene(centre, span, front)
    rgb = patch_colours(triangles, patch_ids)
    make_mesh("patches", positions, triangles, np.repeat(srgb_to_linear(rgb[patch_ids]), 3, axis=0))
    tri = positions[triangles]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(normal, axis=1) / 2
    facing = normal[:, 2] / np.maximum(2 * area, 1e-300) > 0.5
    centroid = tri.mean(axis=1)
    placed = []
    order = np.argsort([-area[patch_ids == p].sum() for p in range(int(patch_ids.max()) + 1)])
    for p in order:
        mine = patch_ids == p
        front_area = area[mine & facing].sum()
        if front_area < 0.4 * area[mine].sum():
            continue
        sel = np.nonzero(mine & facing)[0]
        mid = (centroid[sel] * area[sel, None]).sum(axis=0) / front_area
        for f in sel[np.argsort(np.linalg.norm(centroid[sel, :2] - mid[:2], axis=1))]:
            at = centroid[f]
            near = np.linalg.norm(positions[:, :2] - at[:2], axis=1) < small
            hidden = np.any(positions[near, 2] > at[2] + 0.02)
            crowded = any(np.linalg.norm(at[:2] - q) < 2.2 * small for q in placed)
            if not hidden and not crowded:
                placed.append(at[:2])
                text_mesh(str(p), (at[0], at[1], front), small * 1.3, (0.0, 0.0, 0.0), align="CENTER")
                break
    text_mesh(
        "%d patches (front view)" % (int(patch_ids.max()) + 1),
        (left + small, top - 1.5 * small, front),
        small * 1.6,
        white,
    )
    render(os.path.join(out, "human-woman-patches.png"))

    # (b, c) |angle defect| before and after, one scale
    for label, shape, defect in (("before", positions, data["defect_before"]), ("after", after, data["defect_after"])):
        setup_scene(centre, span, front)
        make_mesh("defect " + label, shape, triangles, defect_colours(defect, interior)[triangles.reshape(-1)])
        flat = np.mean(np.abs(defect[interior]) < 1e-3)
        text_mesh(
            "Angle defect %s\nmean |defect| %.2e rad\n|defect| < 1e-3 rad: %.0f %%"
            % (label, np.abs(defect[interior]).mean(), 100 * flat),
            (left + small, top - 3 * small, front),
            small * 1.5,
            white,
        )
        width, height = span * 0.30, small * 1.2
        x0, y0 = left + 3 * small, bottom + 3.5 * small
        colour_bar(x0, y0, width, height, front)
        ticks = [
            (-1e-1, "-1e-1"),
            (-1e-2, "-1e-2"),
            (-1e-3, "-1e-3"),
            (0, "±1e-4"),
            (1e-3, "1e-3"),
            (1e-2, "1e-2"),
            (1e-1, "1e-1"),
        ]
        for value, name in ticks:
            if value == 0:
                x = x0 + width / 2
            else:
                u = np.log10(abs(value) / LOW) / np.log10(HIGH / LOW)
                x = x0 + width / 2 * (1 + np.sign(value) * u)
            text_mesh("|", (x, y0 - 0.5 * small, front), small * 0.8, white, align="CENTER")
            text_mesh(name, (x, y0 - 1.5 * small, front), small * 0.85, white, align="CENTER")
        text_mesh("angle defect (rad), log scale", (x0, y0 + height + 1.1 * small, front), small * 1.05, white)
        render(os.path.join(out, "human-woman-defect-%s.png" % label))

    # (d) close-ups of the head and of the left hand (on the +x side), before and after
    cell = 0.32
    setup_scene((0.0, 0.0), 2 * cell, 0.5)
    regions = (("head", (positions[:, 1] > 1.40) & (np.abs(positions[:, 0]) < 0.13)), ("hand", positions[:, 0] > 0.60))
    for row, (name, keep) in enumerate(regions):
        faces = np.nonzero(keep[triangles].all(axis=1))[0]
        used = np.unique(triangles[faces])
        box = (positions[used].min(axis=0) + positions[used].max(axis=0)) / 2
        for column, (label, shape, defect) in enumerate(
            (("before", positions, data["defect_before"]), ("after", after, data["defect_after"]))
        ):
            centre_xy = np.array([(column - 0.5) * cell, (0.5 - row) * cell])
            offset = np.array([centre_xy[0] - box[0], centre_xy[1] - box[1], -box[2]])
            remap = np.full(len(shape), -1)
            remap[used] = np.arange(len(used))
            sub = remap[triangles[faces]]
            colours = defect_colours(defect, interior)[used]
            make_mesh("%s %s" % (name, label), shape[used] + offset, sub, colours[sub.reshape(-1)])
            text_mesh(
                "%s, %s" % (name, label),
                (centre_xy[0] - 0.47 * cell, centre_xy[1] + 0.44 * cell, 0.5),
                cell * 0.045,
                white,
            )
    render(os.path.join(out, "human-woman-closeup.png"))


if __name__ == "__main__":
    main()

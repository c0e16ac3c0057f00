#!/usr/bin/env python3
"""Flat patterns: the unfolding (dev_unfold: cuts, flat maps, splits, outlines, layout; no SVG)
timed per stage at 10k, 100k, 500k and 1M faces, before and after, and the docs' pictures.

    /usr/bin/python3 bench/pattern.py [--build BUILD] [--before OLD_BUILD [--before-commit C]] [--out docs]
                                      [--no-large]

Cases: exact developable sheets (a curved fold swept long: one patch) of about 10k, 100k, 500k and
1M faces; noisy bent sheets (devkit/families.py, grid, noise 2 % of the edge length, seed 1) of 10k,
100k and 500k faces after the engine with its defaults; human_woman after the engine (its patches),
also with a 3 mm seam allowance and with 3 mm glue tabs; Suzanne after the engine (when Blender is
installed); a noisy square-to-round duct after the engine (tests/pattern_support.py, seed 2); a plate
with holes, rolled (seed 3); sphere caps of 60 and 120 degrees. The
engine runs once per mesh (with BUILD); every unfolding runs in its own process (peak memory: its
high-water mark less its size before the call), once per library: OLD_BUILD's ("before", when
given) and BUILD's ("after"). Targets (issue 38): a developable 1M-face sheet under 5 s, a 500k-face
noisy sheet after the engine under 10 s. Writes the table between the markers of OUT/pattern.md and,
with rsvg-convert, sheet 1 of the duct, the 10k bent sheet, human_woman and the holed plate
(OUT/pattern-*.png; the duct and human_woman also before). About 10 minutes on 2 cores."""
import argparse
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "tests"))

from devkit import families, machine, meshes, paths  # noqa: E402
from devkit.obj import read_obj  # noqa: E402

BEGIN, END = "<!-- bench/pattern.py: begin -->", "<!-- bench/pattern.py: end -->"
AUTO = {"scale": 0}


def band(faces):
    """An exact developable of about `faces` triangles: a curved fold with rows x cols vertices,
    cols = 4 rows."""
    rows = max(3, int(round(np.sqrt(faces / 8.0))))
    return meshes.curved_fold(seed=5, rows=rows, cols=4 * rows)


def worker(library, mesh_file, params, repeats):
    """Runs in its own process: unfolds the mesh `repeats` times, prints the figures as JSON."""
    from devkit.binding import native

    native.load(path=library)
    data = np.load(mesh_file)
    ids = data["ids"] if "ids" in data.files else None
    status = pathlib.Path("/proc/self/status")

    def kib(field):
        return int(re.search(r"%s:\s+(\d+)" % field, status.read_text()).group(1))

    before = kib("VmRSS")
    best = None
    for _ in range(repeats):
        gaps, last = [0.0], [time.process_time()]

        def progress(fraction, stage):
            now = time.process_time()
            gaps[0], last[0] = max(gaps[0], now - last[0]), now
            return True

        cpu, wall = time.process_time(), time.perf_counter()
        pattern = native.unfold(data["pos"], data["tri"], ids, params=params, progress=progress)
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        st = pattern.stats
        row = {
            "pieces": st["pieces"],
            "splits": st["splits"],
            "cut_edges": st["cut_edges"],
            "sheets": st["sheets"],
            "max_strain": st["max_strain"],
            "mean_strain": st["mean_strain"],
            "unfold_s": st["time_unfold_ms"] / 1e3,
            "layout_s": st["time_layout_ms"] / 1e3,
            "cpu_s": cpu,
            "wall_s": wall,
            "gap_s": gaps[0],
        }
        if best is None or row["cpu_s"] < best["cpu_s"]:
            best = row
    best["peak_mib"] = (kib("VmHWM") - before) / 1024.0
    print(json.dumps(best))


def run_worker(library, mesh_file, params, repeats):
    proc = subprocess.run(
        [sys.executable, __file__, "--worker", str(library), str(mesh_file), json.dumps(params), str(repeats)],
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        return {"error": proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "failed"}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def save(folder, name, pos, tri, ids=None):
    path = pathlib.Path(folder) / (name + ".npz")
    if ids is None:
        np.savez(path, pos=pos, tri=tri)
    else:
        np.savez(path, pos=pos, tri=tri, ids=ids)
    return path


def prepare(native, folder, large):
    """[(case, faces, mesh file, params, repeats, picture name or None)]: the meshes, the engine
    run on those it is asked of."""
    from pattern_support import holed_plate, square_to_round

    cases = []
    for faces in [10_000, 100_000, 500_000] + ([1_000_000] if large else []):
        pos, tri = band(faces)
        repeats = 3 if faces <= 100_000 else 1
        cases.append(
            ("exact developable (curved fold)", len(tri), save(folder, "band%d" % faces, pos, tri), AUTO, repeats, None)
        )
    for faces in [10_000, 100_000] + ([500_000] if large else []):
        mesh = families.make("bent_sheet", "grid", faces=faces, noise=0.02, seed=1)
        result = native.run(mesh.positions, mesh.triangles)
        path = save(folder, "bent%d" % faces, result.positions, mesh.triangles, result.patch_ids)
        picture = "pattern-bent-sheet.png" if faces == 10_000 else None
        cases.append(
            (
                "noisy bent sheet after the engine",
                len(mesh.triangles),
                path,
                AUTO,
                3 if faces <= 100_000 else 1,
                picture,
            )
        )
    pos, tri = read_obj(paths.MESHES / "human_woman.obj")
    result = native.run(pos, tri)
    woman = save(folder, "woman", result.positions, tri, result.patch_ids)
    name = "human_woman after the engine (%d patches)" % result.stats["patches"]
    cases.append((name, len(tri), woman, AUTO, 3, "pattern-human-woman.png"))
    cases.append(("the same, 3 mm seam allowance", len(tri), woman, {"scale": 0, "seam_allowance_mm": 3.0}, 3, None))
    cases.append(("the same, 3 mm glue tabs", len(tri), woman, {"scale": 0, "glue_tabs_mm": 3.0}, 3, None))
    suzanne = blender_suzanne(folder)
    if suzanne is not None:
        result = native.run(*suzanne)
        monkey = save(folder, "suzanne", result.positions, suzanne[1], result.patch_ids)
        name = "Suzanne (Blender's monkey, triangulated) after the engine (%d patches)" % result.stats["patches"]
        cases.append((name, len(suzanne[1]), monkey, AUTO, 3, None))
    pos, tri = square_to_round(seed=2)
    result = native.run(pos, tri)
    duct = save(folder, "duct", result.positions, tri, result.patch_ids)
    cases.append(("noisy square-to-round duct after the engine", len(tri), duct, AUTO, 3, "pattern-duct.png"))
    pos, tri, holes = holed_plate(seed=3, bent=True)
    cases.append(
        (
            "plate with %d hole(s), rolled" % holes,
            len(tri),
            save(folder, "plate", pos, tri),
            AUTO,
            3,
            "pattern-holed-plate.png",
        )
    )
    for angle in (60, 120):
        pos, tri = meshes.sphere_cap(angle)
        cases.append(("sphere cap %d deg" % angle, len(tri), save(folder, "cap%d" % angle, pos, tri), AUTO, 3, None))
    return cases


def blender_suzanne(folder):
    """(positions, triangles) of Blender's monkey, triangulated, or None without Blender."""
    if shutil.which("blender") is None:
        return None
    obj = pathlib.Path(folder) / "suzanne.obj"
    script = (
        "import bpy\n"
        "bpy.ops.object.select_all(action='SELECT'); bpy.ops.object.delete()\n"
        "bpy.ops.mesh.primitive_monkey_add()\n"
        "me = bpy.context.active_object.data\n"
        "me.calc_loop_triangles()\n"
        "with open(%r, 'w') as f:\n"
        "    for v in me.vertices: f.write('v %%r %%r %%r\\n' %% tuple(v.co))\n"
        "    for t in me.loop_triangles: f.write('f %%d %%d %%d\\n' %% tuple(i + 1 for i in t.vertices))\n" % str(obj)
    )
    subprocess.run(["blender", "-b", "--python-expr", script], capture_output=True, timeout=300)
    return read_obj(obj) if obj.exists() else None


def picture(library, mesh_file, png, dpi=60):
    """Sheet 1 of the unfolding's SVG at `dpi`, through a worker-free load (the SVG is written by
    the library given)."""
    with tempfile.TemporaryDirectory() as tmp:
        svg = pathlib.Path(tmp) / "p.svg"
        code = (
            "import sys, numpy as np; sys.path.insert(0, %r); from devkit.binding import native; "
            "native.load(path=%r); d = np.load(%r); "
            "p = native.unfold(d['pos'], d['tri'], d['ids'] if 'ids' in d.files else None, params={'scale': 0}, "
            "svg_path=%r); print(p.files[0])" % (str(REPO), str(library), str(mesh_file), str(svg))
        )
        first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()[
            -1
        ]
        subprocess.run(
            ["rsvg-convert", "-d", str(dpi), "-p", str(dpi), "-b", "white", "-o", str(png), first], check=True
        )


def cell(row, key, fmt):
    return "-" if row is None or "error" in row else fmt % row[key]


def table(rows, have_before):
    head = "| case | faces | pieces | max strain | mean strain | unfold | layout | CPU | peak | progress gap | target |"
    if have_before:
        head = (
            "| case | faces | pieces before / after | max strain before / after | mean strain after "
            "| CPU before / after | unfold / layout after | peak before / after | progress gap after | target |"
        )
    lines = [head, "|" + "|".join(["---"] * (head.count("|") - 1)) + "|"]
    for case, faces, before, after in rows:
        target = ""
        if case.startswith("exact") and faces >= 900_000:
            target = "< 5 s CPU: %s" % ("met" if after["cpu_s"] < 5 else "MISSED")
        elif case.startswith("noisy bent") and faces >= 450_000:
            target = "< 10 s CPU: %s" % ("met" if after["cpu_s"] < 10 else "MISSED")
        if have_before:
            lines.append(
                "| %s | %d | %s / %d | %s / %.2e | %.2e | %s / %.2f s | %.2f / %.2f s | %s / %.0f MiB | %.2f s | %s |"
                % (
                    case,
                    faces,
                    cell(before, "pieces", "%d"),
                    after["pieces"],
                    cell(before, "max_strain", "%.2e"),
                    after["max_strain"],
                    after["mean_strain"],
                    cell(before, "cpu_s", "%.2f s"),
                    after["cpu_s"],
                    after["unfold_s"],
                    after["layout_s"],
                    cell(before, "peak_mib", "%.0f MiB"),
                    after["peak_mib"],
                    after["gap_s"],
                    target,
                )
            )
        else:
            lines.append(
                "| %s | %d | %d | %.2e | %.2e | %.2f s | %.2f s | %.2f s | %.0f MiB | %.2f s | %s |"
                % (
                    case,
                    faces,
                    after["pieces"],
                    after["max_strain"],
                    after["mean_strain"],
                    after["unfold_s"],
                    after["layout_s"],
                    after["cpu_s"],
                    after["peak_mib"],
                    after["gap_s"],
                    target,
                )
            )
    return lines


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        worker(sys.argv[2], sys.argv[3], json.loads(sys.argv[4]), int(sys.argv[5]))
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=str(paths.build_dir()))
    ap.add_argument("--before", help="a build folder of the code to compare with (e.g. an older commit's)")
    ap.add_argument("--before-commit", help="the commit OLD_BUILD was built from, for the table")
    ap.add_argument("--out", default=str(REPO / "docs"))
    ap.add_argument("--no-large", action="store_true", help="skip the 500k and 1M-face cases")
    args = ap.parse_args()
    library = paths.library_path(args.build)
    old = paths.library_path(args.before) if args.before else None
    from devkit.binding import native

    native.load(path=library)
    out = pathlib.Path(args.out)
    info = machine.machine_info(pathlib.Path(args.build), library)
    old_commit = args.before_commit or (machine.commit(pathlib.Path(args.before)) if args.before else None)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        cases = prepare(native, folder, not args.no_large)
        for case, faces, mesh_file, params, repeats, png in cases:
            before = run_worker(old, mesh_file, params, repeats) if old else None
            after = run_worker(library, mesh_file, params, repeats)
            rows.append((case, faces, before, after))
            print(
                "%-45s %8d faces  pieces %s -> %d  max %s -> %.2e  CPU %s -> %.2f s  peak %.0f MiB  gap %.2f s"
                % (
                    case,
                    faces,
                    cell(before, "pieces", "%d"),
                    after["pieces"],
                    cell(before, "max_strain", "%.2e"),
                    after["max_strain"],
                    cell(before, "cpu_s", "%.2f"),
                    after["cpu_s"],
                    after["peak_mib"],
                    after["gap_s"],
                ),
                flush=True,
            )
            if png and shutil.which("rsvg-convert"):
                picture(library, mesh_file, out / png)
                if old and png in ("pattern-duct.png", "pattern-human-woman.png"):
                    picture(old, mesh_file, out / png.replace(".png", "-before.png"))
    lines = [
        BEGIN,
        "",
        "Measured %s on %s (%d cores, %.0f GiB), commit %s, %s build%s; best of 3 by CPU time (1 at 500k "
        "faces and more). Load average at the start: %s."
        % (
            info["date"],
            info["cpu"],
            info["cores"],
            info["memory_gib"],
            info.get("commit", "?"),
            info.get("build_type", "?"),
            ", before: commit %s" % old_commit if old_commit else "",
            info.get("load_start"),
        ),
        "",
    ]
    lines += table(rows, old is not None)
    lines += [
        "",
        "CPU: the process's CPU time for the whole dev_unfold call (one thread; the machine is shared, "
        "its wall time is up to 2.5 x that, so the targets are held to CPU time); unfold / layout: the "
        "engine's own clocks (wall) for the unfolding and for the layout (automatic scale on A4, no "
        "SVG); peak: the process's high-water mark less its size before the call; progress gap: the "
        "longest CPU time between two progress reports.",
        "",
        END,
    ]
    doc = out / "pattern.md"
    text = doc.read_text() if doc.exists() else "# Flat patterns\n\n%s\n%s\n" % (BEGIN, END)
    text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: "\n".join(lines), text, flags=re.S)
    doc.write_text(text)
    print("wrote", doc)


if __name__ == "__main__":
    main()

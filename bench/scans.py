"""The engine on meshes a user brings (issue 38): noisy scans of sheets (the seeded families at
0.5-5 % of the edge length) and whole objects, from 10k to 1M faces, with the defaults.

    /usr/bin/python3 bench/scans.py [--sizes 10000,100000,1000000] [--quick] [--keep | --render]
                                    [--tool build/bin/developable] [--md docs/scans.md] [--json bench/scans.json]

Each case runs the command-line tool in its own process. Per case it prints and writes (the
table into --md, the rows into --json): CPU seconds (user + system of the tool, all threads),
wall seconds, peak resident memory, the stage times the tool reports (curve fit and
factorisation, the paper's iterations, the polish), the result's origin and the figures a user
sees (flat, flat-and-ruled and crumpled shares after; for sheets the largest and rms distance to
the noise-free twin over the input's). At the end it fits CPU seconds = a * faces^b for each kind
(one-patch sheets, segmented objects) and gives each run's ratio to the fit. --keep keeps the
rows of --json whose sizes this run does not measure (the 1M cases can then run on their own);
--render only writes the table again from --json. With sheets and objects at two sizes or more it
also fits the add-on's time estimate (wall seconds per kind) and writes it into
addon/core/estimate.py.
CPU seconds are what the fit uses: wall seconds on a shared machine depend on what else runs."""
import argparse
import json
import pathlib
import sys
import tempfile

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from devkit import families, objects
from devkit.machine import machine_info
from devkit.tool import run_tool_measured
from addon.core import estimate

SHEETS = ("cylinder_patch", "cone_patch", "bent_sheet", "tangent_random")
SHEET_NOISE = (0.005, 0.02, 0.05)  # of the average edge length
OBJECTS = ("rounded_box", "blob")  # blob tops out at 81920 faces (its icosphere level)
OBJECT_NOISE = 0.01


def cases(sizes, quick):
    """(kind, name, maker) in a fixed order: a maker returns (positions, triangles, clean or None)."""
    out = []
    for faces in sizes:
        sheets = SHEETS[:2] if faces >= 1_000_000 or quick else SHEETS
        noises = (0.02,) if faces >= 1_000_000 or quick else SHEET_NOISE
        for family in sheets:
            for noise in noises:

                def sheet(family=family, faces=faces, noise=noise):
                    m = families.make(family, "grid", faces=faces, noise=noise, seed=7)
                    return m.positions, m.triangles, m.clean

                out.append(("sheet", "%s noise %.1f %%" % (family, 100 * noise), faces, sheet))
        for kind in OBJECTS[:1] if faces >= 1_000_000 or quick else OBJECTS:

            def thing(kind=kind, faces=faces):
                m = objects.make(kind, faces=faces, noise=OBJECT_NOISE, seed=7)
                return m.positions, m.triangles, None

            out.append(("object", "%s noise %.0f %%" % (kind, 100 * OBJECT_NOISE), faces, thing))
    return out


def run_case(tool, work, positions, triangles):
    """(stats, cpu seconds, wall seconds, peak bytes, output positions) of the tool's defaults
    (its warnings are in stats["result_message"])."""
    run = run_tool_measured(tool, work, positions, triangles)
    if isinstance(run, str):
        raise RuntimeError("the tool failed: " + run)
    return run.report["stats"], run.cpu_s, run.wall_s, run.peak_bytes, run.positions


def twin_distances(before, after, clean):
    """(largest, rms) vertex distance to the twin after, each over the input's."""
    d0 = np.linalg.norm(before - clean, axis=1)
    d1 = np.linalg.norm(after - clean, axis=1)
    return float(d1.max() / d0.max()), float(np.sqrt((d1**2).mean() / (d0**2).mean()))


def power_fit(rows, seconds="cpu_s"):
    """(a, b) of seconds = a * faces^b, least squares on the logarithms; None with fewer than 2 sizes."""
    if len({r["size"] for r in rows}) < 2:
        return None
    faces = np.array([r["faces"] for r in rows], float)
    cpu = np.array([r[seconds] for r in rows], float)
    b, log_a = np.polyfit(np.log(faces), np.log(cpu), 1)
    return float(np.exp(log_a)), float(b)


def panel_estimate(rows):
    """The add-on's estimate per kind (addon/core/estimate.py MEASURED): wall seconds = a * (faces /
    1e5)^b fitted over every size, and the runs of the sizes from LARGE_MESH_FACES on (those the panel
    estimates) over the fit from low to high."""
    out = {}
    for kind in ("sheet", "object"):
        mine = [r for r in rows if r["kind"] == kind]
        fit = power_fit(mine, "wall_s")
        large = [r for r in mine if r["size"] >= estimate.LARGE_MESH_FACES]
        if fit is None or not large:
            continue
        a, b = fit[0] * 1e5 ** fit[1], fit[1]
        ratios = [r["wall_s"] / (a * (r["faces"] / 1e5) ** b) for r in large]
        out[kind] = {"a": a, "b": b, "low": min(ratios), "high": max(ratios)}
    return out


def write_estimate(fits, info):
    """Rewrites the MEASURED block of addon/core/estimate.py (between its bench/scans.py markers)."""
    path = REPO / "addon" / "core" / "estimate.py"
    text = path.read_text()
    begin, end = "# bench/scans.py: begin\n", "# bench/scans.py: end\n"
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    block = [
        "# Wall seconds = a * (faces / 1e5)^b; measured runs at 100k faces and more",
        "# over the fit from low to high (bench/scans.py, %s," % info["date"],
        "# %s, %d cores)." % (info["cpu"], info["cores"]),
        "MEASURED = {",
    ]
    for kind, fit in fits.items():
        block.append('    "%s": {%s},' % (kind, ", ".join('"%s": %r' % (k, float("%.3g" % v)) for k, v in fit.items())))
    block.append("}")
    path.write_text(head + begin + "\n".join(block) + "\n" + end + tail)


HEADER = (
    "| mesh | faces | CPU s | wall s | peak MiB | fit+factor ms | iterations ms | polish ms (steps) | origin | "
    "flat % | flat & ruled % | crumpled % | to twin max / rms |"
)


def table_row(r):
    twin = "%.2f / %.2f" % (r["twin_max"], r["twin_rms"]) if r["twin_max"] is not None else "-"
    return "| %s | %d | %.2f | %.2f | %.0f | %.0f | %.0f | %.0f (%d) | %s | %.1f | %.1f | %.1f | %s |" % (
        r["name"],
        r["faces"],
        r["cpu_s"],
        r["wall_s"],
        r["peak_bytes"] / 2**20,
        r["time_decompose_ms"],
        r["time_iterate_ms"],
        r["time_polish_ms"],
        r["polish_iterations"],
        r["origin"],
        100 * r["flat"],
        100 * r["flat_and_ruled"],
        100 * r["crumpled"],
        twin,
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="10000,100000,1000000")
    parser.add_argument("--tool", default=str(REPO / "build" / "bin" / "developable"))
    parser.add_argument("--md", default=str(REPO / "docs" / "scans.md"))
    parser.add_argument("--json", default=str(REPO / "bench" / "scans.json"))
    parser.add_argument("--keep", action="store_true", help="keep the rows of --json of other sizes")
    parser.add_argument("--render", action="store_true", help="no runs: write --md again from the rows of --json")
    parser.add_argument("--quick", action="store_true", help="two sheets at 2 %% noise and one object per size")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    md, raw = pathlib.Path(args.md), pathlib.Path(args.json)
    rows = []
    info = machine_info()
    if (args.keep or args.render) and raw.exists():
        old = json.loads(raw.read_text())
        rows = [r for r in old["rows"] if args.render or r["size"] not in sizes]
        for r in rows:
            r.setdefault("run", old["machine"]["date"])  # rows written before runs were dated
        if args.render:
            info = old["machine"]
    print(HEADER, flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for kind, name, size, maker in [] if args.render else cases(sizes, args.quick):
            positions, triangles, clean = maker()
            stats, cpu, wall, peak, after = run_case(args.tool, work, positions, triangles)
            twin = twin_distances(positions, after, clean) if clean is not None else (None, None)
            row = {
                "kind": kind,
                "name": name,
                "size": size,
                "faces": int(len(triangles)),
                "cpu_s": cpu,
                "wall_s": wall,
                "peak_bytes": peak,
                "time_decompose_ms": stats["time_decompose_ms"],
                "time_iterate_ms": stats["time_iterate_ms"],
                "time_polish_ms": stats["time_polish_ms"],
                "polish_iterations": stats["polish_iterations"],
                "iterations": stats["iterations"],
                "patches": stats["patches"],
                "origin": stats["result_origin"],
                "result": stats["result"],
                "flat": stats["flat_share_after"],
                "flat_and_ruled": stats["ruled_share_after"],
                "crumpled": stats["crumpled_share_after"],
                "twin_max": twin[0],
                "twin_rms": twin[1],
                "run": info["date"],
            }
            rows.append(row)
            print(table_row(row), flush=True)
    rows.sort(key=lambda r: (r["size"], r["kind"] == "object"))
    fits = {}
    lines = ["CPU seconds fitted as a * faces^b, and each run over its fit:", ""]
    for kind in ("sheet", "object"):
        mine = [r for r in rows if r["kind"] == kind]
        fit = power_fit(mine)
        if fit is None:
            continue
        fits[kind] = {"a": fit[0], "b": fit[1], "at_1e5": fit[0] * 1e5 ** fit[1]}
        ratios = [r["cpu_s"] / (fit[0] * r["faces"] ** fit[1]) for r in mine]
        lines.append(
            "- %s: %.3g s at 100k faces, exponent %.3f; run / fit from %.2f to %.2f"
            % (kind, fits[kind]["at_1e5"], fit[1], min(ratios), max(ratios))
        )
    print("\n".join(lines))
    runs = sorted({(r["size"], r["run"]) for r in rows})
    dated = "; ".join("%d faces: %s" % (size, date) for size, date in runs)
    intro = [
        "# Meshes a user brings: noisy scans (written by bench/scans.py)",
        "",
        "The seeded families (`devkit/families.py`, grid triangulation, seed 7) at noise of 0.5, 2 and 5 %% "
        "of the edge length, and seeded whole objects (`devkit/objects.py`, 1 %% noise), each a separate run "
        "of the command-line tool with the defaults. *CPU s*: the tool's user + system time over all its "
        "threads; wall seconds and stage times (wall) depend on what else ran. *To twin*: the largest and rms "
        "vertex distance to the noise-free surface after the run, each over the input's (1.00: as far from "
        "the true shape as the scan; below 1: noise removed). What the figures mean for the method: "
        "docs/method.md, Known limits. Last run: %s, %s, %d cores, load at the start %s. Rows by size (a "
        "run may keep other sizes' rows, --keep): %s."
        % (info["date"], info["cpu"], info["cores"], info["load_start"], dated),
        "",
    ]
    table = [HEADER, "|" + "---|" * (HEADER.count("|") - 1)] + [table_row(r) for r in rows]
    md.write_text("\n".join(intro + table + [""] + lines) + "\n")
    raw.write_text(json.dumps({"machine": info, "rows": rows, "fits": fits}, indent=1))
    panel = panel_estimate(rows)
    if len(panel) == 2:
        write_estimate(panel, info)
        print("written: addon/core/estimate.py (the panel's estimate)")
    print("written: %s, %s" % (md, raw))


if __name__ == "__main__":
    main()

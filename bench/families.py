"""The family table of issue 11: the engine on seeded random developables
(devkit/families.py) with their noise-free twins, through the command-line
tool with its defaults.

    /usr/bin/python3 bench/families.py                       # build/bin/developable
    /usr/bin/python3 bench/families.py --tool OTHER/bin/developable --label before
    /usr/bin/python3 bench/families.py --write docs/families.md   # (re)writes the table there
    /usr/bin/python3 bench/families.py --noise 0.1-0.5 --tolerance 2 --label "scan noise"   # sheets as scans bring them

Per family and triangulation, over the seeds (default 100-102, not the
tuning seeds 0-9; faces 500-5000 log-uniform, noise 0.5-5 % AE log-uniform, --noise to change):
  dE      mean |defect| change, %: median over the seeds (worst in brackets)
  flat    share of interior vertices with |defect| < 1e-3 rad after: median (lowest)
  f&r     share of interior vertices flat and ruled after (their faces' normals within 0.02 rad
          of one great circle; devkit/measures.py): median (lowest)
  H/H0    Hausdorff distance of the result to the twin over the input's: median (largest)
  twin    the same ratio for the twin itself run through the tool (median, largest): how far
          the noise-free mesh has to move to become developable on these triangles (an
          irregular triangulation of a developable surface is not developable itself), so
          a result that far from the twin moved it no more than the triangles force
  folds   faces turned over (normal > 90 degrees from the input's), summed
  unch.   runs that returned the input unchanged
"""
import argparse
import json
import pathlib
import sys
import tempfile

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from devkit import families
from devkit.distance import sampled_hausdorff
from devkit.measures import developability_figures
from devkit.tool import run_tool


angle_defects = families.angle_defects
face_normals = families.face_normals


def measure(mesh, tool, work, options=()):
    """One run: the figures of the table for one FamilyMesh (and its twin's own run), the tool's
    defaults and `options`."""
    run = run_tool(tool, work, mesh.positions, mesh.triangles, options)
    twin_run = run_tool(tool, work, mesh.clean, mesh.triangles, options)
    if isinstance(run, str) or isinstance(twin_run, str):
        return {"error": run if isinstance(run, str) else twin_run}
    out, stats, seconds = run
    d0, interior = angle_defects(mesh.positions, mesh.triangles)
    d1, _ = angle_defects(out, mesh.triangles)
    e0, e1 = np.abs(d0[interior]).mean(), np.abs(d1[interior]).mean()
    turned = int(
        np.sum(
            np.einsum("ij,ij->i", face_normals(mesh.positions, mesh.triangles), face_normals(out, mesh.triangles)) < 0
        )
    )
    h0 = sampled_hausdorff(mesh.positions, mesh.triangles, mesh.clean, mesh.triangles)
    h1 = sampled_hausdorff(out, mesh.triangles, mesh.clean, mesh.triangles)
    h_twin = sampled_hausdorff(twin_run[0], mesh.triangles, mesh.clean, mesh.triangles)
    return {
        "dE": 100.0 * (e1 - e0) / e0,
        "flat": float(np.mean(np.abs(d1[interior]) < 1e-3)),
        "flat_and_ruled": developability_figures(out, mesh.triangles)["flat_and_ruled"],
        "H_ratio": h1 / max(h0, 1e-300),
        "H_twin_ratio": h_twin / max(h0, 1e-300),
        "turned": turned,
        "unchanged": bool(np.array_equal(out, mesh.positions)) or stats.get("result") == "unchanged",
        "faces": len(mesh.triangles),
        "noise": mesh.noise,
        "seconds": seconds,
    }


def rows_of(results):
    """Aggregated table rows: (family, triangulation) -> summary strings."""
    rows = []
    for (family, triangulation), runs in results.items():
        good = [r for r in runs if "error" not in r]
        if not good:
            rows.append((family, triangulation, "error", "", "", "", "", "", ""))
            continue
        de = np.array([r["dE"] for r in good])
        flat = np.array([r["flat"] for r in good])
        ruled = np.array([r["flat_and_ruled"] for r in good])
        ratio = np.array([r["H_ratio"] for r in good])
        twin = np.array([r["H_twin_ratio"] for r in good])
        rows.append(
            (
                family,
                triangulation,
                "%.1f (%.1f)" % (np.median(de), de.max()),
                "%.0f %% (%.0f %%)" % (100 * np.median(flat), 100 * flat.min()),
                "%.1f %% (%.1f %%)" % (100 * np.median(ruled), 100 * ruled.min()),
                "%.2f (%.2f)" % (np.median(ratio), ratio.max()),
                "%.2f (%.2f)" % (np.median(twin), twin.max()),
                "%d" % sum(r["turned"] for r in good),
                "%d/%d" % (sum(r["unchanged"] for r in good), len(runs)),
            )
        )
    return rows


def summary(results):
    """The distance figures over all cells, one paragraph."""
    cells = [[r for r in runs if "error" not in r] for runs in results.values()]
    cells = [c for c in cells if c]
    largest = np.array([max(r["H_ratio"] for r in c) for c in cells])
    # Within 1.5 times the larger of the noise and what the twin itself had to move.
    forced = sum(all(r["H_ratio"] <= 1.5 * max(1.0, r["H_twin_ratio"]) for r in c) for c in cells)
    return (
        "Mean log of the largest H/H0 per cell %.4f; cells whose largest H/H0 is within 1.5: %d of %d; "
        "whose every run is within 1.5 times the larger of H0 and the twin's own move: %d of %d.\n"
        % (np.mean(np.log(largest)), int(np.sum(largest <= 1.5)), len(cells), forced, len(cells))
    )


def table(rows, label):
    lines = [
        "| family | triangulation | dE % median (worst) | flat median (lowest) | f&r median (lowest) | "
        "H/H0 median (largest) | twin's own H/H0 | folds | unchanged |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "**%s**\n\n" % label + "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", default=str(REPO / "build" / "bin" / "developable"))
    ap.add_argument("--seeds", default="100-102", help="first-last (inclusive)")
    ap.add_argument("--families", default=",".join(families.FAMILIES))
    ap.add_argument("--triangulations", default=",".join(families.TRIANGULATIONS))
    ap.add_argument(
        "--faces",
        default="500-5000",
        help="first-last face count, drawn log-uniform per seed (the issue's range: 500-50000)",
    )
    ap.add_argument(
        "--noise", default="0.005-0.05", help="first-last noise amplitude in AE, drawn log-uniform per seed"
    )
    ap.add_argument(
        "--tolerance",
        type=float,
        help="move limit in average edge lengths instead of the defaults' (--max-move 0 --tolerance X): "
        "above the noise's amplitude for scan noise",
    )
    ap.add_argument("--label", default="this build")
    ap.add_argument("--json", help="also write the raw figures here")
    ap.add_argument(
        "--write",
        help="markdown file whose block between the markers "
        "<!-- families:LABEL --> ... <!-- /families:LABEL --> gets the table",
    )
    args = ap.parse_args()
    first, last = (int(x) for x in args.seeds.split("-"))
    face_range = tuple(int(x) for x in args.faces.split("-"))
    noise_range = tuple(float(x) for x in args.noise.split("-"))
    options = () if args.tolerance is None else ("--max-move", "0", "--tolerance", repr(args.tolerance))
    limit = "defaults" if args.tolerance is None else "move limit %g AE" % args.tolerance
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for family in args.families.split(","):
            for triangulation in args.triangulations.split(","):
                if family == "curved_fold" and triangulation == "irregular":
                    continue
                runs = []
                for seed in range(first, last + 1):
                    mesh = families.random_case(
                        family, seed, faces=face_range, noise=noise_range, triangulations=[triangulation]
                    )
                    runs.append(measure(mesh, args.tool, work, options))
                results[(family, triangulation)] = runs
                print(" | ".join(rows_of({(family, triangulation): runs})[0]), flush=True)
    text = (
        table(
            rows_of(results),
            "%s (seeds %s, %s faces, noise %s AE, %s)" % (args.label, args.seeds, args.faces, args.noise, limit),
        )
        + "\n"
        + summary(results)
    )
    print(text)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps({"%s/%s" % k: v for k, v in results.items()}, indent=1))
    if args.write:
        path = pathlib.Path(args.write)
        old = path.read_text() if path.exists() else ""
        begin, end = "<!-- families:%s -->" % args.label, "<!-- /families:%s -->" % args.label
        block = begin + "\n" + text + end
        if begin in old and end in old:
            new = old[: old.index(begin)] + block + old[old.index(end) + len(end) :]
        else:
            new = old.rstrip("\n") + "\n\n" + block + "\n"
        path.write_text(new)


if __name__ == "__main__":
    main()

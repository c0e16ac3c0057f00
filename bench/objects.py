"""Whole objects nobody tuned for: the command-line tool with its defaults on
devkit/objects.py's seeded random closed objects (blobs, rounded boxes, tori, limbs;
1k-20k faces, every other seed with scan noise).

    /usr/bin/python3 bench/objects.py                      # seeds 100-109, build/bin/developable
    /usr/bin/python3 bench/objects.py --tool OTHER/bin/developable --seeds 0-9

Per kind, over the seeds: the runs that came back improved (the others are returned
unchanged, with the reason the tool prints), the flat share (interior vertices with
|defect| < 1e-3 rad) and the flat and ruled share (flat, and their faces' normals on one great
circle: not crumpled) before -> after (median over the improved runs), the flat and ruled share
inside the pieces the tool reports (off their seams: issue 35's measure; median and lowest over
the improved runs) and the share of the interior vertices off the seams (median), the pieces
(median, largest), the mean |defect|
change (median and largest over the improved runs: a closed surface keeps its total
curvature, so it may grow up to 5 %, said), the Hausdorff distance to the input in % of the
bounding box diagonal (largest), faces turned over (> 90 degrees from the input's normal,
summed), edges whose angle grew by more than 90 degrees (summed; on seams between patches,
where the curvature gathers) and the seconds per run (median, largest).
"""
import argparse
import json
import pathlib
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from devkit import objects
from devkit.distance import bbox_diagonal, sampled_hausdorff
from devkit.measures import developability_figures, face_normals, seam_vertices, sharpened_edges
from devkit.tool import run_tool_report


def measure(job):
    tool, kind, seed = job
    m = objects.random_case(kind, seed)
    with tempfile.TemporaryDirectory() as work:
        run = run_tool_report(tool, pathlib.Path(work), m.positions, m.triangles)
    if isinstance(run, str):
        return {"kind": kind, "seed": seed, "error": run}
    after, report, seconds = run
    stats = report["stats"]
    off_seams = ~seam_vertices(len(after), m.triangles, np.asarray(report["patch_ids"]))
    inside = developability_figures(after, m.triangles, interior=off_seams)
    turned = np.einsum("ij,ij->i", face_normals(m.positions, m.triangles), face_normals(after, m.triangles)) < 0
    return {
        "kind": kind,
        "seed": seed,
        "faces": len(m.triangles),
        "noise": m.noise,
        "seconds": seconds,
        "improved": stats["result"] == "improved",
        "patches": stats["patches"],
        "flat_before": stats["flat_share_before"],
        "flat_after": stats["flat_share_after"],
        "ruled_before": stats["ruled_share_before"],
        "ruled_after": stats["ruled_share_after"],
        "ruled_inside": inside["flat_and_ruled"],
        "off_seams": inside["vertices"] / stats["interior_vertices"],
        "change": stats["change_percent"],
        "hausdorff": sampled_hausdorff(after, m.triangles, m.positions, m.triangles) / bbox_diagonal(m.positions),
        "turned": int(turned.sum()),
        "folded": len(sharpened_edges(m.positions, after, m.triangles, growth_degrees=90.0 + 1e-6)),
    }


def table(results, title):
    lines = [
        "**%s**" % title,
        "",
        "| kind | improved | flat before → after (median) | flat and ruled before → after (median) "
        "| flat and ruled inside the pieces (median, lowest) | off the seams | pieces (median, largest) "
        "| mean \\|defect\\| % (median, largest) | Hausdorff % diag (largest) | turned | folded edges "
        "| seconds (median, largest) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind in objects.KINDS:
        runs = [r for r in results if r["kind"] == kind and "error" not in r]
        better = [r for r in runs if r["improved"]] or runs
        # nanmedian: an object whose every interior vertex lies on a seam has no inside share.
        med = lambda key: float(np.nanmedian([r[key] for r in better]))  # noqa: E731
        lines.append(
            "| %s | %d/%d | %.0f → %.0f %% | %.0f → %.0f %% | %.0f %% (%.0f) | %.0f %% | %.0f (%d) "
            "| %+.1f (%+.1f) | %.2f | %d | %d | %.1f (%.1f) |"
            % (
                kind,
                sum(r["improved"] for r in runs),
                len(runs),
                100 * med("flat_before"),
                100 * med("flat_after"),
                100 * med("ruled_before"),
                100 * med("ruled_after"),
                100 * med("ruled_inside"),
                100 * np.nanmin([r["ruled_inside"] for r in better]),
                100 * med("off_seams"),
                med("patches"),
                max(r["patches"] for r in better),
                med("change"),
                max(r["change"] for r in better),
                100 * max(r["hausdorff"] for r in runs),
                sum(r["turned"] for r in runs),
                sum(r["folded"] for r in runs),
                float(np.median([r["seconds"] for r in runs])),
                max(r["seconds"] for r in runs),
            )
        )
    seams_only = [r for r in results if "error" not in r and np.isnan(r["ruled_inside"])]
    if seams_only:
        lines += [
            "",
            "Every interior vertex on a seam (no inside share): "
            + ", ".join("%s %d" % (r["kind"], r["seed"]) for r in seams_only),
        ]
    errors = [r for r in results if "error" in r]
    if errors:
        lines += ["", "Errors: " + "; ".join("%s %d: %s" % (r["kind"], r["seed"], r["error"]) for r in errors)]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", default=str(REPO / "build" / "bin" / "developable"))
    ap.add_argument("--seeds", default="100-109", help="first-last (inclusive)")
    ap.add_argument("--json", help="also write every run's figures here")
    args = ap.parse_args()
    first, last = (int(s) for s in args.seeds.split("-"))
    jobs = [(args.tool, kind, seed) for kind in objects.KINDS for seed in range(first, last + 1)]
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(measure, jobs))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(results, indent=1))
    print(table(results, "Random whole objects, seeds %s, the tool's defaults" % args.seeds))


if __name__ == "__main__":
    main()

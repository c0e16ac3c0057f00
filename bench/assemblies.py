"""Sheet-metal assemblies of issue 35 through the command-line tool with its defaults: does the
engine find the natural pieces, keep the creases between them, and come back developable in
the honest sense, flat AND ruled, and near the noise-free twin?

    /usr/bin/python3 bench/assemblies.py                         # build/bin/developable, seeds 100-104
    /usr/bin/python3 bench/assemblies.py --tool OTHER/bin/developable --seeds 0-9
    /usr/bin/python3 bench/assemblies.py --scan                  # sheets with scan noise instead

Assemblies (devkit/assemblies.py random_case: 1000-8000 faces log-uniform, noise 0.5-5 % AE
log-uniform, the triangulation drawn too, all from the seed), a table per part with a row per
seed, then one row per part over the seeds:
  pieces      the patches of the tool's report (the natural count in the part's heading);
              exact: the runs that found exactly the natural count. The square-to-round's 8
              pieces (4 triangles, 4 cones) are tangent along their seams, flat and ruled there
              too: one patch is as right for it
  H/H0        sampled Hausdorff distance of the result to the noise-free twin over the noisy
              input's: below 1 the noise was removed, above it the shape moved
  flat, f&r   shares of the vertices strictly inside the natural pieces (off the seams) with
              |angle defect| < 1e-3 rad, and flat and ruled too (ruled_spread < 0.02 rad,
              devkit/measures.py), before -> after; the twin has 100 % of both
  crease      the mean angle between the face normals across the true seam edges in the result
              over the twin's: 1 kept, well below 1 rounded off (a fillet), above 1 sharpened
              (the noise alone raises it: the input's figure is in brackets). The
              square-to-round's seams are tangent (the twin's angle is the facets' own),
              so its figure is mostly noise
  seconds     the tool's wall time (two runs at once by default, --jobs)

--scan: devkit/assemblies.py random_scan_sheet, every family of devkit/families.py with noise
10-50 % of the edge length (log-uniform), one row per family over the seeds: flat, flat and
ruled, crumpled (flat but not ruled) shares of the interior vertices after (median, worst),
the root mean square distance of the vertices to the twin's and the Hausdorff distance to the
twin, each over the input's (median, largest), seconds. An irregular triangulation of a curved
family is not developable itself (families.py), so its twin is no lower bound there.
"""
import argparse
import pathlib
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from devkit import assemblies, families  # noqa: E402
from devkit.distance import sampled_hausdorff  # noqa: E402
from devkit.measures import developability_figures, dihedral_angles  # noqa: E402
from devkit.tool import run_tool  # noqa: E402


def inside_pieces(mesh):
    """Vertices whose faces all belong to one natural piece."""
    n = len(mesh.clean)
    low, high = np.full(n, np.iinfo(np.int32).max), np.full(n, -1)
    for corner in range(3):
        np.minimum.at(low, mesh.triangles[:, corner], mesh.pieces)
        np.maximum.at(high, mesh.triangles[:, corner], mesh.pieces)
    return low == high


def run(tool, mesh):
    """(result positions, stats, seconds) of the tool on the noisy mesh, or its error text."""
    with tempfile.TemporaryDirectory() as work:
        return run_tool(tool, pathlib.Path(work), mesh.positions, mesh.triangles)


def measure_assembly(job):
    tool, part, seed = job
    m = assemblies.random_case(part, seed)
    row = {"part": part, "seed": seed, "triangulation": m.triangulation, "faces": len(m.triangles), "noise": m.noise}
    result = run(tool, m)
    if isinstance(result, str):
        return dict(row, error=result)
    out, stats, seconds = result
    inside = inside_pieces(m)
    before = developability_figures(m.positions, m.triangles, interior=inside)
    after = developability_figures(out, m.triangles, interior=inside)
    crease = None
    if len(m.creases):
        twin = dihedral_angles(m.clean, m.triangles, m.creases).mean()
        crease = (
            dihedral_angles(out, m.triangles, m.creases).mean() / twin,
            dihedral_angles(m.positions, m.triangles, m.creases).mean() / twin,
        )
    h0 = sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
    return dict(
        row,
        natural=m.natural_pieces,
        pieces=stats["patches"],
        result=stats["result"],
        H=sampled_hausdorff(out, m.triangles, m.clean, m.triangles) / h0,
        flat=(before["flat"], after["flat"]),
        ruled=(before["flat_and_ruled"], after["flat_and_ruled"]),
        crease=crease,
        seconds=seconds,
    )


def measure_scan(job):
    tool, family, seed = job
    m = assemblies.random_scan_sheet(family, seed)
    row = {
        "family": family,
        "seed": seed,
        "triangulation": m.triangulation,
        "faces": len(m.triangles),
        "noise": m.noise,
    }
    result = run(tool, m)
    if isinstance(result, str):
        return dict(row, error=result)
    out, stats, seconds = result
    after = developability_figures(out, m.triangles)

    def rms(p):
        return np.sqrt(np.mean(np.sum((p - m.clean) ** 2, axis=1)))

    return dict(
        row,
        result=stats["result"],
        flat=after["flat"],
        ruled=after["flat_and_ruled"],
        crumpled=after["crumpled"],
        rms=rms(out) / rms(m.positions),
        H=(
            sampled_hausdorff(out, m.triangles, m.clean, m.triangles)
            / sampled_hausdorff(m.positions, m.triangles, m.clean, m.triangles)
        ),
        flat_before=developability_figures(m.positions, m.triangles)["flat"],
        seconds=seconds,
    )


def percent(x):
    return "–" if np.isnan(x) else "%.0f %%" % (100 * x)


def part_table(part, runs):
    good = [r for r in runs if "error" not in r]
    natural = assemblies.NATURAL_PIECES[part]
    lines = [
        "**%s** (natural pieces: %d; exact: %d of %d runs)"
        % (part, natural, sum(r["pieces"] == natural for r in good), len(runs)),
        "",
        "| seed | triangulation | faces | noise % AE | pieces | H/H0 | flat before → after "
        "| flat & ruled before → after | crease kept (input) | seconds | result |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in runs:
        if "error" in r:
            lines.append(
                "| %d | %s | %d | %.1f | error: %s |"
                % (r["seed"], r["triangulation"], r["faces"], 100 * r["noise"], r["error"])
            )
            continue
        crease = "–" if r["crease"] is None else "%.2f (%.2f)" % r["crease"]
        lines.append(
            "| %d | %s | %d | %.1f | %d | %.2f | %s → %s | %s → %s | %s | %.1f | %s |"
            % (
                r["seed"],
                r["triangulation"],
                r["faces"],
                100 * r["noise"],
                r["pieces"],
                r["H"],
                percent(r["flat"][0]),
                percent(r["flat"][1]),
                percent(r["ruled"][0]),
                percent(r["ruled"][1]),
                crease,
                r["seconds"],
                r["result"],
            )
        )
    return "\n".join(lines) + "\n"


def summary_table(results, parts):
    lines = [
        "**All parts** (median over the seeds, worst in brackets)",
        "",
        "| part | natural pieces | pieces returned | exact | H/H0 | flat after | flat & ruled after "
        "| crease kept | seconds |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for part in parts:
        good = [r for r in results if r["part"] == part and "error" not in r]
        if not good:
            lines.append("| %s | %d | error |" % (part, assemblies.NATURAL_PIECES[part]))
            continue
        h = [r["H"] for r in good]
        flat, ruled = [r["flat"][1] for r in good], [r["ruled"][1] for r in good]
        crease = [r["crease"][0] for r in good if r["crease"] is not None]
        lines.append(
            "| %s | %d | %s | %d/%d | %.2f (%.2f) | %s (%s) | %s (%s) | %s | %.1f (%.1f) |"
            % (
                part,
                assemblies.NATURAL_PIECES[part],
                ", ".join(str(r["pieces"]) for r in good),
                sum(r["pieces"] == r["natural"] for r in good),
                sum(r["part"] == part for r in results),
                np.median(h),
                max(h),
                percent(np.median(flat)),
                percent(min(flat)),
                percent(np.median(ruled)),
                percent(min(ruled)),
                "%.2f (%.2f)" % (np.median(crease), min(crease)) if crease else "–",
                np.median([r["seconds"] for r in good]),
                max(r["seconds"] for r in good),
            )
        )
    return "\n".join(lines) + "\n"


def scan_table(results, names):
    lines = [
        "**Sheets with scan noise 10-50 % AE** (median over the seeds, worst in brackets)",
        "",
        "| family | triangulations | noise % AE | flat before | flat after | flat & ruled after "
        "| crumpled after | rms/rms0 | H/H0 | seconds | unchanged |",
        "|---" * 11 + "|",
    ]
    for family in names:
        runs = [r for r in results if r["family"] == family]
        good = [r for r in runs if "error" not in r]
        if not good:
            lines.append("| %s | error: %s |" % (family, runs[0]["error"]))
            continue

        def col(key, worst, fmt):
            values = [r[key] for r in good]
            return "%s (%s)" % (fmt(np.median(values)), fmt(worst(values)))

        lines.append(
            "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %.1f (%.1f) | %d/%d |"
            % (
                family,
                ", ".join(sorted({r["triangulation"] for r in good})),
                "-".join("%.0f" % (100 * f(r["noise"] for r in good)) for f in (min, max)),
                percent(np.median([r["flat_before"] for r in good])),
                col("flat", min, percent),
                col("ruled", min, percent),
                col("crumpled", max, percent),
                col("rms", max, lambda x: "%.2f" % x),
                col("H", max, lambda x: "%.2f" % x),
                np.median([r["seconds"] for r in good]),
                max(r["seconds"] for r in good),
                sum(r["result"] == "unchanged" for r in good),
                len(runs),
            )
        )
    errors = [r for r in results if "error" in r]
    if errors:
        lines += ["", "Errors: " + "; ".join("%s %d: %s" % (r["family"], r["seed"], r["error"]) for r in errors)]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", default=str(REPO / "build" / "bin" / "developable"))
    ap.add_argument("--seeds", default="100-104", help="first-last (inclusive)")
    ap.add_argument("--parts", default=",".join(assemblies.PARTS))
    ap.add_argument("--scan", action="store_true", help="sheets of every family with scan noise instead")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once")
    args = ap.parse_args()
    first, last = (int(s) for s in args.seeds.split("-"))
    names = list(families.FAMILIES) if args.scan else args.parts.split(",")
    jobs = [(args.tool, name, seed) for name in names for seed in range(first, last + 1)]
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(measure_scan if args.scan else measure_assembly, jobs))
    if args.scan:
        print(scan_table(results, names))
        return
    for part in names:
        print(part_table(part, [r for r in results if r["part"] == part]))
    print(summary_table(results, names))


if __name__ == "__main__":
    main()

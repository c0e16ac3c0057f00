"""Two builds of the command-line tool side by side on held-out family meshes of a size the
family table does not draw (issue 38: 10k-40k faces by default), with the defaults.

    /usr/bin/python3 bench/tool_pair.py BEFORE/bin/developable AFTER/bin/developable
                                        [--seeds 101] [--faces 10000-40000] [--noise 0.005-0.05]
                                        [--json OUT.json] [--md OUT.md]

Every family and triangulation of devkit/families.py per seed, its face count and noise drawn
log-uniform from the seed (the same meshes for both builds). Per run: the tool's CPU seconds
(user + system, all threads), the result's origin, flat and flat-and-ruled shares, and the largest
and rms distance to the noise-free twin over the input's. At the end, per build: the summed CPU
seconds, the mean log Hausdorff ratio, the largest ratio, the runs above 1.5 and the lowest
flat-and-ruled share; then the runs where one build is more than 10 % farther from the twin.
Two runs at a time on the 2-core machine: seconds are comparable between the builds, not with
an idle machine."""
import argparse
import json
import pathlib
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "bench"))
from devkit import families  # noqa: E402
from scans import run_case, twin_distances  # noqa: E402


def drawn(family, triangulation, seed, faces, noise):
    """The face count and noise (AE) of one held-out run, log-uniform from the seed."""
    rng = np.random.default_rng(
        [seed, 77, families.FAMILIES.index(family), families.TRIANGULATIONS.index(triangulation)]
    )
    count = int(np.exp(rng.uniform(np.log(faces[0]), np.log(faces[1]))))
    return count, float(np.exp(rng.uniform(np.log(noise[0]), np.log(noise[1]))))


def one_run(job):
    family, triangulation, seed, faces, noise, build, tool = job
    count, amplitude = drawn(family, triangulation, seed, faces, noise)
    mesh = families.make(family, triangulation, faces=count, noise=amplitude, seed=seed)
    with tempfile.TemporaryDirectory() as work:
        stats, cpu, _, _, out = run_case(tool, pathlib.Path(work), mesh.positions, mesh.triangles)
    largest, rms = twin_distances(mesh.positions, out, mesh.clean)
    return {
        "family": family,
        "triangulation": triangulation,
        "seed": seed,
        "build": build,
        "faces": len(mesh.triangles),
        "noise": amplitude,
        "cpu_s": cpu,
        "origin": stats["result_origin"],
        "flat": stats["flat_share_after"],
        "flat_and_ruled": stats["ruled_share_after"],
        "H": largest,
        "rms": rms,
    }


def summary(rows, builds):
    lines = [
        "| build | runs | CPU s | mean log H/H0 | largest H/H0 | runs above 1.5 | lowest flat & ruled |",
        "|---|---|---|---|---|---|---|",
    ]
    for build in builds:
        runs = [r for r in rows if r["build"] == build]
        h = np.array([r["H"] for r in runs])
        lines.append(
            "| %s | %d | %.1f | %.3f | %.2f | %d | %.1f %% |"
            % (
                build,
                len(runs),
                sum(r["cpu_s"] for r in runs),
                np.log(h).mean(),
                h.max(),
                (h > 1.5).sum(),
                100 * min(r["flat_and_ruled"] for r in runs),
            )
        )
    key = lambda r: (r["family"], r["triangulation"], r["seed"])  # noqa: E731
    first = {key(r): r for r in rows if r["build"] == builds[0]}
    lines += [
        "",
        "| family | triangulation | seed | faces | H/H0 %s | %s | origin %s | %s |"
        % (builds[0], builds[1], builds[0], builds[1]),
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["build"] != builds[1] or key(r) not in first:
            continue
        b = first[key(r)]
        if r["H"] > 1.1 * b["H"] or b["H"] > 1.1 * r["H"]:
            lines.append(
                "| %s | %s | %d | %d | %.2f | %.2f | %s | %s |"
                % (*key(r), r["faces"], b["H"], r["H"], b["origin"], r["origin"])
            )
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--seeds", default="101", help="first-last (inclusive)")
    parser.add_argument("--faces", default="10000-40000")
    parser.add_argument("--noise", default="0.005-0.05", help="first-last amplitude in AE")
    parser.add_argument("--json")
    parser.add_argument("--md")
    args = parser.parse_args()
    first, last = (int(x) for x in args.seeds.split("-")) if "-" in args.seeds else (int(args.seeds),) * 2
    faces = tuple(int(x) for x in args.faces.split("-"))
    noise = tuple(float(x) for x in args.noise.split("-"))
    builds = ("before", "after")
    jobs = [
        (family, triangulation, seed, faces, noise, build, tool)
        for seed in range(first, last + 1)
        for family in families.FAMILIES
        for triangulation in families.TRIANGULATIONS
        if not (family == "curved_fold" and triangulation == "irregular")
        for build, tool in zip(builds, (args.before, args.after))
    ]
    rows = []
    with ProcessPoolExecutor(2) as pool:
        for r in pool.map(one_run, jobs):
            rows.append(r)
            print(
                "%-20s %-11s %d %6d %-6s cpu %6.2f %-22s flat %.3f f&r %.3f H %.2f rms %.2f"
                % (
                    r["family"],
                    r["triangulation"],
                    r["seed"],
                    r["faces"],
                    r["build"],
                    r["cpu_s"],
                    r["origin"],
                    r["flat"],
                    r["flat_and_ruled"],
                    r["H"],
                    r["rms"],
                ),
                flush=True,
            )
    table = summary(rows, builds)
    print(table)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1))
    if args.md:
        pathlib.Path(args.md).write_text(table)


if __name__ == "__main__":
    main()

"""Which outputs of the engine a change alters: the command-line tool with its defaults on
the shared meshes, the seeded families (devkit/families.py) and the seeded closed objects
(devkit/objects.py), each output hashed bit for bit with the figures a user sees.

    /usr/bin/python3 bench/regression.py record OUT.json [--tool build/bin/developable]
    /usr/bin/python3 bench/regression.py compare BEFORE.json AFTER.json

The families run every triangulation of seeds 100-102 (the held-out seeds of
tests/test_families.py) and the triangulation each seed draws (bench/families.py's). `record` writes one row per mesh: a hash of the output positions, the result (improved or
unchanged), which candidate made it, the flat share, the mean and largest |defect|, the
largest move and the seconds. `compare` lists the meshes whose output changed, with both
rows' figures side by side, and says whether any figure the user sees got worse. A
restructuring that should change nothing shows "0 of N outputs changed"."""
import argparse
import hashlib
import json
import pathlib
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from devkit import families, objects
from devkit.obj import read_obj
from devkit.paths import MESHES
from devkit.distance import sampled_hausdorff
from devkit.tool import run_tool

FAMILY_SEEDS = (100, 101, 102)
OBJECT_SEEDS = (100, 101, 102)
# Shared meshes of more than a few seconds (boat, mountain, dress_high) are left to
# bench/run.py: this harness is run before and after every change of the decisions.
SHARED = (
    "bunny",
    "cube_no_bottom",
    "fish_low_resolution",
    "hand_lowres",
    "human_woman",
    "penguin",
    "sphere",
    "spot_low_resolution",
    "torus",
    "wingnut",
)


def cases():
    """(name, maker) of every mesh, in a fixed order."""
    out = [("shared/" + name, ("shared", name)) for name in SHARED]
    for family in families.FAMILIES:
        for triangulation in families.TRIANGULATIONS:
            if family == "curved_fold" and triangulation == "irregular":
                continue  # families.random_case does not make it
            for seed in FAMILY_SEEDS:
                out.append(("family/%s/%s/%d" % (family, triangulation, seed), ("family", family, seed, triangulation)))
        for seed in FAMILY_SEEDS:  # the triangulation drawn from the seed, as bench/families.py draws it
            out.append(("family/%s/drawn/%d" % (family, seed), ("family", family, seed, None)))
    for kind in objects.KINDS:
        for seed in OBJECT_SEEDS:
            out.append(("object/%s/%d" % (kind, seed), ("object", kind, seed)))
    return out


def mesh_of(maker):
    """(positions, triangles, noise-free twin or None)."""
    if maker[0] == "shared":
        return read_obj(MESHES / (maker[1] + ".obj")) + (None,)
    if maker[0] == "family":
        m = families.random_case(maker[1], maker[2], triangulations=[maker[3]] if maker[3] else None)
        return m.positions, m.triangles, m.clean
    m = objects.random_case(maker[1], maker[2])
    return m.positions, m.triangles, None


def record_one(job):
    tool, name, maker = job
    positions, triangles, twin = mesh_of(maker)
    with tempfile.TemporaryDirectory() as work:
        run = run_tool(tool, pathlib.Path(work), positions, triangles)
    if isinstance(run, str):
        return name, {"error": run}
    out, stats, seconds = run
    # The families' distance to their noise-free twin over the input's (bench/families.py's H/H0).
    twin_ratio = None
    if twin is not None:
        twin_ratio = sampled_hausdorff(out, triangles, twin, triangles) / max(
            sampled_hausdorff(positions, triangles, twin, triangles), 1e-300
        )
    return name, {
        "hash": hashlib.sha1(np.ascontiguousarray(out, dtype=np.float64).tobytes()).hexdigest()[:16],
        "result": stats.get("result"),
        "origin": stats.get("result_origin", ""),
        "patches": stats.get("patches"),
        "flat": stats.get("flat_share_after"),
        "mean": stats.get("mean_defect_after"),
        "max": stats.get("max_defect_after"),
        "move": stats.get("max_vertex_move"),
        "ruled": stats.get("ruled_share_after"),
        "seconds": round(seconds, 3),
        "twin_ratio": twin_ratio,
    }


def record(args):
    jobs = [(args.tool, name, maker) for name, maker in cases() if args.only in name]
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = dict(pool.map(record_one, jobs))
    pathlib.Path(args.out).write_text(json.dumps(rows, indent=1, sort_keys=True))
    print("%d outputs recorded in %s" % (len(rows), args.out))


def worse(a, b):
    """The figures of row b that a user sees worse than in row a."""
    out = []
    if a.get("result") == "improved" and b.get("result") != "improved":
        out.append("no longer improved")
    if (b.get("flat") or 0) < (a.get("flat") or 0) - 1e-12:
        out.append("flat share")
    if (b.get("mean") or 0) > (a.get("mean") or 0) * (1 + 1e-9):
        out.append("mean |defect|")
    if (b.get("max") or 0) > (a.get("max") or 0) * (1 + 1e-9):
        out.append("largest |defect|")
    if (b.get("ruled") or 0) < (a.get("ruled") or 0) - 1e-12:
        out.append("flat and ruled share")
    if a.get("twin_ratio") and b.get("twin_ratio") and b["twin_ratio"] > a["twin_ratio"] * (1 + 1e-9):
        out.append("distance to the twin %.2f -> %.2f" % (a["twin_ratio"], b["twin_ratio"]))
    return out


def compare(args):
    before = json.loads(pathlib.Path(args.before).read_text())
    after = json.loads(pathlib.Path(args.after).read_text())
    changed = [k for k in before if k in after and before[k].get("hash") != after[k].get("hash")]
    print("%d of %d outputs changed" % (len(changed), len(before)))
    fmt = "%-34s %-9s %-22s flat %6s -> %6s  mean %9s -> %9s  max %7s -> %7s  %s"
    for k in changed:
        a, b = before[k], after[k]
        if "error" in a or "error" in b:
            print("%-34s %s -> %s" % (k, a.get("error", "ok"), b.get("error", "ok")))
            continue
        pct = lambda x: "%.1f%%" % (100 * x) if x is not None else "-"  # noqa: E731
        num = lambda x: "%.3g" % x if x is not None else "-"  # noqa: E731
        print(
            fmt
            % (
                k,
                b["result"],
                b.get("origin", ""),
                pct(a["flat"]),
                pct(b["flat"]),
                num(a["mean"]),
                num(b["mean"]),
                num(a["max"]),
                num(b["max"]),
                ", ".join(worse(a, b)) or "no figure worse",
            )
        )
    for k in sorted(set(before) ^ set(after)):
        print("%-34s only in %s" % (k, "before" if k in before else "after"))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record")
    rec.add_argument("out")
    rec.add_argument("--tool", default=str(REPO / "build" / "bin" / "developable"))
    rec.add_argument("--jobs", type=int, default=2)
    rec.add_argument("--only", default="", help="record only the meshes whose name contains this")
    cmp_ = sub.add_parser("compare")
    cmp_.add_argument("before")
    cmp_.add_argument("after")
    args = parser.parse_args()
    record(args) if args.command == "record" else compare(args)


if __name__ == "__main__":
    main()

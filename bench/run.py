#!/usr/bin/env python3
"""Benchmarks of the developable engine: one command writes docs/benchmarks.md
and the docs/bench-*.png plots.

    /usr/bin/python3 bench/run.py                 # everything (about 20-30 min on 2 cores)
    /usr/bin/python3 bench/run.py --quick         # a small slice (< 1 min), for CI
    /usr/bin/python3 bench/run.py --compare 'OTHER_TOOL {in} {out}'
                                                  # adds the other tool's rows, same metrics
    /usr/bin/python3 bench/run.py --quick --out /tmp/b   # write somewhere else than docs/

Every case runs in its own subprocess (bench/worker.py) so that its peak
memory is its own; the cases run one after another so that they do not share
the two cores. Build first: cmake -S . -B build && cmake --build build -j2."""
import argparse
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(REPO))  # devkit

import report
from devkit import meshes
from devkit.machine import load_average, machine_info
from devkit.obj import write_obj
from devkit.paths import MESHES as SHARED

SIZES = [1_000, 10_000, 100_000, 1_000_000]
FAMILIES = ["cylinder", "cone", "gcone"]
E_ALLOW = [0.02, 0.33, 10.0]
OMEGAS = [5.0, 15.0]
QUICK_SHARED = ["cube_no_bottom.obj"]


def log(message):
    print("[bench %s] %s" % (time.strftime("%H:%M:%S"), message), flush=True)


# ---------------------------------------------------------------- cases

# The < 50 ms target's setup of the curved cone in the paper tables (the issue's:
# refit mode, boundary pinned, E_allow 10 AE, omega 5).
PINNED_CONE = ("curved_cone", "refit", 10.0, 5.0)


def target_repeat(args):
    """Runs of a case a speed target is judged on: their median. Small runs
    here vary by tens of percent with the machine's load (the pinned curved
    cone 37-55 ms from run to run), so three runs decide by chance."""
    return 1 if args.quick else max(args.repeat, 7)


def plan(args):
    """The list of cases: dicts with section, label, mesh spec, params."""
    cases = []
    shared = []
    if SHARED.is_dir():
        names = sorted(p.name for p in SHARED.glob("*.obj"))
        shared = [n for n in names if n in QUICK_SHARED] if args.quick else names
    sizes = [1_000] if args.quick else [s for s in SIZES if s <= args.max_faces]
    families = ["cylinder"] if args.quick else FAMILIES

    def add(section, label, mesh, params=None, **extra):
        case = {"section": section, "label": label, "mesh": mesh, "params": params or {}}
        case.update(extra)
        cases.append(case)

    # Paper's Tables I and II first: small, and what the paper reports.
    for name, title in (("curved_cone", "curved cone"), ("skirt", "skirt")):
        combos = [(e, w) for e in E_ALLOW for w in OMEGAS]
        if args.quick:
            combos = [(0.02, 15.0), (10.0, 5.0)] if name == "curved_cone" else [(0.33, 5.0), (10.0, 5.0)]
        for mode in ("paper", "refit"):
            for e_allow, omega in combos:
                add(
                    "paper_tables",
                    title,
                    {"named": name},
                    {"mode": mode, "tolerance": e_allow, "max_move": 0.0, "omega": omega, "pin_boundary": 1},
                    table=name,
                    e_allow=e_allow,
                    omega=omega,
                    mode=mode,
                    repeat=target_repeat(args) if (name, mode, e_allow, omega) == PINNED_CONE else args.repeat,
                )
    # The paper's two models with the defaults (the < 50 ms target), then the real meshes.
    for name, title in (("curved_cone", "curved cone"), ("skirt", "skirt")):
        add("real", title, {"named": name}, repeat=target_repeat(args))
    for name in shared:
        add("real", name[:-4], {"file": str(SHARED / name)}, repeat=args.repeat)
    # Generated meshes of growing size, defaults (1M last: the slowest).
    for faces in sizes:
        for family in families:
            add(
                "scaling",
                "%s %s" % (family, faces),
                {"family": family, "faces": faces},
                family=family,
                target_faces=faces,
                repeat=args.repeat if faces <= 20_000 else 1,
            )
    # Modes and segmentation: the curved cone, the skirt, the real meshes and the 10k meshes.
    mode_meshes = [("curved cone", {"named": "curved_cone"})]
    if not args.quick:
        mode_meshes.append(("skirt", {"named": "skirt"}))
    mode_meshes += [(n[:-4], {"file": str(SHARED / n)}) for n in shared]
    if not args.quick:
        mode_meshes += [("%s 10000" % f, {"family": f, "faces": 10_000}) for f in families]
    variants = [
        ("refit, seg auto", {}),
        ("paper, seg auto", {"mode": "paper"}),
        ("refit, seg on", {"segmentation": 1}),
        ("refit, seg off", {"segmentation": 0}),
    ]
    for label, mesh in mode_meshes:
        for variant, params in variants:
            add("modes", label, mesh, params, variant=variant)
    if args.compare:
        compare_meshes = [("curved cone", {"named": "curved_cone"})]
        if not args.quick:
            compare_meshes.append(("skirt", {"named": "skirt"}))
        compare_meshes += [(n[:-4], {"file": str(SHARED / n)}) for n in shared]
        compare_meshes += [
            ("%s %s" % (f, s), {"family": f, "faces": s})
            for s in sizes
            for f in families
            if s <= args.compare_max_faces
        ]
        for label, mesh in compare_meshes:
            add("compare", label, mesh, compare=args.compare)
    return cases


def case_key(case):
    keep = {k: case.get(k) for k in ("section", "label", "mesh", "params", "compare", "repeat")}
    return json.dumps(keep, sort_keys=True)


def run_case(case, library, timeout):
    job = dict(case)
    job["library"] = str(library)
    job.setdefault("hausdorff", True)
    repeat = max(1, int(case.get("repeat") or 1))
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(
                [sys.executable, str(HERE / "worker.py"), json.dumps(job)],
                capture_output=True,
                text=True,
                timeout=timeout,
            )
        except subprocess.TimeoutExpired:
            return {"error": "timed out after %d s" % timeout}
        if proc.returncode != 0 or not proc.stdout.strip():
            tail = (proc.stderr or "").strip().splitlines()[-3:]
            return {"error": "worker exit %d: %s" % (proc.returncode, " | ".join(tail))}
        row = json.loads(proc.stdout.strip().splitlines()[-1])
        row["case_seconds"] = time.perf_counter() - t0
        if "error" in row:
            return row
        runs.append(row)
        job["hausdorff"] = False  # the same numbers again: only the timings differ
    row = runs[0]
    if len(runs) > 1:
        for key in ("t_D", "t_I", "t_T", "wall_ms", "cpu_ms"):
            if key in row:
                values = sorted(r[key] for r in runs)
                row[key] = values[len(values) // 2]  # median
                row[key + "_all"] = values
        row["peak_mib"] = max(r["peak_mib"] for r in runs)
        row["repeats"] = len(runs)
    return row


# ---------------------------------------------------------------- profile


def run_profiles(args, workdir):
    import profile as callgrind

    if not callgrind.available():
        return {"skipped": "valgrind or callgrind_annotate not found"}
    # One profile build per checkout: CMake refuses a build folder another source made.
    checkout = hashlib.sha1(str(REPO).encode()).hexdigest()[:8]
    build_dir = pathlib.Path(tempfile.gettempdir()) / ("developable-bench-profile-build-" + checkout)
    log("profile: building the engine with -g into %s" % build_dir)
    tool = callgrind.build(build_dir)
    out = {"cases": []}
    targets = [
        ("curved cone (720 v, 1280 f), defaults", {"named": "curved_cone"}, ()),
        (
            "curved cone, paper mode, E_allow 10 AE, omega 5, boundary pinned",
            {"named": "curved_cone"},
            ("--mode", "paper", "--tolerance", "10", "--max-move", "0", "--omega", "5", "--pin-boundary"),
        ),
    ]
    if not args.quick:
        targets.append(("noisy cylinder, 100k faces, defaults", {"family": "cylinder", "faces": 100_000}, ()))
    for title, spec, extra in targets:
        log("profile: callgrind on %s" % title)
        positions, triangles = meshes.load(spec)
        with tempfile.TemporaryDirectory(prefix="bench-profile-") as tmp:
            obj = pathlib.Path(tmp) / "mesh.obj"
            write_obj(obj, positions, triangles)
            t0 = time.perf_counter()
            try:
                result = callgrind.profile(tool, obj, extra)
            except subprocess.CalledProcessError as error:
                out["cases"].append({"title": title, "error": str(error)})
                continue
        result["title"] = title
        result["v"], result["f"] = len(positions), len(triangles)
        result["seconds"] = time.perf_counter() - t0
        out["cases"].append(result)
    return out


# ---------------------------------------------------------------- main


def main(argv=None):
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "--quick", action="store_true", help="a small fast slice (CI smoke test): a few small meshes, no profile"
    )
    parser.add_argument(
        "--out", default=str(REPO / "docs"), help="folder for benchmarks.md and bench-*.png (default docs/)"
    )
    parser.add_argument(
        "--build-dir",
        default=os.environ.get("DEVELOPABLE_BUILD_DIR", str(REPO / "build")),
        help="engine build folder (default build/ or $DEVELOPABLE_BUILD_DIR)",
    )
    parser.add_argument(
        "--compare",
        metavar="'COMMAND {in} {out}'",
        help="another developability tool: {in} is an OBJ it reads, {out} the "
        "OBJ it must write; its rows get the same metrics",
    )
    parser.add_argument(
        "--compare-max-faces",
        type=int,
        default=100_000,
        help="largest generated mesh given to --compare (default 100000)",
    )
    parser.add_argument("--max-faces", type=int, default=1_000_000, help="largest generated mesh (default 1000000)")
    parser.add_argument(
        "--repeat", type=int, default=3, help="runs per small case (<= 20k faces); timings are the median"
    )
    parser.add_argument("--timeout", type=int, default=3600, help="seconds per case")
    parser.add_argument("--no-profile", action="store_true", help="skip the callgrind profile")
    parser.add_argument(
        "--reuse",
        action="store_true",
        help="reuse rows of the previous results file for identical cases "
        "(only to iterate on the report; final numbers need a fresh run)",
    )
    parser.add_argument(
        "--report-only",
        action="store_true",
        help="no runs: rewrite the document and plots from the raw results " "of the last run in the same --out folder",
    )
    args = parser.parse_args(argv)
    if args.quick:
        args.repeat = 1
        args.no_profile = True

    build_dir = pathlib.Path(args.build_dir)
    library = build_dir / "lib" / "libdevelopable.so"
    if not library.exists():
        sys.exit("no engine at %s: build first (cmake -S . -B build && cmake --build build -j2)" % library)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    default_out = out.resolve() == (REPO / "docs").resolve()
    raw_path = HERE / "results.json" if default_out else out / "bench-results.json"

    if args.report_only:
        data = json.loads(raw_path.read_text())
        report.write(data, out)
        log("rewrote %s from %s" % (out / "benchmarks.md", raw_path))
        return 0

    previous = {}
    if args.reuse and raw_path.exists():
        for row in json.loads(raw_path.read_text()).get("rows", []):
            previous[row["key"]] = row

    started = time.perf_counter()
    info = machine_info(build_dir=build_dir, library=library)
    log("engine %s, commit %s, %s" % (info.get("engine_version"), info.get("commit"), info["cpu"]))
    cases = plan(args)
    rows = []
    for index, case in enumerate(cases, 1):
        key = case_key(case)
        if key in previous and "error" not in previous[key]:
            row = previous[key]
        else:
            log(
                "%d/%d %s: %s %s"
                % (
                    index,
                    len(cases),
                    case["section"],
                    case["label"],
                    json.dumps(case["params"]) if case["params"] else "",
                )
            )
            result = run_case(case, library, args.timeout)
            row = dict(case)
            row.update(result)
            row["key"] = key
            if "error" in result:
                log("   error: %s" % result["error"])
            else:
                log(
                    "   t_T %.1f ms, peak %.0f MiB, mean |defect| %.3g -> %.3g"
                    % (
                        result.get("t_T", float("nan")),
                        result.get("peak_mib", float("nan")),
                        result.get("mean_before", float("nan")),
                        result.get("mean_after", float("nan")),
                    )
                )
        rows.append(row)
        raw_path.write_text(json.dumps({"machine": info, "rows": rows}, indent=1))

    profiles = None
    if not args.no_profile:
        profiles = run_profiles(args, out)
    info["load_end"] = load_average()
    info["bench_minutes"] = round((time.perf_counter() - started) / 60.0, 1)
    command = "/usr/bin/python3 bench/run.py" + (" --quick" if args.quick else "")
    if args.compare:
        command += " --compare %r" % args.compare
    data = {"machine": info, "rows": rows, "profiles": profiles, "command": command, "quick": args.quick}
    raw_path.write_text(json.dumps(data, indent=1))
    report.write(data, out)
    log("wrote %s and its plots (%s), raw numbers in %s" % (out / "benchmarks.md", out, raw_path))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Runs one benchmark case in its own process (so that its peak memory is its
own) and prints one JSON object on stdout.

    python3 bench/worker.py '<json case>'

case: {"mesh": {...} (see devkit.meshes.load), "params": {engine dev_params fields},
       "library": path to libdevelopable.so, "compare": null | "COMMAND {in} {out}",
       "hausdorff": true}"""
import json
import math
import os
import pathlib
import resource
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))  # devkit
from devkit import measures, meshes
from devkit.binding import native, params_from_names
from devkit.distance import bbox_diagonal, sampled_hausdorff
from devkit.obj import read_obj, write_obj


def status_kib(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return -1


def reset_peak():
    """Linux: writing 5 to clear_refs resets VmHWM to the current RSS."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def run_engine(case, positions, triangles):
    native.load(path=case["library"])
    marks = []

    def progress(fraction, stage):
        if not marks or marks[-1][1] != stage:
            marks.append((time.perf_counter(), stage))
        return True

    pinned = None
    params = params_from_names(case.get("params", {}))
    rss0 = status_kib("VmRSS")
    peak_reset = reset_peak()
    cpu0 = resource.getrusage(resource.RUSAGE_SELF)
    t0 = time.perf_counter()
    try:
        result = native.run(positions, triangles, pinned=pinned, params=params, progress=progress)
    except native.EngineError as error:
        return {"error": str(error)}
    wall = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    peak = status_kib("VmHWM") if peak_reset else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    marks.append((t0 + wall, "end"))
    stages = {}
    for (start, name), (stop, _) in zip(marks, marks[1:]):
        stages[name] = stages.get(name, 0.0) + 1000.0 * (stop - start)
    s = result.stats
    return {
        "out_positions": result.positions,
        "engine_stats": {k: (v if not isinstance(v, float) or math.isfinite(v) else None) for k, v in s.items()},
        "t_D": s["time_decompose_ms"],
        "t_I": s["time_iterate_ms"],
        "t_T": s["time_total_ms"],
        "wall_ms": 1000.0 * wall,
        "cpu_ms": 1000.0 * cpu,
        "rss_before_mib": rss0 / 1024.0,
        "peak_mib": peak / 1024.0,
        "iterations": s["iterations"],
        "stop_reason": native.STOP_REASONS[s["stop_reason"]],
        "patches": s["patches"],
        "stages_ms": stages,
    }


def run_compare(case, positions, triangles):
    with tempfile.TemporaryDirectory(prefix="bench-compare-") as tmp:
        src, dst = os.path.join(tmp, "in.obj"), os.path.join(tmp, "out.obj")
        write_obj(src, positions, triangles)
        command = case["compare"].replace("{in}", shlex.quote(src)).replace("{out}", shlex.quote(dst))
        # A child forked from this Python process starts with its RSS counted in
        # ru_maxrss; GNU time forks the command from a small process instead.
        gnu_time = shutil.which("time") if os.path.exists("/usr/bin/time") else None
        rss_file = os.path.join(tmp, "maxrss")
        argv = [gnu_time, "-f", "%M", "-o", rss_file, "sh", "-c", command] if gnu_time else ["sh", "-c", command]
        t0 = time.perf_counter()
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        _, err = proc.communicate(timeout=case.get("timeout", 3600))
        wall = time.perf_counter() - t0
        try:
            peak = int(open(rss_file).read().split()[-1])  # KiB
        except (OSError, ValueError, IndexError):
            peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss  # upper bound
        if proc.returncode != 0 or not os.path.exists(dst):
            return {"error": "exit %d: %s" % (proc.returncode, err.decode(errors="replace")[-300:])}
        out_pos, out_tri = read_obj(dst)
    return {
        "out_positions": out_pos,
        "out_triangles": out_tri,
        "t_T": 1000.0 * wall,
        "wall_ms": 1000.0 * wall,
        "peak_mib": peak / 1024.0,
    }


def main():
    case = json.loads(sys.argv[1])
    t0 = time.perf_counter()
    positions, triangles = meshes.load(case["mesh"])
    row = {"v": int(len(positions)), "f": int(len(triangles)), "mesh_seconds": time.perf_counter() - t0}
    run = run_compare(case, positions, triangles) if case.get("compare") else run_engine(case, positions, triangles)
    if "error" in run:
        row.update(run)
        print(json.dumps(row))
        return
    out_pos = run.pop("out_positions")
    out_tri = run.pop("out_triangles", triangles)
    row.update(run)
    before = measures.defect_summary(positions, triangles)
    after = measures.defect_summary(out_pos, out_tri)
    row.update(
        {
            "AE": measures.average_edge_length(positions, triangles),
            "mean_before": before["mean"],
            "max_before": before["max"],
            "flat_before": before["flat"],
            "mean_after": after["mean"],
            "max_after": after["max"],
            "flat_after": after["flat"],
        }
    )
    row["dE"] = 100.0 * (after["mean"] - before["mean"]) / before["mean"] if before["mean"] else 0.0
    row["out_v"], row["out_f"] = int(len(out_pos)), int(len(out_tri))
    diag = bbox_diagonal(positions)
    row["max_move"] = (
        float(np.linalg.norm(out_pos - positions, axis=1).max()) if len(out_pos) == len(positions) else None
    )
    if case.get("hausdorff", True):
        t1 = time.perf_counter()
        row["hausdorff"] = sampled_hausdorff(positions, triangles, out_pos, out_tri) / diag
        row["hausdorff_seconds"] = time.perf_counter() - t1
    print(json.dumps(row))


if __name__ == "__main__":
    main()

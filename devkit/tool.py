"""The command-line tool on arrays, for the benchmark scripts that compare runs
(bench/families.py, bench/objects.py, bench/scans.py): the mesh written as OBJ,
the tool run with its defaults (--quiet --report), the result read back."""
import json
import os
import subprocess
import time
from dataclasses import dataclass

import numpy as np

from .obj import read_obj, write_obj


@dataclass
class ToolRun:
    """One run of the tool: its result, its whole report (stats, patch_ids,
    curves) and what it cost."""

    positions: np.ndarray
    report: dict
    wall_s: float  # seconds from start to exit
    cpu_s: float  # user + system seconds of the tool, all its threads
    peak_bytes: int  # the tool's peak resident memory


def run_tool_measured(tool, work, positions, triangles, options=()):
    """A ToolRun of the tool's defaults (and the command-line `options`) on
    the mesh, its files in the folder `work`; or the end of its error
    message. CPU and memory from the child's own rusage (os.wait4): the
    figures of the tool alone, whatever else this process runs."""
    src, dst, report, errors = work / "in.obj", work / "out.obj", work / "r.json", work / "stderr.txt"
    write_obj(src, positions, triangles)
    start = time.perf_counter()
    # stderr into a file: a pipe nobody reads while waiting could fill up.
    with open(errors, "w") as stderr:
        child = subprocess.Popen(
            [str(tool), str(src), str(dst), "--quiet", "--report", str(report), *options],
            stdout=subprocess.DEVNULL,
            stderr=stderr,
        )
        _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        return errors.read_text().strip()[-200:] or "the tool failed with exit code %d" % code
    return ToolRun(
        read_obj(dst)[0],
        json.loads(report.read_text()),
        wall,
        usage.ru_utime + usage.ru_stime,
        usage.ru_maxrss * 1024,
    )


def run_tool_report(tool, work, positions, triangles, options=()):
    """(result positions, the whole report, wall seconds) of run_tool_measured,
    or the end of its error message."""
    run = run_tool_measured(tool, work, positions, triangles, options)
    if isinstance(run, str):
        return run
    return run.positions, run.report, run.wall_s


def run_tool(tool, work, positions, triangles, options=()):
    """As run_tool_report, with the report's stats in place of the whole report."""
    run = run_tool_measured(tool, work, positions, triangles, options)
    if isinstance(run, str):
        return run
    return run.positions, run.report["stats"], run.wall_s

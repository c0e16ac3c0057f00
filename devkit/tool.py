"""The command-line tool on arrays, for the benchmark scripts that compare runs
(bench/families.py, bench/objects.py): the mesh written as OBJ, the tool run with
its defaults (--quiet --report), the result read back."""
import json
import subprocess
import time

from .obj import read_obj, write_obj


def run_tool(tool, work, positions, triangles, options=()):
    """(result positions, report stats, seconds) of the tool's defaults (and
    the command-line `options`) on the mesh, its files in the folder `work`,
    or the end of its error message."""
    run = run_tool_report(tool, work, positions, triangles, options)
    if isinstance(run, str):
        return run
    after, report, seconds = run
    return after, report["stats"], seconds


def run_tool_report(tool, work, positions, triangles, options=()):
    """As run_tool, with the whole report (its stats, patch_ids, curves) in
    place of its stats."""
    src, dst, report = work / "in.obj", work / "out.obj", work / "r.json"
    write_obj(src, positions, triangles)
    start = time.perf_counter()
    run = subprocess.run(
        [str(tool), str(src), str(dst), "--quiet", "--report", str(report), *options], capture_output=True, text=True
    )
    seconds = time.perf_counter() - start
    if run.returncode != 0:
        return run.stderr.strip()[-200:]
    return read_obj(dst)[0], json.loads(report.read_text()), seconds

"""Smoke test of the benchmark command (bench/run.py --quick), so that it cannot
rot: it must run end to end on a few small meshes and write a well-formed
table of finite numbers, into a folder of our choosing (never docs/)."""
import json
import math
import re
import subprocess
import sys

import numpy as np
import pytest


def _tables(markdown):
    """Every markdown table as a list of rows (lists of cells), header first."""
    tables, current = [], []
    for line in markdown.splitlines():
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not all(re.fullmatch(r"-+", c) for c in cells):
                current.append(cells)
        elif current:
            tables.append(current)
            current = []
    if current:
        tables.append(current)
    return tables


def run_bench(repo_dir, script, *args):
    """Runs bench/`script` with `args` under this interpreter; fails the test with its output's
    tail unless it exits 0."""
    proc = subprocess.run(
        [sys.executable, str(repo_dir / "bench" / script), *args], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory, build_dir, repo_dir):
    out = tmp_path_factory.mktemp("bench")
    docs_before = {p.name: p.stat().st_mtime_ns for p in (repo_dir / "docs").glob("*")}
    run_bench(repo_dir, "run.py", "--quick", "--out", str(out), "--build-dir", str(build_dir))
    docs_after = {p.name: p.stat().st_mtime_ns for p in (repo_dir / "docs").glob("*")}
    return out, docs_before, docs_after


def test_quick_run_writes_into_out_only(quick_run):
    out, docs_before, docs_after = quick_run
    assert (out / "benchmarks.md").is_file()
    assert (out / "bench-results.json").is_file()
    assert docs_before == docs_after, "the smoke run must not touch docs/"


def test_tables_are_well_formed(quick_run):
    out = quick_run[0]
    text = (out / "benchmarks.md").read_text()
    for heading in (
        "## Targets",
        "## Real meshes",
        "## Generated meshes of growing size",
        "## The paper's Tables I and II",
        "## Paper mode against refit mode",
    ):
        assert heading in text
    assert "dev_version_string" in text and "cores" in text
    tables = _tables(text)
    assert len(tables) >= 4
    for t in tables:
        width = len(t[0])
        assert all(len(row) == width for row in t), t
    assert not re.search(r"\|\s*(nan|inf|-inf|error[^|]*)\s*\|", text), "non-finite or failed cell"
    mesh_table = next(t for t in tables if t[0][:3] == ["mesh", "#v", "#f"])
    assert len(mesh_table) >= 3  # header + the curved cone + at least one more mesh
    for row in mesh_table[1:]:
        for cell in row[1:12] + row[15:]:
            assert math.isfinite(float(cell.split("→")[-1])), row


def test_raw_numbers_are_finite(quick_run):
    out = quick_run[0]
    data = json.loads((out / "bench-results.json").read_text())
    rows = data["rows"]
    assert rows and all("error" not in r for r in rows), [r.get("error") for r in rows]
    for r in rows:
        for key in ("mean_before", "mean_after", "max_after", "flat_after", "hausdorff", "t_T", "peak_mib"):
            assert np.isfinite(r[key]), (r["label"], key)
        # Never worse than the input by the engine's score: E^mean, or on a segmented
        # mesh in the refit mode the median |defect| inside the patches, which the
        # benchmark does not record; there the flat share (what it follows) must not fall.
        # (The "modes" rows try other settings and are not held to this.)
        if r["section"] != "modes" and r["patches"] > 1 and r.get("mode") != "paper":
            assert r["flat_after"] >= r["flat_before"], r["label"]
        elif r["section"] != "modes":
            assert r["mean_after"] <= r["mean_before"] * (1 + 1e-9), r["label"]
        assert 0 <= r["hausdorff"] < 1
    sections = {r["section"] for r in rows}
    assert {"real", "scaling", "paper_tables", "modes"} <= sections


def test_the_scan_benchmark_runs_and_measures_what_it_says(tmp_path, build_dir, repo_dir):
    """bench/scans.py on small scans: a row per case with finite figures, the sheets' distance
    to their twin measured, the table written where it was told (never docs/ here)."""
    md, raw = tmp_path / "scans.md", tmp_path / "scans.json"
    run_bench(
        repo_dir,
        "scans.py",
        "--sizes",
        "1500,3000",
        "--quick",
        "--tool",
        str(build_dir / "bin" / "developable"),
        "--md",
        str(md),
        "--json",
        str(raw),
    )
    rows = json.loads(raw.read_text())["rows"]
    assert [r["kind"] for r in rows] == ["sheet", "sheet", "object"] * 2
    for r in rows:
        assert r["cpu_s"] > 0 and r["peak_bytes"] > 2**20 and 0 <= r["flat"] <= 1
        assert (r["twin_max"] is not None) == (r["kind"] == "sheet")
    # small noisy sheets come back within the noise of their true shape (least motion runs there)
    assert all(r["twin_rms"] < 1.0 for r in rows if r["kind"] == "sheet")
    table = _tables(md.read_text())[0]
    assert len(table) == 1 + len(rows)

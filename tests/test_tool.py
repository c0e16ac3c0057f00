"""The command-line tool: files in and out, options, report, errors."""
import json
import subprocess

import numpy as np
import pytest

from devkit import meshes
from devkit.obj import read_obj, write_obj


def run_tool(tool_path, *args):
    return subprocess.run([str(tool_path), *map(str, args)], capture_output=True, text=True, timeout=120)


def test_help(tool_path):
    run = run_tool(tool_path, "--help")
    assert run.returncode == 0
    for option in (
        "--omega",
        "--tolerance",
        "--max-iterations",
        "--mode",
        "--pin-boundary",
        "--pin",
        "--report",
        "--quiet",
        "--segmentation",
        "--seams",
        "--max-move",
        "--polish",
    ):
        assert option in run.stdout


@pytest.mark.parametrize("suffix", ["obj", "off", "ply", "stl"])
def test_formats_round_trip(tool_path, tmp_path, suffix):
    positions, triangles = meshes.noisy_cylinder_patch()
    source = tmp_path / "in.obj"
    write_obj(source, positions, triangles)
    middle = tmp_path / ("mid." + suffix)
    assert run_tool(tool_path, source, middle, "--max-iterations", "1", "--quiet").returncode == 0
    target = tmp_path / "out.obj"
    run = run_tool(tool_path, middle, target, "--quiet")
    assert run.returncode == 0, run.stderr
    out_positions, out_triangles = read_obj(target)
    assert out_positions.shape == positions.shape and len(out_triangles) == len(triangles)


def test_run_with_report_and_pins(tool_path, tmp_path):
    positions, triangles = meshes.curved_cone()
    source, target, report = tmp_path / "cone.obj", tmp_path / "out.obj", tmp_path / "r.json"
    write_obj(source, positions, triangles)
    pins = tmp_path / "pins.txt"
    pinned = [0, 5, 715]  # on the boundary rings: an interior pin would hold the bulge
    pins.write_text("\n".join(map(str, pinned)) + "\n")
    run = run_tool(
        tool_path,
        source,
        target,
        "--pin-boundary",
        "--pin",
        pins,
        "--tolerance",
        "10",
        "--max-move",
        "0",
        "--omega",
        "5",
        "--report",
        report,
    )
    assert run.returncode == 0, run.stderr
    assert "E_before" in run.stderr and "t_T" in run.stderr
    data = json.loads(report.read_text())
    stats = data["stats"]
    assert stats["vertices"] == 720 and stats["faces"] == 1280
    assert stats["change_percent"] <= -90
    assert len(data["patch_ids"]) == 1280 and len(data["curves"]) == stats["curves"] >= 1
    out_positions, _ = read_obj(target)
    assert np.array_equal(out_positions[pinned], positions[pinned])
    assert np.abs(out_positions - positions).max() <= 10 * stats["average_edge_length"] + 1e-12


def test_report_says_why_the_input_came_back(tool_path, tmp_path):
    positions, triangles = meshes.plane()
    source, report = tmp_path / "plane.obj", tmp_path / "r.json"
    write_obj(source, positions, triangles)
    run = run_tool(tool_path, source, tmp_path / "out.obj", "--report", report)
    assert run.returncode == 0, run.stderr
    assert "result unchanged (already_developable)" in run.stderr
    # Nothing to do is no failure: a note, not a warning.
    assert "note: The mesh is already developable" in run.stderr and "WARNING" not in run.stderr
    stats = json.loads(report.read_text())["stats"]
    assert stats["result"] == "unchanged" and stats["unchanged_reason"] == "already_developable"


def test_quiet_prints_nothing(tool_path, tmp_path):
    positions, triangles = meshes.noisy_cylinder_patch()
    source = tmp_path / "in.obj"
    write_obj(source, positions, triangles)
    run = run_tool(tool_path, source, tmp_path / "out.obj", "--quiet")
    assert run.returncode == 0 and run.stdout == "" and run.stderr == ""


@pytest.mark.parametrize(
    "args,words",
    [
        (["--omega"], "needs a value"),
        (["--omega", "abc"], "needs a number"),
        (["--mode", "fast"], "unknown value"),
        (["--frobnicate"], "unknown option"),
        (["--max-iterations", "2.5"], "whole number"),
    ],
)
def test_bad_options(tool_path, tmp_path, args, words):
    positions, triangles = meshes.plane()
    source = tmp_path / "in.obj"
    write_obj(source, positions, triangles)
    run = run_tool(tool_path, source, tmp_path / "out.obj", *args)
    assert run.returncode == 1 and words in run.stderr
    assert not (tmp_path / "out.obj").exists()


def test_file_errors(tool_path, tmp_path):
    run = run_tool(tool_path, tmp_path / "missing.obj", tmp_path / "out.obj")
    assert run.returncode == 1 and "cannot open" in run.stderr
    source = tmp_path / "in.obj"
    write_obj(source, *meshes.plane())
    run = run_tool(tool_path, source, tmp_path / "out.xyz")
    assert run.returncode == 1 and "cannot write" in run.stderr
    pins = tmp_path / "pins.txt"
    pins.write_text("3\n99999\n")
    run = run_tool(tool_path, source, tmp_path / "out.obj", "--pin", pins)
    assert run.returncode == 1 and "99999" in run.stderr
    assert not (tmp_path / "out.obj").exists()

"""The command-line tool: files in and out, options, report, errors."""
import json
import subprocess

import numpy as np
import pytest

from devkit import meshes
from devkit.obj import read_obj, write_obj
from test_one_sided import flipped, moebius


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


def test_obj_dialects_read_as_one_mesh(tool_path, tmp_path):
    """What OBJ files carry besides "v x y z" and "f a b c" (CRLF line ends, tabs, comments, normals
    and texture coordinates, "a/b/c" corners, indices counted back from the end, quads, no final
    line end) is read as the same mesh, and the output keeps every bit of the coordinates."""
    positions, triangles = meshes.noisy_cylinder_patch()
    plain = tmp_path / "plain.obj"
    write_obj(plain, positions, triangles)
    n = len(positions)
    lines = ["# exported", "o patch", "s off", ""]
    lines += ["\tv\t%r  %r %r " % tuple(p) for p in positions]
    lines += ["vn 0 0 1", "vt 0.5 0.5"]
    lines += ["f %d/1/1 %d//1 %d/1" % (a - n, b + 1, c - n) for a, b, c in triangles]
    dialect = tmp_path / "dialect.obj"
    dialect.write_bytes("\r\n".join(lines).encode())
    outputs = []
    for source in (plain, dialect):
        target = tmp_path / (source.stem + "_out.obj")
        run = run_tool(tool_path, source, target, "--max-iterations", "3", "--quiet")
        assert run.returncode == 0, run.stderr
        outputs.append(target.read_bytes())
    assert outputs[0] == outputs[1]
    # All 17 digits: a tilted plane with jittered vertices is developable as it is and comes back
    # unchanged, every coordinate to the bit.
    plane_positions, plane_triangles = meshes.plane()
    rng = np.random.default_rng(3)
    plane_positions = plane_positions + rng.uniform(-0.01, 0.01, plane_positions.shape) * [1, 1, 0]
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    plane_positions = plane_positions @ rotation.T + [0.1, -2.3, 1e-3]
    flat = tmp_path / "flat.obj"
    write_obj(flat, plane_positions, plane_triangles)
    same = tmp_path / "same.obj"
    run = run_tool(tool_path, flat, same)
    assert run.returncode == 0 and "returned unchanged" in run.stderr, run.stderr
    back, back_triangles = read_obj(same)
    assert np.array_equal(back, plane_positions) and np.array_equal(back_triangles, plane_triangles)


def read_off_or_ply(path):
    """(positions (n, 3), triangles (m, 3)) of an ASCII OFF or PLY file of triangles, as OpenMesh writes them."""
    lines = path.read_text().splitlines()
    if lines[0] == "OFF":
        n, m = map(int, lines[1].split()[:2])
        start = 2
    else:
        n, m = (int(line.split()[2]) for line in lines if line.startswith("element "))
        start = lines.index("end_header") + 1
    positions = np.array([line.split() for line in lines[start : start + n]], dtype=np.float64)
    faces = np.array([line.split() for line in lines[start + n : start + n + m]], dtype=np.int64)
    assert (faces[:, 0] == 3).all()
    return positions, faces[:, 1:].astype(np.int32)


def read_stl(path):
    """(facet normals (m, 3), corners (m, 3, 3)) of an ASCII STL file."""
    words = path.read_text().split()
    normals = [words[i + 1 : i + 4] for i, w in enumerate(words) if w == "normal"]
    corners = [words[i + 1 : i + 4] for i, w in enumerate(words) if w == "vertex"]
    return np.array(normals, dtype=np.float64), np.array(corners, dtype=np.float64).reshape(-1, 3, 3)


def renumbered_by_first_use(faces):
    """The faces with their vertices numbered in the order the faces first use them."""
    _, first = np.unique(faces.ravel(), return_index=True)
    number = np.empty(faces.max() + 1, np.int64)
    number[faces.ravel()[np.sort(first)]] = np.arange(len(first))
    return number[faces]


def one_sided_or_inconsistent(kind):
    if kind == "moebius":
        return moebius(noise=0.03, seed=6)
    positions, triangles = meshes.noisy_cylinder_patch()
    return positions, flipped(triangles, np.random.default_rng(1).random(len(triangles)) < 0.3)


@pytest.mark.parametrize("kind", ["moebius", "wound at random"])
def test_every_format_writes_the_faces_as_returned(tool_path, tmp_path, kind):
    # The engine runs one-sided and inconsistently wound meshes and returns the caller's faces,
    # which no OpenMesh mesh can hold (its add_face refuses a "complex edge"): every writer gets them
    # as they are, in the order and winding of the OBJ.
    positions, triangles = one_sided_or_inconsistent(kind)
    source = tmp_path / "in.obj"
    write_obj(source, positions, triangles)
    outputs = {suffix: tmp_path / ("out." + suffix) for suffix in ("obj", "off", "ply", "stl")}
    for target in outputs.values():
        run = run_tool(tool_path, source, target, "--max-iterations", "3", "--quiet")
        assert run.returncode == 0, (target.name, run.stderr)
    reference, faces = read_obj(outputs["obj"])
    assert np.array_equal(faces, triangles) and reference.shape == positions.shape
    for suffix in ("off", "ply"):
        got, got_faces = read_off_or_ply(outputs[suffix])
        assert np.array_equal(got_faces, faces), suffix
        assert np.allclose(got, reference, rtol=0, atol=1e-6), suffix  # single precision
    normals, corners = read_stl(outputs["stl"])
    assert np.allclose(corners, reference[faces], rtol=0, atol=1e-6)
    # Each facet's normal is its own winding's, also where neighbours disagree.
    own = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert ((normals * own).sum(1) > 0).all()
    # And the tool reads each back and runs it: the same vertices and faces (an STL's vertices are
    # numbered as its facets first use them).
    for suffix in ("off", "ply", "stl"):
        back = tmp_path / ("back-" + suffix + ".obj")
        run = run_tool(tool_path, outputs[suffix], back, "--max-iterations", "1", "--quiet")
        assert run.returncode == 0, (suffix, run.stderr)
        back_positions, back_faces = read_obj(back)
        assert back_positions.shape == reference.shape, suffix
        assert np.array_equal(back_faces, faces if suffix != "stl" else renumbered_by_first_use(faces)), suffix


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

"""The tool's pattern options: --pattern, --sheet, --scale, --unit and the
pattern part of --report."""
import json
import pathlib
import subprocess
import xml.etree.ElementTree as ET

import numpy as np

from devkit import meshes
from devkit.obj import read_obj, write_obj


def run_tool(tool_path, *args):
    return subprocess.run([str(tool_path)] + [str(a) for a in args], capture_output=True, text=True)


def test_tool_writes_the_pattern_and_reports_it(tool_path, tmp_path):
    pos, tri = meshes.cone()
    mesh = tmp_path / "cone.obj"
    write_obj(mesh, pos * 10, tri)  # 10 x the unit band, in cm: about 30 cm across
    report = tmp_path / "report.json"
    proc = run_tool(
        tool_path,
        mesh,
        tmp_path / "out.obj",
        "--quiet",
        "--pattern",
        tmp_path / "p.svg",
        "--sheet",
        "a3",
        "--unit",
        "cm",
        "--scale",
        "auto",
        "--report",
        report,
    )
    assert proc.returncode == 0, proc.stderr
    data = json.loads(report.read_text())["pattern"]
    assert data["parameters"]["unit"] == "cm" and data["parameters"]["unit_mm"] == 10
    assert data["parameters"]["sheet_width_mm"] == 297 and data["parameters"]["sheet_height_mm"] == 420
    st = data["stats"]
    assert st["pieces"] == len(data["pieces"]) >= 1 and st["seams"] == len(data["seams"])
    assert 0 < st["scale"] <= 1
    for path in data["files"]:
        root = ET.parse(path).getroot()
        assert root.get("width") == "297mm" and root.get("height") == "420mm"
    # Sizes on the sheet follow the scale: outline in cm, sheet in mm.
    piece = max(data["pieces"], key=lambda p: p["area_3d"])
    assert piece["width_mm"] <= 297 - 20 and piece["height_mm"] <= 420 - 32
    area_mm2 = piece["area_flat"] * 100 * st["scale"] ** 2
    assert area_mm2 <= piece["width_mm"] * piece["height_mm"] * (1 + 1e-9)


def test_tool_pattern_options_are_checked(tool_path, tmp_path):
    pos, tri = meshes.plane()
    mesh = tmp_path / "plane.obj"
    write_obj(mesh, pos, tri)
    for bad in (["--sheet", "big"], ["--sheet", "0x10"], ["--scale", "-2"], ["--unit", "ft"]):
        proc = run_tool(tool_path, mesh, tmp_path / "o.obj", "--pattern", tmp_path / "p.svg", *bad)
        assert proc.returncode == 1 and "error" in proc.stderr
    # A 2 m plane at 1:1 does not fit A4: the engine says which scale would.
    proc = run_tool(tool_path, mesh, tmp_path / "o.obj", "--quiet", "--pattern", tmp_path / "p.svg")
    assert proc.returncode == 2 and "1:10" in proc.stderr


def pattern_of_a_plane_in_inches(tool_path, tmp_path, *options):
    """(tool run, report's pattern) of a 4 in x 3.2 in plane with --unit in."""
    pos, tri = meshes.plane(rows=5, cols=6, size=4.0)
    mesh = tmp_path / "plane.obj"
    write_obj(mesh, pos, tri)
    report = tmp_path / "r.json"
    proc = run_tool(
        tool_path,
        mesh,
        tmp_path / "o.obj",
        "--quiet",
        "--pattern",
        tmp_path / "p.svg",
        "--unit",
        "in",
        "--report",
        report,
        *options,
    )
    assert proc.returncode == 0, proc.stderr
    return proc, json.loads(report.read_text())["pattern"]


def test_tool_letter_sheet_in_inches(tool_path, tmp_path):
    _, pattern = pattern_of_a_plane_in_inches(tool_path, tmp_path, "--sheet", "letter")
    piece = pattern["pieces"][0]
    # The engine leaves an already developable plane unchanged: 4 x 3.2 in = 101.6 x 81.28 mm.
    assert np.allclose(sorted([piece["width_mm"], piece["height_mm"]]), [81.28, 101.6], atol=1e-6)
    svg = (tmp_path / "p.svg").read_text()
    assert 'width="215.9mm"' in svg and " in</text>" in svg


def test_tool_seam_allowance(tool_path, tmp_path):
    # The 4 in x 3.2 in plane with a 6 mm allowance: the piece's box on the
    # sheet grows by 12 mm both ways, the outline becomes the dashed seam line.
    proc, data = pattern_of_a_plane_in_inches(tool_path, tmp_path, "--seam-allowance", "6")
    assert "convex hull" not in proc.stderr
    assert data["parameters"]["seam_allowance_mm"] == 6 and data["stats"]["cut_lines_from_hull"] == 0
    piece = data["pieces"][0]
    assert np.allclose(sorted([piece["width_mm"], piece["height_mm"]]), [93.28, 113.6], atol=1e-6)
    root = ET.parse(tmp_path / "p.svg").getroot()
    groups = {g.get("id"): g for g in root.iter("{http://www.w3.org/2000/svg}g")}
    assert "seam-lines" in groups and groups["seam-lines"].get("stroke-dasharray")
    for bad in ("-1", "nan"):
        proc = run_tool(
            tool_path,
            tmp_path / "plane.obj",
            tmp_path / "o.obj",
            "--quiet",
            "--pattern",
            tmp_path / "p.svg",
            "--seam-allowance",
            bad,
        )
        assert proc.returncode != 0 and "seam" in proc.stderr and "allowance" in proc.stderr, proc.stderr


def test_tool_glue_tabs(tool_path, tmp_path):
    # A closed cylinder band in cm: cut once, so one seam and one tab, its
    # fold line dashed; not together with a seam allowance.
    pos, tri = meshes.cylinder()
    mesh = tmp_path / "band.obj"
    write_obj(mesh, pos * 10, tri)
    report = tmp_path / "r.json"
    proc = run_tool(
        tool_path,
        mesh,
        tmp_path / "o.obj",
        "--quiet",
        "--pattern",
        tmp_path / "p.svg",
        "--unit",
        "cm",
        "--scale",
        "auto",
        "--glue-tabs",
        "5",
        "--report",
        report,
    )
    assert proc.returncode == 0, proc.stderr
    data = json.loads(report.read_text())["pattern"]
    assert data["parameters"]["glue_tabs_mm"] == 5
    assert data["stats"]["seams"] == 1 and data["stats"]["glue_tabs"] == 1 and data["stats"]["glue_tabs_dropped"] == 0
    root = ET.parse(tmp_path / "p.svg").getroot()
    groups = {g.get("id"): g for g in root.iter("{http://www.w3.org/2000/svg}g")}
    assert len(list(groups["fold-lines"].iter("{http://www.w3.org/2000/svg}path"))) == 1
    proc = run_tool(
        tool_path,
        mesh,
        tmp_path / "o.obj",
        "--quiet",
        "--pattern",
        tmp_path / "p.svg",
        "--glue-tabs",
        "5",
        "--seam-allowance",
        "5",
    )
    assert proc.returncode == 2 and "not both" in proc.stderr


def test_a_band_without_interior_vertex_is_written_unchanged_and_unfolds(tool_path, tmp_path):
    """A cone frustum one face high, as sheet metal draws a transition. No
    vertex inside: no curvature to lower, and the band unfolds as it
    stands into one piece (the engine refuses such a mesh; the tool writes it
    back with a note, as the add-on says it, and still makes its pattern)."""
    positions, triangles = meshes.cone(rows=2, cols=32, r0=1.0, r1=0.5, height=1.0)  # one face high
    mesh = tmp_path / "frustum.obj"
    write_obj(mesh, positions, triangles)
    report = tmp_path / "report.json"
    out = tmp_path / "out.obj"
    proc = run_tool(
        tool_path, mesh, out, "--quiet", "--pattern", tmp_path / "p.svg", "--scale", "auto", "--report", report
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.startswith("note: Returned the input unchanged: every vertex is on the boundary"), proc.stderr
    assert "WARNING" not in proc.stderr
    back, faces = read_obj(out)
    given, given_faces = read_obj(mesh)
    assert np.array_equal(back, given) and np.array_equal(faces, given_faces)
    data = json.loads(report.read_text())
    assert data["stats"]["result"] == "unchanged" and data["stats"]["unchanged_reason"] == "no_interior_vertex"
    st = data["pattern"]["stats"]
    assert st["pieces"] == 1 and st["max_strain"] < 1e-9
    assert all(pathlib.Path(f).exists() for f in data["pattern"]["files"])

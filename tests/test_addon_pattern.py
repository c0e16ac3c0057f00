"""Unfold Pattern (addon/pattern.py) in a real Blender 3.4, the add-on
installed from the zip: headless, and under xvfb for undo and a screenshot."""
import os
import pathlib
import shutil

import pytest

from blender_support import SCRIPTS, results, run_blender
from devkit import meshes
from devkit.obj import write_obj

PATTERN_SCENARIOS = SCRIPTS / "pattern_scenarios.py"


def pattern_scenario(env, name, *extra, xvfb=False, before=()):
    proc = run_blender(
        list(before) + ["--python", str(PATTERN_SCENARIOS), "--", name] + [str(e) for e in extra], env, xvfb=xvfb
    )
    res = results(proc)
    assert res, "no RESULT\nstdout:\n%s\nstderr:\n%s" % (proc.stdout[-4000:], proc.stderr[-4000:])
    assert "traceback" not in proc.stderr.lower(), proc.stderr[-4000:]
    assert "exception" not in res[-1], res[-1]["exception"]
    return res[-1]


def test_unfold_pattern_headless(blender_env, tmp_path):
    r = pattern_scenario(blender_env, "headless", tmp_path)
    res, err, base = r["base"]
    assert res == ["FINISHED"], err
    assert base["record"]["source"] == "base mesh"
    assert base["uv_maps"] == ["Developable Pattern"] and base["active_uv"] == "Developable Pattern"
    assert base["islands"] == base["record"]["pieces"] >= 1  # one island per piece
    assert base["seams"] > 0  # the closed band is cut open
    domain, kind, count, low, high = base["strain"]
    assert (
        (domain, kind) == ("FACE", "FLOAT")
        and low >= 0
        and high == pytest.approx(base["record"]["worst_strain"] / 100, rel=1e-4)
    )
    assert r["run"] == ["FINISHED"]
    res, err, key = r["key"]
    assert res == ["FINISHED"], err
    assert key["record"]["source"] == "shape key Developable"
    assert key["uv_maps"] == ["Developable Pattern"]  # replaced, not added
    assert key["islands"] == key["record"]["pieces"]
    assert key["keys"] == ["Basis", "Developable"]
    # A sheet too small: a clear error, and nothing of the earlier result is lost.
    res, err, big = r["too_big"]
    assert res == ["CANCELLED"] and "does not fit" in err
    assert big["record"] == key["record"] and big["seams"] == key["seams"]
    names = r["files"]
    assert any(n.startswith("base") for n in names) and any(n.startswith("key") for n in names)
    assert not any(n.startswith("big") for n in names)  # nothing written when it does not fit
    assert len([n for n in names if n.startswith("base")]) == base["record"]["sheets"]
    assert r["base_unchanged"]


def test_unfold_pattern_takes_the_shown_shape_at_world_size(blender_env, tmp_path):
    r = pattern_scenario(blender_env, "true_size", tmp_path)
    # 10 x 5 cm at scale 2, x stretched by 1.5 by the visible key: 0.3 x 0.1 m.
    assert r["source"] == "base mesh" and r["area"] == pytest.approx(0.03, rel=1e-6)
    assert r["key_source"] == "shape key Developable"
    assert r["key_area"] == pytest.approx(0.03, rel=1e-6)
    assert r["key_z"] == pytest.approx([2.0, 2.0], rel=1e-6)  # lifted 1 m, at scale 2


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="xvfb-run is missing")
def test_undo_removes_what_unfold_pattern_wrote(blender_env, tmp_path):
    # DEVELOPABLE_PATTERN_SCREENSHOT=PATH also takes docs/pattern-uv-editor.png's picture.
    shot = os.environ.get("DEVELOPABLE_PATTERN_SCREENSHOT", "")
    blend = []
    if shot:  # started on a saved file, Blender shows no splash screen over the editor
        blend = [str(tmp_path / "start.blend")]
        run_blender(["--python-expr", "import bpy; bpy.ops.wm.save_as_mainfile(filepath=%r)" % blend[0]], blender_env)
        out = tmp_path / "out"
        out.mkdir()
    else:
        out = tmp_path
    r = pattern_scenario(blender_env, "undo", out, *([shot] if shot else []), xvfb=True, before=blend)
    assert r["result"] == ["FINISHED"], r["error"]
    assert r["after"]["uv_maps"] == ["Developable Pattern"] and r["after"]["seams"] > 0
    assert r["after"]["strain"] is not None and r["after"]["record"]["has_result"]
    assert r["after"]["islands"] == r["after"]["record"]["pieces"]
    assert len(r["files"]) == r["after"]["record"]["sheets"] >= 1
    assert r["after_undo"] == r["before"]
    assert r["after_undo"]["uv_maps"] == [] and r["after_undo"]["seams"] == 0
    assert r["after_undo"]["strain"] is None and not r["after_undo"]["record"]["has_result"]
    assert r["undo_base_unchanged"]
    assert r["after_redo"] == r["after"]


def test_batch_script_writes_the_pattern(blender_env, tmp_path):
    from test_addon_batch import _batch

    out = tmp_path / "band.blend"
    svg = tmp_path / "band.svg"
    proc, r = _batch(blender_env, "demo:cone_band", out, "--pattern", svg, "--pattern-scale", "auto", "--sheet", "a3")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    p = r["pattern"]
    assert p["pieces"] >= 1 and p["sheets"] >= 1 and 0 < p["scale"] <= 1
    assert all(pathlib.Path(f).is_file() for f in p["files"]) and len(p["files"]) == p["sheets"]
    assert 'width="297mm"' in pathlib.Path(p["files"][0]).read_text()
    assert 'id="seam-lines"' not in pathlib.Path(p["files"][0]).read_text()
    # The panel's Seam Allowance: the cut lines go around dashed seam lines.
    proc, r = _batch(
        blender_env,
        "demo:cone_band",
        out,
        "--pattern",
        svg,
        "--pattern-scale",
        "auto",
        "--sheet",
        "a3",
        "--seam-allowance",
        "5",
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    text = pathlib.Path(r["pattern"]["files"][0]).read_text()
    assert 'id="seam-lines"' in text and "stroke-dasharray" in text
    # Glue Tabs: a closed cylinder is cut once, and that seam gets a tab
    # folded along a dashed line.
    band = tmp_path / "cylinder.obj"
    write_obj(band, *meshes.cylinder())
    proc, r = _batch(
        blender_env, band, tmp_path / "cylinder.blend", "--pattern", svg, "--pattern-scale", "auto", "--glue-tabs", "5"
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    text = pathlib.Path(r["pattern"]["files"][0]).read_text()
    folds = text.split('id="fold-lines"')[1].split("</g>")[0]
    assert r["pattern"]["seams"] >= 1 and folds.count("<path") == r["pattern"]["seams"]
    proc, r = _batch(blender_env, "demo:cone_band", out, "--pattern", svg, "--sheet", "60x60")
    assert proc.returncode == 1 and "does not fit" in r["pattern"]["error"]

"""Headless use: the batch script on files, and the one-line call on a .blend."""
import json
import subprocess

from blender_support import BLENDER, REPO, run_blender

BATCH = REPO / "scripts" / "batch_developable.py"


def _batch(env, *args):
    proc = run_blender(["-P", str(BATCH), "--"] + [str(a) for a in args], env, check=False)
    lines = [
        json.loads(line.split(" ", 1)[1]) for line in proc.stdout.splitlines() if line.startswith("DEVELOPABLE_RESULT ")
    ]
    return proc, (lines[-1] if lines else None)


def test_batch_demo_to_obj_to_ply_to_blend(blender_env, tmp_path):
    obj = tmp_path / "sheet.obj"
    proc, r = _batch(
        blender_env,
        "demo:half_cylinder",
        obj,
        "--pin-boundary",
        "--omega",
        7,
        "--mode",
        "PAPER",
        "--max-iterations",
        20,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert r["operator"] == ["FINISHED"] and r["e_after"] < r["e_before"]
    assert obj.exists() and obj.stat().st_size > 0
    ply = tmp_path / "sheet.ply"
    proc, r = _batch(blender_env, obj, ply)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert ply.exists()
    blend = tmp_path / "sheet.blend"
    proc, r = _batch(blender_env, ply, blend)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert blend.exists()


def test_batch_reports_a_bad_mesh(blender_env, tmp_path):
    bad = tmp_path / "edges.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n")
    proc, r = _batch(blender_env, bad, tmp_path / "out.obj")
    assert proc.returncode != 0
    assert "EMPTY_INPUT" in proc.stdout or "no mesh object" in proc.stdout + proc.stderr
    assert "Traceback" not in proc.stdout + proc.stderr
    assert not (tmp_path / "out.obj").exists()


def test_one_liner_on_a_blend(blender_env, tmp_path):
    blend = tmp_path / "cone.blend"
    proc, r = _batch(blender_env, "demo:cone_band", blend)
    assert proc.returncode == 0, proc.stdout[-3000:]
    # the add-on enabled in the (private) preferences, as a user would have it
    cmd = [
        BLENDER,
        "-b",
        str(blend),
        "--python-exit-code",
        "1",
        "--python-expr",
        "import bpy; bpy.context.view_layer.objects.active = bpy.data.objects['cone_band']; "
        "bpy.ops.mesh.make_developable(); "
        "print('KEYS', [k.name for k in bpy.data.objects['cone_band'].data.shape_keys.key_blocks])",
    ]
    proc = subprocess.run(cmd, env=blender_env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "KEYS ['Basis', 'Developable']" in proc.stdout

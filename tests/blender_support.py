"""Helpers and fixtures for the add-on tests (tests/test_addon_*.py).

The add-on is tested as a user gets it: the zip from the addon_zip target is
installed with bpy.ops.preferences.addon_install into a private user folder
(BLENDER_USER_SCRIPTS / BLENDER_USER_CONFIG under pytest's tmp), and every
test starts the real Blender (--background --factory-startup) on a scenario of
tests/blender_scripts/scenarios.py, which prints RESULT {json} lines."""
import json
import os
import pathlib
import shutil
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
SCRIPTS = pathlib.Path(__file__).resolve().parent / "blender_scripts"
SCENARIOS = SCRIPTS / "scenarios.py"
MODULE = "developable_mesh"
BLENDER = shutil.which("blender")


def blender_base_env():
    env = dict(os.environ)
    env.pop("DEVELOPABLE_LIBRARY", None)  # the library must come from the zip
    return env


def run_blender(args, env, timeout=300, xvfb=False, check=True):
    cmd = [BLENDER, "--background", "--factory-startup", "--python-exit-code", "1"] + list(args)
    if xvfb:
        cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", BLENDER, "--factory-startup",
               "--python-exit-code", "1"] + list(args)
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError("blender failed (%d)\ncmd: %s\nstdout:\n%s\nstderr:\n%s"
                             % (proc.returncode, " ".join(map(str, cmd)), proc.stdout[-6000:],
                                proc.stderr[-6000:]))
    return proc


def results(proc):
    """The RESULT {json} lines a scenario printed."""
    out = []
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            out.append(json.loads(line[len("RESULT "):]))
    return out


def scenario(env, name, *extra, xvfb=False, timeout=300):
    """Runs one scenario; returns its (last) RESULT dict."""
    args = ["--python", str(SCENARIOS), "--", name] + [str(e) for e in extra]
    proc = run_blender(args, env, timeout=timeout, xvfb=xvfb)
    res = results(proc)
    assert res, "scenario %s printed no RESULT\nstdout:\n%s\nstderr:\n%s" % (
        name, proc.stdout[-6000:], proc.stderr[-4000:])
    assert "traceback" not in proc.stderr.lower(), proc.stderr[-4000:]
    return res[-1]


def build_addon_zip(build_dir):
    subprocess.run(["cmake", "--build", str(build_dir), "--target", "addon_zip"],
                   check=True, capture_output=True, text=True)
    zips = sorted(pathlib.Path(build_dir, "dist").glob(MODULE + "-*.zip"))
    assert len(zips) == 1, "expected one zip in build/dist, found %s" % zips
    return zips[0]


def install_zip(zip_path, root):
    """Installs the zip into a private Blender user folder; returns the env."""
    env = blender_base_env()
    env["BLENDER_USER_SCRIPTS"] = str(root / "scripts")
    env["BLENDER_USER_CONFIG"] = str(root / "config")
    (root / "scripts").mkdir(parents=True, exist_ok=True)
    (root / "config").mkdir(parents=True, exist_ok=True)
    code = ("import bpy, sys\n"
            "bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)\n"
            "bpy.ops.preferences.addon_enable(module=%r)\n"
            "bpy.ops.wm.save_userpref()\n" % MODULE)
    run_blender(["--python-expr", code, "--", str(zip_path)], env)
    return env


@pytest.fixture(scope="session")
def addon_zip(build_dir):
    if BLENDER is None:
        pytest.skip("blender is not installed")
    return build_addon_zip(build_dir)


@pytest.fixture(scope="session")
def blender_env(addon_zip, tmp_path_factory):
    """Environment whose Blender has the zip installed (and enabled in its prefs)."""
    return install_zip(addon_zip, tmp_path_factory.mktemp("blender_user"))


@pytest.fixture(scope="session")
def installed_addon_dir(blender_env):
    return pathlib.Path(blender_env["BLENDER_USER_SCRIPTS"]) / "addons" / MODULE

"""Helpers and fixtures for the add-on tests (tests/test_addon_*.py).

The add-on is tested as a user gets it: the zip from the addon_zip target is
installed into a private user folder under pytest's tmp, and every test starts
a real Blender on a scenario of tests/blender_scripts/scenarios.py, which
prints RESULT {json} lines.

Blenders: Debian's `blender` (3.4; the zip installed as a legacy add-on with
bpy.ops.preferences.addon_install, run with --background --factory-startup)
and the `bpy` wheels that scripts/setup_bpy.sh put in
$DEVELOPABLE_BPY_CACHE (default ~/.cache/developable/bpy-<line>; the zip
installed as an extension with bpy.ops.extensions.package_install_files into
BLENDER_USER_RESOURCES, run through blender_scripts/bpy_main.py). The
`any_blender_env` fixture runs a test on each of them.

The fixtures here are session-scoped and made visible to every test module by
tests/conftest.py, which imports them: a test module must not import them
itself (pytest would then keep one instance per module, and the zip would be
rebuilt and installed again for each module). Under pytest-xdist each worker
has its own session, so its own installs."""
import fcntl
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


BPY_MAIN = SCRIPTS / "bpy_main.py"
BPY_CACHE = pathlib.Path(os.environ.get("DEVELOPABLE_BPY_CACHE", pathlib.Path.home() / ".cache" / "developable"))
MODULE_PYTHON = "DEVELOPABLE_TEST_BPY_PYTHON"  # env key: run this bpy module's Python


def module_blenders():
    """{line: python of its venv} for the bpy environments that installed fully."""
    found = {}
    for env in sorted(BPY_CACHE.glob("bpy-*")):
        if list(env.glob(".installed-*")) and (env / "bin" / "python").exists():
            found[env.name[len("bpy-") :]] = env / "bin" / "python"
    return found


BLENDER_NAMES = (["3.4"] if BLENDER else []) + sorted(module_blenders())


def blender_base_env():
    env = dict(os.environ)
    env.pop("DEVELOPABLE_LIBRARY", None)  # the library must come from the zip
    return env


def run_blender(args, env, timeout=300, xvfb=False, check=True):
    cmd = [BLENDER, "--background", "--factory-startup", "--python-exit-code", "1"] + list(args)
    if env.get(MODULE_PYTHON):
        if xvfb:
            pytest.skip("Blender as a Python module has no window")
        cmd = [env[MODULE_PYTHON], str(BPY_MAIN)] + [str(a) for a in args]
    elif xvfb:
        # -a takes the first display number from -n on without a lock file, which
        # two xvfb-runs started at once can both take: each pytest-xdist worker
        # starts its search elsewhere (gw0 at xvfb-run's usual 99, gw1 at 149 ...)
        worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")
        first = 99 + 50 * int(worker[2:]) if worker[2:].isdigit() else 99
        cmd = [
            "xvfb-run",
            "-n",
            str(first),
            "-a",
            "-s",
            "-screen 0 1280x800x24",
            BLENDER,
            "--factory-startup",
            "--python-exit-code",
            "1",
        ] + list(args)
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(
            "blender failed (%d)\ncmd: %s\nstdout:\n%s\nstderr:\n%s"
            % (proc.returncode, " ".join(map(str, cmd)), proc.stdout[-6000:], proc.stderr[-6000:])
        )
    return proc


def results(proc):
    """The RESULT {json} lines a scenario printed."""
    out = []
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            out.append(json.loads(line[len("RESULT ") :]))
    return out


def scenario(env, name, *extra, xvfb=False, timeout=300):
    """Runs one scenario; returns its (last) RESULT dict."""
    args = ["--python", str(SCENARIOS), "--", name] + [str(e) for e in extra]
    proc = run_blender(args, env, timeout=timeout, xvfb=xvfb)
    res = results(proc)
    assert res, "scenario %s printed no RESULT\nstdout:\n%s\nstderr:\n%s" % (
        name,
        proc.stdout[-6000:],
        proc.stderr[-4000:],
    )
    assert "traceback" not in proc.stderr.lower(), proc.stderr[-4000:]
    return res[-1]


def several(env, *specs, timeout=600):
    """Runs background scenarios ("NAME [ARGS]") one after another in one
    Blender start-up; returns {spec: its RESULT dict}."""
    proc = run_blender(["--python", str(SCENARIOS), "--", "several", *specs], env, timeout=timeout)
    res = results(proc)
    assert len(res) == len(specs), "scenarios %s printed %d RESULTs\nstdout:\n%s\nstderr:\n%s" % (
        specs,
        len(res),
        proc.stdout[-6000:],
        proc.stderr[-4000:],
    )
    assert "traceback" not in proc.stderr.lower(), proc.stderr[-4000:]
    return dict(zip(specs, res))


def build_addon_zip(build_dir, into):
    """Builds the addon_zip target and copies the zip into the folder `into`;
    returns the copy. The target rewrites build/dist on every build, so it is
    built under a lock and each test session (each pytest-xdist worker) uses
    its own copy, which another session's build cannot replace meanwhile."""
    with open(pathlib.Path(build_dir) / "addon_zip.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        subprocess.run(
            ["cmake", "--build", str(build_dir), "--target", "addon_zip"], check=True, capture_output=True, text=True
        )
        zips = sorted(pathlib.Path(build_dir, "dist").glob(MODULE + "-*.zip"))
        assert len(zips) == 1, "expected one zip in build/dist, found %s" % zips
        return pathlib.Path(shutil.copy2(zips[0], pathlib.Path(into) / zips[0].name))


def install_zip(zip_path, root):
    """Installs the zip into a private Blender user folder; returns the env."""
    env = blender_base_env()
    env["BLENDER_USER_SCRIPTS"] = str(root / "scripts")
    env["BLENDER_USER_CONFIG"] = str(root / "config")
    (root / "scripts").mkdir(parents=True, exist_ok=True)
    (root / "config").mkdir(parents=True, exist_ok=True)
    code = (
        "import bpy, sys\n"
        "bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)\n"
        "bpy.ops.preferences.addon_enable(module=%r)\n"
        "bpy.ops.wm.save_userpref()\n" % MODULE
    )
    run_blender(["--python-expr", code, "--", str(zip_path)], env)
    return env


def install_extension(zip_path, root, python):
    """Installs the zip as an extension (4.2+) of the bpy module at `python`
    into a private BLENDER_USER_RESOURCES; returns the env."""
    env = blender_base_env()
    env["BLENDER_USER_RESOURCES"] = str(root)
    env[MODULE_PYTHON] = str(python)
    root.mkdir(parents=True, exist_ok=True)
    code = (
        "import bpy, sys\n"
        "r = bpy.ops.extensions.package_install_files(filepath=sys.argv[-1], "
        "repo='user_default', enable_on_install=True)\n"
        "assert r == {'FINISHED'}, r\n"
        "assert hasattr(bpy.types, 'MESH_OT_make_developable')\n"
        "import os, sys; sys.stdout.flush(); os._exit(0)  # see bpy_main.py\n"
    )
    proc = subprocess.run(
        [str(python), "-c", code, str(zip_path)], env=env, capture_output=True, text=True, timeout=300
    )
    if proc.returncode != 0:
        raise AssertionError("extension install failed\n%s\n%s" % (proc.stdout[-4000:], proc.stderr[-4000:]))
    return env


def validate_manifest(zip_path, python):
    """That Blender's own extension validator (bl_pkg's blender_ext.py validate)
    on the zip: (return code, output)."""
    found = list(
        pathlib.Path(python).parent.parent.glob(
            "lib/python3*/site-packages/bpy/*/scripts/addons_core/bl_pkg/cli/blender_ext.py"
        )
    )
    if not found:
        return None, "no blender_ext.py"
    proc = subprocess.run(
        [str(python), str(found[0]), "validate", str(zip_path)], capture_output=True, text=True, timeout=120
    )
    return proc.returncode, proc.stdout + proc.stderr


@pytest.fixture(scope="session")
def built_zip(build_dir, tmp_path_factory):
    """The add-on zip of the build under test (this session's copy)."""
    return build_addon_zip(build_dir, tmp_path_factory.mktemp("zip"))


@pytest.fixture(scope="session", params=BLENDER_NAMES)
def any_blender_env(request, built_zip, tmp_path_factory):
    """The env of one Blender under test with the zip installed (each in turn);
    for 3.4 the install of `blender_env` (the same zip the same way)."""
    if request.param == "3.4":
        env = dict(request.getfixturevalue("blender_env"))
    else:
        root = tmp_path_factory.mktemp("blender_%s" % request.param)
        env = install_extension(built_zip, root, module_blenders()[request.param])
    env["DEVELOPABLE_TEST_BLENDER_NAME"] = request.param
    return env


@pytest.fixture(scope="session")
def addon_zip(built_zip):
    if BLENDER is None:
        pytest.skip("blender is not installed")
    return built_zip


@pytest.fixture(scope="session")
def blender_env(addon_zip, tmp_path_factory):
    """Environment whose Blender has the zip installed (and enabled in its prefs)."""
    return install_zip(addon_zip, tmp_path_factory.mktemp("blender_user"))


@pytest.fixture(scope="session")
def installed_addon_dir(blender_env):
    return pathlib.Path(blender_env["BLENDER_USER_SCRIPTS"]) / "addons" / MODULE

"""Shared fixtures: where the build and the test meshes are.

scripts/test.sh builds before running pytest; run pytest alone only after a
build (DEVELOPABLE_BUILD_DIR overrides the build folder, default build/).
Tests and bench share the development kit devkit/ at the repository root."""
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))  # devkit

from devkit import paths
from devkit.binding import native

# The add-on tests' session fixtures, defined once here for every module (a
# module importing them itself would get its own instances: one zip build and
# one set of Blender installs per module instead of per session).
from blender_support import addon_zip, any_blender_env, blender_env, built_zip, installed_addon_dir  # noqa: F401


@pytest.fixture(scope="session")
def repo_dir():
    return REPO


@pytest.fixture(scope="session")
def build_dir():
    path = paths.build_dir()
    if not paths.library_path(path).exists():
        pytest.fail("no build at %s: run scripts/test.sh (it builds first)" % path)
    return path


@pytest.fixture(scope="session")
def library_path(build_dir):
    return paths.library_path(build_dir)


@pytest.fixture(scope="session")
def tool_path(build_dir):
    return build_dir / "bin" / "developable"


@pytest.fixture(scope="session")
def library(library_path):
    """The engine of the build under test, loaded into addon/core/native.py (the one
    binding): tests call native.run(...); raw C ABI tests call library.dev_*."""
    return native.load(path=library_path)


@pytest.fixture(scope="session")
def meshes_dir():
    if not paths.MESHES.is_dir():
        pytest.skip("../shared/meshes is not beside the checkout")
    return paths.MESHES


# -- running in parallel --------------------------------------------------------------
# scripts/test.sh runs pytest-xdist with one worker per core and --dist loadgroup.
# A test that uses a module-scoped fixture defined beside it (a shared Blender
# start-up, a pattern unfolded once) is put in one xdist_group with the
# module's other users of such fixtures, per Blender for the add-on modules
# whose fixture is per Blender; the other tests are handed out one at a time.
# The longest units go first (FIRST: the ASan run of test_hardening.py and
# the fuzz run take about a minute each), so that no worker is left alone
# with one of them at the end.
FIRST = (
    "test_hardening_sanitizers.py::test_engine_suite_under_asan_and_ubsan[tests/test_hardening.py]",
    "test_hardening_sanitizers.py::test_fuzz_for_a_minute",  # 60 s on one core
    "test_hardening.py::test_two_million_faces_work_or_are_refused_cleanly",
    "test_hardening_sanitizers.py",  # the other engine files under ASan
    "test_families.py",
    "test_pattern.py",
)  # rasterising the human figure's sheets


# -- the quick tier --------------------------------------------------------------------
# `bash scripts/test.sh --quick` (pytest -m "not slow") leaves out what takes minutes
# on the 2-core machine and is covered in kind by a quicker test: the engine suite
# again under ASan/UBSan and the fuzz run (their builds alone take minutes after a
# change to native/), the two-million-face refusal, the held-out sweeps of the
# families and of closed and open objects, the human figure's rasterised sheets, the larger
# meshes' least motion, and the add-on on the bpy wheels (4.2, 5.0: Blender 3.4
# runs every add-on test). CI and scripts/test.sh run everything.
SLOW = (
    "test_hardening_sanitizers.py",
    "test_hardening.py::test_two_million_faces_work_or_are_refused_cleanly",
    "test_hardening.py::test_the_coupled_solver_is_refused_sooner",
    "test_families.py",
    "test_objects.py",
    "test_objects_pieces.py::test_open_objects_come_back_flat_and_ruled",
    "test_assemblies_engine.py",
    "test_pattern.py::test_rasterised_sheets_are_not_blank",
    "test_segmentation.py::test_human_woman_is_made_piecewise_developable",
    "test_segmentation.py::test_whole_objects_with_the_defaults_bend_without_crumpling",
    "test_determinism.py::test_segmented_runs_repeat_bit_for_bit",
    "test_engine.py::test_larger_meshes_have_least_motions_candidates",
    "test_engine.py::test_a_sheet_above_the_old_size_switch_keeps_its_shape",
)
WHEEL_BLENDERS = ("4.2", "5.0")


def _slow(item):
    """Whether the test belongs to the full suite only (SLOW, or an add-on test on a bpy wheel)."""
    names = (item.path.name, "%s::%s" % (item.path.name, item.originalname))
    if any(name in SLOW for name in names):
        return True
    callspec = getattr(item, "callspec", None)
    if callspec is None:
        return False
    return any(str(value) in WHEEL_BLENDERS for name, value in callspec.params.items() if "blender" in name)


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: full suite only, left out by scripts/test.sh --quick (conftest.SLOW)")


def _group(item):
    """The xdist group of a test, or None (see above)."""
    module = item.nodeid.split("::")[0]
    shared = False
    for name in item.fixturenames:
        for fixturedef in item._fixtureinfo.name2fixturedefs.get(name, ()):
            if fixturedef.scope == "module" and fixturedef.baseid.split("::")[0] == module:
                shared = True
    if not shared:
        return None
    callspec = getattr(item, "callspec", None)
    blender = callspec.params.get("any_blender_env") if callspec else None
    return module + ("[%s]" % blender if blender else "")


def _rank(item):
    """Where the test's unit is in FIRST (a module, a test or one of its parameters)."""
    names = (item.path.name, "%s::%s" % (item.path.name, item.originalname), "%s::%s" % (item.path.name, item.name))
    for i, first in enumerate(FIRST):
        if first in names:
            return i
    return len(FIRST)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    for item in items:
        group = _group(item)
        if group:
            item.add_marker(pytest.mark.xdist_group(group))
        if _slow(item):
            item.add_marker(pytest.mark.slow)
    items.sort(key=_rank)  # stable: the others keep pytest's order

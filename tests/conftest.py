"""Shared fixtures: where the build and the test meshes are.

scripts/test.sh builds before running pytest; run pytest alone only after a
build (DEVELOPABLE_BUILD_DIR overrides the build folder, default build/).
Tests and bench share the development kit devkit/ at the repository root."""
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))  # devkit

from devkit import paths  # noqa: E402
from devkit.binding import native  # noqa: E402
# The add-on tests' session fixtures, defined once here for every module (a
# module importing them itself would get its own instances: one zip build and
# one set of Blender installs per module instead of per session).
from blender_support import (addon_zip, any_blender_env, blender_env,  # noqa: E402,F401
                             built_zip, installed_addon_dir)


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
    """The engine of the build under test, loaded into addon/native.py (the one
    binding): tests call native.run(...); raw C ABI tests call library.dev_*."""
    return native.load(path=library_path)


@pytest.fixture(scope="session")
def meshes_dir():
    if not paths.MESHES.is_dir():
        pytest.skip("../shared/meshes is not beside the checkout")
    return paths.MESHES

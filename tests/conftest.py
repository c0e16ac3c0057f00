"""Shared fixtures: where the build and the test meshes are.

scripts/test.sh builds before running pytest; run pytest alone only after a
build (DEVELOPABLE_BUILD_DIR overrides the build folder, default build/)."""
import os
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
sys.path.insert(0, str(REPO))  # devkit

import engine as engine_module  # noqa: E402


@pytest.fixture(scope="session")
def repo_dir():
    return REPO


@pytest.fixture(scope="session")
def build_dir():
    path = pathlib.Path(os.environ.get("DEVELOPABLE_BUILD_DIR", REPO / "build"))
    if not (path / "lib" / "libdevelopable.so").exists():
        pytest.fail("no build at %s: run scripts/test.sh (it builds first)" % path)
    return path


@pytest.fixture(scope="session")
def library_path(build_dir):
    return build_dir / "lib" / "libdevelopable.so"


@pytest.fixture(scope="session")
def tool_path(build_dir):
    return build_dir / "bin" / "developable"


@pytest.fixture(scope="session")
def engine(library_path):
    return engine_module.Engine(str(library_path))


@pytest.fixture(scope="session")
def meshes_dir():
    path = REPO.parent / "shared" / "meshes"
    if not path.is_dir():
        pytest.skip("../shared/meshes is not beside the checkout")
    return path

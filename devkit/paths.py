"""Where things are, resolved from this checkout (never absolute paths)."""
import os
import pathlib

REPO = pathlib.Path(__file__).resolve().parent.parent
# The shared folder (paper, test meshes with their licences) sits beside the checkout.
SHARED = REPO.parent / "shared"
MESHES = SHARED / "meshes"


def build_dir():
    """$DEVELOPABLE_BUILD_DIR, else the checkout's build/."""
    return pathlib.Path(os.environ.get("DEVELOPABLE_BUILD_DIR", REPO / "build"))


def library_path(build=None):
    """The engine library of a build folder (default build_dir())."""
    return pathlib.Path(build or build_dir()) / "lib" / "libdevelopable.so"

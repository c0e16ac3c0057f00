"""addon/native.py, the one binding of the C ABI, as a plain module.

The add-on package's __init__ imports bpy, so `addon.native` cannot be
imported outside Blender; this loads the file itself, once per process, as
the module `developable_native`:

    from devkit.binding import native
    native.load(path=devkit.paths.library_path())
    result = native.run(positions, triangles, params={"max_iterations": 5})"""
import importlib.util
import sys

from .paths import REPO

_NAME = "developable_native"


def _load():
    if _NAME in sys.modules:
        return sys.modules[_NAME]
    spec = importlib.util.spec_from_file_location(_NAME, REPO / "addon" / "native.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[_NAME] = module
    spec.loader.exec_module(module)
    return module


native = _load()

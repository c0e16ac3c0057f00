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

# The enumerated parameters by name, as benchmark cases and reports spell them.
ENUMS = {
    "mode": {"refit": native.MODE_REFIT, "paper": native.MODE_PAPER},
    "solver": {"decoupled": native.SOLVER_DECOUPLED, "coupled": native.SOLVER_COUPLED},
    "seams": {"free": native.SEAMS_FREE, "pinned": native.SEAMS_PINNED},
}


def params_from_names(params):
    """dev_params values with enumerations given by name ({"mode": "paper"})
    turned into the binding's numbers; unknown names raise KeyError."""
    return {
        key: ENUMS[key][value] if key in ENUMS and isinstance(value, str) else value for key, value in params.items()
    }


def enum_name(key, value):
    """The name of an enumerated parameter's value (its number if unknown)."""
    return next((name for name, number in ENUMS[key].items() if number == value), value)

"""addon/core/native.py, the one binding of the C ABI, for tests and benchmarks.

The add-on's core imports no bpy (addon/__init__.py imports nothing at module
level), so it is imported as a plain package from the checkout (on sys.path
whenever devkit is importable):

    from devkit.binding import native      # the same module as addon.core.native
    native.load(path=devkit.paths.library_path())
    result = native.run(positions, triangles, params={"max_iterations": 5})"""
from addon.core import native  # the checkout holds devkit/ and addon/ side by side

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

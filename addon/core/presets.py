# SPDX-License-Identifier: GPL-3.0-or-later
"""The jobs (presets): what a mesh is for, in the user's words, and the
settings each implies (no bpy). Values a job does not name keep the General
(engine default) value. docs/addon.md says which job suits which input."""

GENERAL = {
    "move_limit": 1.0,
    "limit_in_edges": False,
    "tolerance": 10.0,
    "omega": 5.0,
    "max_iterations": 400,
    "mode": "REFIT",
    "solver": "DECOUPLED",
    "pin_boundary": False,
    "use_mls_weights": True,
    "stop_relative_change": 0.001,
    "developable_threshold": -10,
    "segmentation": "AUTO",
    "auto_target_patches": True,
    "auto_segment_max_error": True,
    "seams": "FREE",
    "auto_grid_resolution": True,
    "auto_target_smoothing": True,
    "polish": "AUTO",
    "polish_smoothed_input": True,
}
PRESETS = {
    "GENERAL": {},
    "SHEET": {"segmentation": "OFF", "move_limit": 2.0},
    "DUCT": {"pin_boundary": True},
    "GARMENT": {"segmentation": "AUTO", "move_limit": 3.0},
    "OBJECT": {"segmentation": "ON", "move_limit": 1.0},
    "PAPER": {
        "mode": "PAPER",
        "solver": "COUPLED",
        "limit_in_edges": True,
        "tolerance": 10.0,
        "omega": 5.0,
        "pin_boundary": True,
        "seams": "PINNED",
    },
    "CUSTOM": None,  # set by hand: nothing to apply
}
PRESET_ITEMS = [
    ("GENERAL", "General", "Automatic choices for any mesh; the shape may move 1 % of its size"),
    (
        "SHEET",
        "Clean up a scanned sheet",
        "One piece (no splitting), for a noisy scan or a sculpted panel that should become one smooth "
        "developable sheet, its ragged edge smoothed too; moves at most 2 % of the size",
    ),
    (
        "DUCT",
        "Sheet metal / duct",
        "A part whose edges must mate with others (a duct fitting its pipe, a panel its frame): the "
        "boundary is kept exactly, the rest may move 1 % of the size",
    ),
    (
        "GARMENT",
        "Garment / soft piece",
        "A cloth-like piece that may split where it curves both ways; moves at most 3 % of the size",
    ),
    (
        "OBJECT",
        "Whole object into pieces",
        "A closed object (a character, a toy) split into developable pieces that meet at seams; moves "
        "at most 1 % of the size",
    ),
    (
        "PAPER",
        "Paper's settings",
        "As in the paper: fixed targets, the coupled system, the boundary and the seams pinned, limit "
        "10 average edge lengths (E_allow = 10 AE, \u03c9 = 5)",
    ),
    ("CUSTOM", "Custom", "Settings changed by hand"),
]
LABELS = {key: label for key, label, _ in PRESET_ITEMS}


def settings_of(preset):
    """Every setting the job implies (None for Custom)."""
    values = PRESETS.get(preset)
    return None if values is None else dict(GENERAL, **values)

# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender properties: the settings of a run (one definition shared by the
scene settings the panel shows and by the operator, so the button, the menu
entry and Adjust Last Operation use the same values), the presets, and the
per-object record of the last run.

Labels are in the user's words; the paper's symbols are in the tooltips only.
Parameters whose engine value has an "automatic" sentinel (0 or -1) get an
"Automatic" switch instead of showing the bare number."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from . import gauss_image, writeback
from .core import native, presets

# The jobs (presets) and the settings each implies: core/presets.py.
GENERAL, PRESETS, PRESET_ITEMS = presets.GENERAL, presets.PRESETS, presets.PRESET_ITEMS

# What is made developable when the object has modifiers: the shape the viewport
# shows (the modifiers' result) or the mesh beneath them. A shape key cannot
# carry the modifiers' result when they change the topology, and once a mesh has
# shape keys Blender refuses to apply its modifiers: hence a new object, or the
# modifiers applied first.
MODIFIER_ITEMS = [
    (
        "NEW_OBJECT",
        "As Shown: New Object",
        "Make the shape you see developable (the modifiers' result), as a new object beside this one; "
        "this object and its modifiers are left as they are",
    ),
    (
        "APPLY",
        "As Shown: Apply Them",
        "Apply the modifiers (and the shape keys shown) to this object first, as Object > Convert > "
        "Mesh does, then make it developable",
    ),
    (
        "BASE",
        "The Mesh Beneath",
        "Make the mesh without its modifiers developable; the modifiers stay on top of the result, "
        "and its shape key then stops Blender from applying them",
    ),
]
MODIFIER_WORDS = {
    "NEW_OBJECT": "the shape as shown, into a new object",
    "APPLY": "the shape as shown, modifiers applied",
    "BASE": "the mesh beneath its modifiers",
}

# Engine fields whose sentinel means "automatic": name -> sentinel.
AUTOMATIC = {"target_patches": 0, "segment_max_error": 0.0, "grid_resolution": 0, "target_smoothing": -1}

MODE_ITEMS = [
    (
        "REFIT",
        "Refit Each Step",
        "Refit the ideal curve and the target normals from the deformed "
        "mesh every iteration (more developable; default)",
        native.MODE_REFIT,
    ),
    (
        "PAPER",
        "Fixed (Paper)",
        "As in the paper: one ideal curve and one set of target normals; " "the system W A^T A W is factored once",
        native.MODE_PAPER,
    ),
]
SEGMENTATION_ITEMS = [
    (
        "AUTO",
        "Automatic",
        "Split into pieces when the mesh is closed or one ideal curve does not fit "
        "its whole normal image; an open mesh is also tried as one piece, kept if that comes out more "
        "developable",
        -1,
    ),
    ("OFF", "One Piece", "Never split: one ideal curve for the whole mesh", 0),
    ("ON", "Always Split", "Always split the mesh into pieces by curvature (paper Fig. 1 a-b)", 1),
]
SEAMS_ITEMS = [
    ("FREE", "Seams Move", "One global solve; the seams between pieces move freely", native.SEAMS_FREE),
    (
        "PINNED",
        "Seams Pinned",
        "As in the paper: piece borders are pinned and the pieces are " "deformed one by one",
        native.SEAMS_PINNED,
    ),
]
POLISH_ITEMS = [
    ("AUTO", "Automatic", "Finish with the angle polish, except with fixed (paper) targets", -1),
    (
        "ON",
        "On",
        "After the deformation, move the vertices a little so that the angles around "
        "every vertex sum to 360 degrees (angle defect zero)",
        1,
    ),
    ("OFF", "Off", "Stop after the deformation, as in the paper", 0),
]
SOLVER_ITEMS = [
    (
        "DECOUPLED",
        "Fast",
        "The normal rows go to the right-hand side: one n x n matrix shared by " "x, y and z, factored once (default)",
        native.SOLVER_DECOUPLED,
    ),
    (
        "COUPLED",
        "Coupled (Paper)",
        "The paper's 11 rows per triangle (Eq. 3-4) in one 3n x 3n "
        "system W A^T A W x = W A^T c (Eq. 7), refactored when the targets change",
        native.SOLVER_COUPLED,
    ),
]

ENUM_VALUES = {
    "mode": {i[0]: i[3] for i in MODE_ITEMS},
    "segmentation": {i[0]: i[3] for i in SEGMENTATION_ITEMS},
    "seams": {i[0]: i[3] for i in SEAMS_ITEMS},
    "solver": {i[0]: i[3] for i in SOLVER_ITEMS},
    "polish": {i[0]: i[3] for i in POLISH_ITEMS},
}

_APPLYING = [False]  # a preset (or a copy of settings) is being applied


def _mark_custom(self, context):
    """A value changed by hand: the preset no longer describes the settings."""
    if not _APPLYING[0] and self.preset != "CUSTOM":
        _APPLYING[0] = True
        try:
            self.preset = "CUSTOM"
        finally:
            _APPLYING[0] = False


def apply_preset(owner, preset):
    values = PRESETS.get(preset)
    if values is None:
        return
    _APPLYING[0] = True
    try:
        for name, value in dict(GENERAL, **values).items():
            setattr(owner, name, value)
    finally:
        _APPLYING[0] = False


def _preset_update(self, context):
    if not _APPLYING[0]:
        apply_preset(self, self.preset)


def engine_property_definitions():
    """name -> a new bpy property, for every field of dev_params."""
    u = _mark_custom
    return {
        "omega": FloatProperty(
            name="Flattening Strength",
            default=5.0,
            min=1e-6,
            soft_min=0.1,
            soft_max=100.0,
            update=u,
            description="How hard each face is pulled towards its developable "
            "direction: higher is more developable and moves the shape more (the paper's normal "
            "weight \u03c9, Eq. 2-3)",
        ),
        "tolerance": FloatProperty(
            name="Limit in Edge Lengths",
            default=10.0,
            min=0.0,
            soft_max=20.0,
            update=u,
            description="The farthest a vertex may move, in average edge lengths (the paper's "
            "E_allow in multiples of AE; Table I: 0.02 keeps the shape, 10 is nearly free; "
            "0 = no limit). Used when 'Limit in Edge Lengths' is ticked",
        ),
        "max_iterations": IntProperty(
            name="Max Iterations",
            default=400,
            min=1,
            soft_max=1000,
            update=u,
            description="The most deformation steps (MaxIter); runs usually stop earlier, when "
            "the result stops improving",
        ),
        "mode": EnumProperty(
            name="Targets",
            items=MODE_ITEMS,
            default="REFIT",
            update=u,
            description="How the target directions of the faces are updated between steps",
        ),
        "pin_boundary": BoolProperty(
            name="Keep the Boundary",
            default=False,
            update=u,
            description="Every boundary vertex stays where it is, so mating edges keep their lengths and "
            "shape exactly (a duct that must fit its pipe, a panel its frame); on for the job 'Sheet "
            "metal / duct'. Off, the boundary may move like the rest (a scan's ragged edge is smoothed)",
        ),
        "use_mls_weights": BoolProperty(
            name="Soft Falloff Around Pins",
            default=True,
            update=u,
            description="Vertices near pins move less (the paper's moving-least-squares "
            "weights 1/(d^2 + \u03b5^2), Eq. 5)",
        ),
        "stop_relative_change": FloatProperty(
            name="Stop Below Change",
            default=0.001,
            min=0.0,
            soft_max=1.0,
            precision=4,
            subtype="PERCENTAGE",
            update=u,
            description="Stop when the mean curvature changes by less than this between two "
            "steps (the paper's \u0394C_max = 0.001 %)",
        ),
        "developable_threshold": IntProperty(
            name="Flat Enough Below 10^",
            default=-10,
            min=-15,
            max=-1,
            update=u,
            description="A mesh whose mean |angle defect| is below 10 to this power (rad) "
            "already counts as developable and is returned unchanged (default -10: 1e-10 rad)",
        ),
        "segmentation": EnumProperty(
            name="Pieces",
            items=SEGMENTATION_ITEMS,
            default="AUTO",
            update=u,
            description="Split the mesh into pieces by curvature, each with its own ideal curve "
            "(paper Fig. 1, Fig. 5)",
        ),
        "target_patches": IntProperty(
            name="Number of Pieces",
            default=8,
            min=1,
            soft_max=64,
            update=u,
            description="How many pieces to split into when not automatic",
        ),
        "segment_max_error": FloatProperty(
            name="Piece Fit Error",
            default=0.1,
            min=1e-4,
            soft_max=1.0,
            precision=3,
            subtype="ANGLE",
            update=u,
            description="The largest cone-fitting error allowed in one piece when not automatic",
        ),
        "seams": EnumProperty(
            name="Seams",
            items=SEAMS_ITEMS,
            default="FREE",
            update=u,
            description="How the borders between pieces are treated",
        ),
        "grid_resolution": IntProperty(
            name="Curve Search Grid",
            default=64,
            min=8,
            soft_max=512,
            update=u,
            description="Cells per side of the grid in which the ideal curve is searched (the "
            "radial effect field of Eq. 1) when not automatic; automatic: 2 sqrt(faces of the "
            "piece), from 32 to 128",
        ),
        "solver": EnumProperty(
            name="Solver",
            items=SOLVER_ITEMS,
            default="DECOUPLED",
            update=u,
            description="How the linear system is built (Fixed targets always use the coupled " "system)",
        ),
        "target_smoothing": IntProperty(
            name="Target Smoothing",
            default=1,
            min=0,
            max=100,
            soft_max=5,
            update=u,
            description="Rounds of averaging each face's target direction with its neighbours' "
            "in the same piece, so that a piece curved both ways follows a smooth target instead "
            "of crumpling. Automatic: one round on a split mesh, none on one piece",
        ),
        "polish": EnumProperty(
            name="Angle Polish",
            items=POLISH_ITEMS,
            default="AUTO",
            update=u,
            description="Finish by driving the angle defect of every vertex inside the pieces "
            "to zero with small moves, within the same limit (beyond the paper)",
        ),
        "polish_smoothed_input": BoolProperty(
            name="Polish Smoothed Mesh",
            default=True,
            update=u,
            description="Also polish the mesh with its "
            "noise smoothed (each vertex put on a quadric fitted to its neighbours, creases kept) "
            "and keep that if it moved the mesh less and is as flat: a noisy scan then loses its "
            "noise, not its shape; on a one-piece sheet also the nearest developable mesh found "
            "from the smoothed one (beyond the paper)",
        ),
    }


def pin_property_definitions():
    return {
        "pin_group": StringProperty(
            name="Pin Group",
            default="",
            description="Vertex group whose vertices (weight > 0) stay where they are "
            "(position constraints of Eq. 5-6)",
        ),
        "pin_selection": BoolProperty(
            name="Pin Selection",
            default=True,
            description="In Edit mode, the selected vertices stay where they are too",
        ),
        "gauss_image": BoolProperty(
            name="Gauss Image",
            default=False,
            description="After the run, build the Gauss image beside the object: a unit sphere, "
            "the face normals before and after as dots, and the ideal curves",
        ),
    }


def extra_property_definitions():
    """The user-level settings that are not dev_params fields."""
    u = _mark_custom
    defs = {
        "preset": EnumProperty(
            name="Job",
            items=PRESET_ITEMS,
            default="GENERAL",
            update=_preset_update,
            description="What the mesh is for: sets the settings below together",
        ),
        "move_limit": FloatProperty(
            name="Shape May Move",
            default=1.0,
            min=0.0,
            soft_min=0.1,
            soft_max=20.0,
            max=100.0,
            precision=1,
            subtype="PERCENTAGE",
            update=u,
            description="How far the shape may move: the farthest any vertex may go, in % of the "
            "object's size (its bounding-box diagonal). 0 = no limit",
        ),
        "limit_in_edges": BoolProperty(
            name="Limit in Edge Lengths",
            default=False,
            update=u,
            description="Set the limit in average edge lengths (the paper's E_allow) instead of " "'Shape May Move'",
        ),
        "modifiers": EnumProperty(
            name="Modifiers",
            items=MODIFIER_ITEMS,
            default="NEW_OBJECT",
            description="What is made developable when the object has modifiers shown in the viewport",
        ),
    }
    for name in AUTOMATIC:
        defs["auto_" + name] = BoolProperty(
            name="Automatic", default=True, update=u, description="Let the engine choose (untick to set the value)"
        )
    return defs


def all_property_definitions():
    return dict(engine_property_definitions(), **pin_property_definitions(), **extra_property_definitions())


ENGINE_PARAMETERS = tuple(engine_property_definitions().keys())
# dev_params fields set from other settings: max_move from 'Shape May Move'.
DERIVED_PARAMETERS = ("max_move",)
PIN_PARAMETERS = tuple(pin_property_definitions().keys())
EXTRA_PARAMETERS = tuple(extra_property_definitions().keys())
# Copy order: the preset first (it sets the others), then everything else.
SETTINGS = ("preset",) + ENGINE_PARAMETERS + PIN_PARAMETERS + tuple(n for n in EXTRA_PARAMETERS if n != "preset")
assert set(ENGINE_PARAMETERS + DERIVED_PARAMETERS) == set(native.PARAM_NAMES), "a dev_params field has no property"


def copy_settings(source, target, names=SETTINGS):
    """Copies settings between the scene settings and an operator, leaving the
    preset as it was at the source (no preset is re-applied on the way)."""
    _APPLYING[0] = True
    try:
        for name in names:
            value = getattr(source, name)
            if getattr(target, name) != value:
                setattr(target, name, value)
    finally:
        _APPLYING[0] = False


def set_quietly(owner, values):
    """Sets values without turning the preset into Custom."""
    _APPLYING[0] = True
    try:
        for name, value in values.items():
            setattr(owner, name, value)
    finally:
        _APPLYING[0] = False


def engine_values(owner):
    """dict for native.run from an object holding the settings. The move limit
    goes to the engine once, in the unit the user set it in: 'Shape May Move'
    as max_move (a share of the bounding box's diagonal, no limit in edge
    lengths), or with 'Limit in Edge Lengths' the tolerance in average edge
    lengths (no limit by size). The engine reports the limit it used
    (stats["move_limit"], in the mesh's units)."""
    values = {}
    for name in ENGINE_PARAMETERS:
        value = getattr(owner, name)
        if name in ENUM_VALUES:
            value = ENUM_VALUES[name][value]
        elif isinstance(value, bool):
            value = int(value)
        values[name] = value
    for name, sentinel in AUTOMATIC.items():
        if getattr(owner, "auto_" + name):
            values[name] = sentinel
    values["stop_relative_change"] = owner.stop_relative_change / 100.0
    values["developable_threshold"] = 10.0**owner.developable_threshold
    if owner.limit_in_edges:
        values["max_move"] = 0.0
    else:
        values["max_move"] = owner.move_limit / 100.0
        values["tolerance"] = 0.0
    return values


def move_limit_words(owner):
    """The user's move limit in words ("1 %", "10 edge lengths"), "" for none."""
    if owner.limit_in_edges:
        return "%g edge lengths" % owner.tolerance if owner.tolerance > 0 else ""
    return "%g %%" % owner.move_limit if owner.move_limit > 0 else ""


# ---------------------------------------------------------------------------
# Scene settings shown by the panel (the operator reads them for every value
# the caller did not set).


class DEVELOPABLE_PG_settings(PropertyGroup):
    __annotations__ = all_property_definitions()


def _show_after_update(self, context):
    obj = self.id_data
    if obj is not None and obj.type == "MESH":
        writeback.show_colours(obj, after=self.show_after)


def _gauss_visible_update(self, context):
    gauss_image.set_visible(self.id_data, self.show_gauss_image)


def _share(name, text):
    return FloatProperty(name=name, precision=4, subtype="FACTOR", description=text)


class DEVELOPABLE_PG_result(PropertyGroup):
    """The last run on this object (stored in the .blend): the engine's
    figures as it reported them, and the add-on's words for them."""

    has_result: BoolProperty(name="Has Result", default=False)
    verdict: EnumProperty(
        name="Verdict",
        default="IMPROVED",
        items=[
            ("IMPROVED", "Improved", "The mesh is more developable and no figure got worse"),
            ("GATHERED", "Curvature on seams", "More vertices are flat; the curvature left gathered"),
            ("CRUMPLED", "Flat, but crumpled", "Flat, but many flat vertices are facets, not one smooth bend"),
            ("WORSE", "Worse", "A figure got worse: the key is left at 0"),
            ("UNCHANGED", "Unchanged", "Nothing changed: nothing better was found"),
            ("DEVELOPABLE", "Already developable", "Nothing to do: the mesh was developable already"),
        ],
    )
    message: StringProperty(name="Message", description="What the run means, in words")
    engine_result: StringProperty(name="Engine says", description="The engine's own sentence about its result")
    error: StringProperty(
        name="Error", description="Why the last try on this object failed (empty when it ran); the figures are older"
    )
    job: StringProperty(name="Job", description="The job the run used")
    shape_source: StringProperty(name="Shape", description="Which shape was made developable")
    interior_vertices: IntProperty(name="Inner vertices", description="Vertices not on the boundary")
    e_before: FloatProperty(
        name="Mean curvature before",
        precision=6,
        description="E_before: mean |angle defect| over interior vertices (rad)",
    )
    e_after: FloatProperty(
        name="Mean curvature after", precision=6, description="E_after: mean |angle defect| after the run (rad)"
    )
    max_before: FloatProperty(name="Largest curvature before", precision=6)
    max_after: FloatProperty(name="Largest curvature after", precision=6)
    change_percent: FloatProperty(
        name="Change %", precision=2, description="\u0394E = 100 (E_after - E_before) / E_before"
    )
    flat_threshold: FloatProperty(
        name="Flat below",
        precision=6,
        description="The |angle defect| (rad) under which the engine calls a vertex flat",
    )
    flat_before: _share("Flat before", "Share of interior vertices with |angle defect| under the flat threshold")
    flat_after: _share("Flat after", "The same share after the run")
    ruled_before: _share(
        "Flat and ruled before",
        "Share of interior vertices that are flat and whose faces bend about one axis (not crumpled into facets)",
    )
    ruled_after: _share("Flat and ruled after", "The same share after the run")
    crumpled_before: _share("Crumpled before", "Share of interior vertices flat but not ruled: a zigzag of facets")
    crumpled_after: _share("Crumpled after", "The same share after the run")
    faces_turned: IntProperty(
        name="Faces turned over",
        description="Faces whose normal turned by more than 90 degrees (not counting faces already turned "
        "in the input)",
    )
    size: FloatProperty(name="Size", precision=5, description="Bounding-box diagonal of the input (world space)")
    largest_move: FloatProperty(
        name="Largest move made", precision=5, description="The farthest any vertex moved (world units)"
    )
    move_percent: FloatProperty(
        name="Largest move %", precision=3, description="The largest move made, in % of the object's size"
    )
    move_limit: FloatProperty(
        name="Move limit used",
        precision=5,
        description="The farthest a vertex was allowed to move, as the engine applied it (world units; 0: none)",
    )
    time_ms: FloatProperty(name="Time (ms)", precision=1, description="t_T: total engine time")
    time_decompose_ms: FloatProperty(name="t_D (ms)", precision=1)
    time_iterate_ms: FloatProperty(name="t_I (ms)", precision=1)
    iterations: IntProperty(name="Iterations")
    polish_iterations: IntProperty(name="Polish steps", description="Steps of the angle polish kept")
    result_origin: StringProperty(
        name="Made by", description="Which of the engine's methods made the result (native.ORIGIN_NAMES)"
    )
    stop_reason: StringProperty(name="Stopped", description="Why the engine's iteration stopped")
    average_edge: FloatProperty(name="AE", precision=5, description="Average edge length")
    patches: IntProperty(name="Pieces")
    curves: IntProperty(name="Curves")
    pinned: IntProperty(name="Pinned vertices")
    unwelded: IntProperty(
        name="Unwelded vertices", description="Boundary vertices lying on another boundary vertex (a seam never welded)"
    )
    world_space: BoolProperty(
        name="World space", default=False, description="The object's scale was taken into account"
    )
    colour_scale: FloatProperty(
        name="Colour scale",
        precision=6,
        description="Angle defect (rad) shown as full red (+) / full blue (-) in both colour attributes; "
        "white is 0. Never below the engine's flat threshold, so a developable mesh is white",
    )
    show_after: BoolProperty(
        name="Show After",
        default=True,
        update=_show_after_update,
        description="Show the defect colours after (on) or before (off) the run",
    )
    show_gauss_image: BoolProperty(
        name="Show Gauss Image",
        default=True,
        update=_gauss_visible_update,
        description="Show or hide this object's Gauss image objects",
    )
    gauss_collection: PointerProperty(
        name="Gauss Image", type=bpy.types.Collection, description="The collection holding this object's Gauss image"
    )


classes = (DEVELOPABLE_PG_settings, DEVELOPABLE_PG_result)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.developable = PointerProperty(type=DEVELOPABLE_PG_settings)
    bpy.types.Object.developable = PointerProperty(type=DEVELOPABLE_PG_result)


def unregister():
    del bpy.types.Object.developable
    del bpy.types.Scene.developable
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)

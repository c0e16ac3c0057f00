# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender properties: the engine parameters (one property per dev_params
field, shared by the operator and the panel's scene settings), the pin
options, and the per-object record of the last run."""

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty,
                       PointerProperty, StringProperty)
from bpy.types import PropertyGroup

from . import native

# ---------------------------------------------------------------------------
# Engine parameters. Defaults are those of dev_default_params (developable.h);
# tests check the two agree.

MODE_ITEMS = [
    ("REFIT", "Refit", "Refit the ideal curve and the target normals from the deformed mesh "
     "every iteration (more developable, default)", native.MODE_REFIT),
    ("PAPER", "Paper", "As in the paper: one ideal curve and one set of target normals; the "
     "11-row system W A^T A W is factored once", native.MODE_PAPER),
]
SEGMENTATION_ITEMS = [
    ("AUTO", "Automatic", "Segment by curvature only when one ideal curve does not fit the "
     "whole normal image", -1),
    ("OFF", "Off", "One patch: one ideal curve for the whole mesh", 0),
    ("ON", "On", "Always segment the mesh into patches by curvature (paper Fig. 1 a-b)", 1),
]
SEAMS_ITEMS = [
    ("FREE", "Free", "One global solve; seams between patches move freely", native.SEAMS_FREE),
    ("PINNED", "Pinned", "As in the paper: patch borders are pinned and the patches are "
     "deformed one by one", native.SEAMS_PINNED),
]

SOLVER_ITEMS = [
    ("DECOUPLED", "Decoupled", "The normal rows go to the right-hand side: one n x n matrix shared by "
     "x, y and z, factored once even when the target normals change (fast, default)",
     native.SOLVER_DECOUPLED),
    ("COUPLED", "Coupled", "The paper's 11 rows per triangle (Eq. 3-4) in one 3n x 3n system "
     "W A^T A W x = W A^T c (Eq. 7), refactored when the targets change", native.SOLVER_COUPLED),
]

ENUM_VALUES = {
    "mode": {i[0]: i[3] for i in MODE_ITEMS},
    "segmentation": {i[0]: i[3] for i in SEGMENTATION_ITEMS},
    "seams": {i[0]: i[3] for i in SEAMS_ITEMS},
    "solver": {i[0]: i[3] for i in SOLVER_ITEMS},
}


def engine_property_definitions():
    """name -> a new bpy property, for every field of dev_params."""
    return {
        "omega": FloatProperty(
            name="Normal Weight (\u03c9)", default=5.0, min=1e-6, soft_min=0.1, soft_max=100.0,
            description="\u03c9 of Eq. 2-3: weight of the rows n_ob\u00b7(v'j - v'1) = 0 that pull "
            "each face towards its objective normal. Larger: more developable, more shape change"),
        "tolerance": FloatProperty(
            name="Tolerance (E_allow)", default=10.0, soft_min=0.0, soft_max=20.0,
            description="E_allow: the largest distance a vertex may move, in multiples of the "
            "average edge length AE (Table I: 0.02 keeps the shape, 10 is nearly free). "
            "0 means no limit"),
        "max_iterations": IntProperty(
            name="Max Iterations", default=400, min=1, soft_max=1000,
            description="MaxIter: the largest number of deformation iterations (runs usually "
            "stop earlier, when the result stops improving)"),
        "mode": EnumProperty(
            name="Mode", items=MODE_ITEMS, default="REFIT",
            description="How the objective normals are updated between iterations"),
        "pin_boundary": BoolProperty(
            name="Pin Boundary", default=False,
            description="Position constraints at every boundary vertex (as in the paper's "
            "Fig. 3 and 4)"),
        "use_mls_weights": BoolProperty(
            name="MLS Weights", default=True,
            description="Eq. 5: moving-least-squares weights 1/(min_dist(v, constraints)^2 + "
            "\u03b5^2) around the pinned vertices (W of Eq. 6-7)"),
        "stop_relative_change": FloatProperty(
            name="Stop Change", default=1e-5, min=0.0, soft_max=0.01, precision=6,
            description="\u0394C_max: stop when the mean |angle defect| changes by less than this "
            "fraction between two iterations (paper: 0.001 % = 1e-5)"),
        "developable_threshold": FloatProperty(
            name="Developable Threshold", default=1e-10, min=0.0, soft_max=1e-3, precision=10,
            description="Mean |angle defect| (rad) below which the mesh already counts as "
            "developable and is returned unchanged"),
        "segmentation": EnumProperty(
            name="Segmentation", items=SEGMENTATION_ITEMS, default="AUTO",
            description="Curvature-based segmentation into patches, each with its own ideal "
            "curve (paper Fig. 1, Fig. 5)"),
        "target_patches": IntProperty(
            name="Patches", default=0, min=0, soft_max=64,
            description="Segmentation: the wanted number of patches; 0 = automatic"),
        "segment_max_error": FloatProperty(
            name="Patch Max Error", default=0.0, min=0.0, soft_max=1.0, precision=4,
            subtype="ANGLE",
            description="Segmentation: the largest cone-fitting error allowed in one patch; "
            "0 = the engine's default"),
        "seams": EnumProperty(
            name="Seams", items=SEAMS_ITEMS, default="FREE",
            description="How the borders between patches are treated"),
        "grid_resolution": IntProperty(
            name="Grid Resolution", default=0, min=0, soft_max=512,
            description="Cells per side of the radial effect field (Eq. 1) in which the "
            "skeleton of the normal image is found; 0 = automatic, 2 sqrt(faces of the patch) "
            "from 32 to 128"),
        "solver": EnumProperty(
            name="Solver", items=SOLVER_ITEMS, default="DECOUPLED",
            description="How the normal rows enter the linear system (Paper mode always uses "
            "the coupled system)"),
        "target_smoothing": IntProperty(
            name="Target Smoothing", default=-1, min=-1, max=100, soft_max=5,
            description="Rounds of averaging each face's objective normal with those of its "
            "neighbours in the same patch, so that a doubly curved patch follows a smooth "
            "target instead of crumpling; -1 = automatic (Refit mode: 1 on a segmented mesh; "
            "on one patch 0, then 1 if the run stalls with much curvature left)"),
    }


def pin_property_definitions():
    return {
        "pin_group": StringProperty(
            name="Pin Group", default="",
            description="Vertex group whose vertices (weight > 0) are pinned: position "
            "constraints of Eq. 5-6"),
        "pin_selection": BoolProperty(
            name="Pin Selection", default=True,
            description="In Edit mode, the selected vertices are pinned too"),
        "gauss_image": BoolProperty(
            name="Gauss Image", default=False,
            description="After the run, build the Gauss image beside the object: a unit sphere, "
            "the face normals before and after as points, and the ideal curves"),
    }


ENGINE_PARAMETERS = tuple(engine_property_definitions().keys())
PIN_PARAMETERS = tuple(pin_property_definitions().keys())
assert set(ENGINE_PARAMETERS) == set(native.PARAM_NAMES), "a dev_params field has no property"


def engine_values(owner):
    """dict for native.run from an object holding the engine properties."""
    values = {}
    for name in ENGINE_PARAMETERS:
        value = getattr(owner, name)
        if name in ENUM_VALUES:
            value = ENUM_VALUES[name][value]
        elif isinstance(value, bool):
            value = int(value)
        values[name] = value
    return values


# ---------------------------------------------------------------------------
# Scene settings shown by the panel (the Run button copies them into the operator).

class DEVELOPABLE_PG_settings(PropertyGroup):
    __annotations__ = dict(engine_property_definitions(), **pin_property_definitions())


def _show_after_update(self, context):
    from . import writeback
    obj = self.id_data
    if obj is not None and obj.type == 'MESH':
        writeback.show_colours(obj, after=self.show_after)


def _gauss_visible_update(self, context):
    from . import gauss_image
    gauss_image.set_visible(self.id_data, self.show_gauss_image)


class DEVELOPABLE_PG_result(PropertyGroup):
    """The last run on this object (stored in the .blend)."""
    has_result: BoolProperty(name="Has Result", default=False)
    e_before: FloatProperty(name="E before", precision=6,
                            description="E_before: mean |angle defect| over interior vertices (rad)")
    e_after: FloatProperty(name="E after", precision=6,
                           description="E_after: mean |angle defect| after the deformation (rad)")
    max_before: FloatProperty(name="Max defect before", precision=6)
    max_after: FloatProperty(name="Max defect after", precision=6)
    change_percent: FloatProperty(name="dE %", precision=2,
                                  description="\u0394E = 100 (E_after - E_before) / E_before")
    time_ms: FloatProperty(name="Time (ms)", precision=1, description="t_T: total engine time")
    time_decompose_ms: FloatProperty(name="t_D (ms)", precision=1)
    time_iterate_ms: FloatProperty(name="t_I (ms)", precision=1)
    iterations: IntProperty(name="Iterations")
    stop_reason: StringProperty(name="Stopped")
    max_move: FloatProperty(name="Largest move", precision=5,
                            description="Largest distance a vertex moved (object units)")
    average_edge: FloatProperty(name="AE", precision=5, description="Average edge length")
    max_move_ae: FloatProperty(name="Largest move / AE", precision=3)
    patches: IntProperty(name="Patches")
    curves: IntProperty(name="Curves")
    pinned: IntProperty(name="Pinned vertices")
    colour_scale: FloatProperty(
        name="Colour scale", precision=6,
        description="Angle defect (rad) shown as full red (+) / full blue (-) in both colour "
        "attributes; white is 0")
    show_after: BoolProperty(
        name="Show After", default=True, update=_show_after_update,
        description="Show the defect colours after (on) or before (off) the deformation")
    show_gauss_image: BoolProperty(
        name="Show Gauss Image", default=True, update=_gauss_visible_update,
        description="Show or hide this object's Gauss image objects")


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

# SPDX-License-Identifier: GPL-3.0-or-later
"""The curvature colours (no bpy): the angle defect of every vertex as a colour,
blue for negative, white for zero, red for positive, on one scale for the
before and after maps so that they compare directly."""

import numpy as np

# Colour of vertices where the angle defect is not defined (boundary).
BOUNDARY_COLOUR = (0.55, 0.55, 0.55, 1.0)


def colour_scale(defect_before, defect_after, interior, floor):
    """One scale for both colour maps: the 95th percentile of |defect| over the
    interior vertices of both states, so the maps compare directly, never
    below `floor` (the engine's flat threshold): a developable mesh, whose
    defects are rounding noise, is white, not full red and blue."""
    d = np.concatenate([np.abs(defect_before[interior]), np.abs(defect_after[interior])])
    d = d[np.isfinite(d)]
    scale = float(np.percentile(d, 95.0)) if d.size else 0.0
    return max(scale, float(floor))


def defect_colours(defect, interior, scale):
    """(n, 4) float32 linear RGBA: blue (-scale) .. white (0) .. red (+scale),
    grey where the defect is undefined."""
    t = np.clip(np.nan_to_num(defect / scale), -1.0, 1.0)
    n = defect.shape[0]
    rgba = np.ones((n, 4), dtype=np.float32)
    pos = t > 0
    neg = ~pos
    # positive: white -> red; negative: white -> blue
    rgba[pos, 1] = 1.0 - t[pos]
    rgba[pos, 2] = 1.0 - t[pos]
    rgba[neg, 0] = 1.0 + t[neg]
    rgba[neg, 1] = 1.0 + t[neg]
    rgba[~interior] = BOUNDARY_COLOUR
    return rgba

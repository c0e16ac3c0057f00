# SPDX-License-Identifier: GPL-3.0-or-later
"""How long a run is expected to take (no bpy), for the panel's line on
large meshes.

Expected run time on 2 cores, fitted to docs/benchmarks.md (10k-1M faces):
  decoupled factorisation   faces * 3 us * (faces / 1e5)^0.35, once
  one iteration             faces * 0.33 us on one patch, ~0.6 us segmented
  iterations                ~25 on one patch (the engine's Anderson
                            acceleration, above 25000 inner vertices),
                            ~300 segmented
  coupled factorisation     faces * 30 us * (faces / 1e4)^0.4: once in paper
                            mode, every iteration with the coupled solver
  angle polish              on one patch with least motion's candidates
                            7.6 s * (faces / 1e5)^0.75 (100k faces: 7.6 s,
                            1M: 43 s; docs/scans.md, 2 % noise), segmented
                            faces * 6 us (1M faces: 5.6 s), when it runs
max_iterations caps the iterations. Automatic segmentation is decided by the
engine, so the panel gives the range between the one-patch and the
segmented run; an open mesh it splits, up to 10000 interior vertices (about
SECOND_OPINION_FACES), is also run as one patch (docs/segmentation.md).
Issue 37 measured a 500k-face sheet at 81 s where this said about 21 s, before
least motion ran on large sheets; issue 38 asks for an engine-side fit."""

LARGE_MESH_FACES = 100_000
SECOND_OPINION_FACES = 20_000


def expected_seconds(faces, mode, solver, segmentation, fixed_patches, max_iterations, polish):
    """(shortest, longest) expected run time in seconds. mode: "REFIT" or
    "PAPER"; solver: "DECOUPLED" or "COUPLED"; segmentation: "AUTO", "OFF" or
    "ON"; fixed_patches: a number of pieces set by hand (> 1) or 0; polish:
    "AUTO", "ON" or "OFF" (the settings' identifiers)."""
    cap = int(max_iterations)
    coupled = faces * 30e-6 * (faces / 1e4) ** 0.4
    if mode == "PAPER":
        return (coupled,) * 2
    decoupled = faces * 3e-6 * (faces / 1e5) ** 0.35

    def run(iterations, per_face):
        iterations = min(cap, iterations)
        if solver == "COUPLED":
            return iterations * (coupled + faces * per_face)
        return decoupled + iterations * faces * per_face

    one_patch, segmented = run(25, 0.33e-6), run(300, 0.6e-6)
    if polish != "OFF":
        one_patch, segmented = one_patch + 7.6 * (faces / 1e5) ** 0.75, segmented + faces * 6e-6
    if segmentation == "OFF":
        return one_patch, one_patch
    if segmentation == "ON" or fixed_patches > 1:
        return segmented, segmented
    return one_patch, segmented + (one_patch if faces <= SECOND_OPINION_FACES else 0.0)

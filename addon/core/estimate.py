# SPDX-License-Identifier: GPL-3.0-or-later
"""How long a run is expected to take (no bpy), for the panel's line on
large meshes.

With the default settings (refit mode, decoupled solver, automatic
segmentation and patch count, automatic polish) the estimate is the wall
time measured by bench/scans.py on noisy scans (docs/scans.md, 2 cores), per
kind of mesh, fitted as seconds = a * (faces / 1e5)^b: one sheet (an open
mesh: the seeded families at 0.5-5 % noise) or a whole object (a closed
mesh, which the engine splits into pieces and ranks by its flat-and-ruled
share). The runs of one kind spread around their fit (a tangent developable
polishes for longer than a cylinder), so the panel gives the range the
measured runs of 100k faces and more span around it: run / fit from `low` to
`high`. bench/scans.py writes MEASURED below; tests/test_estimate.py checks
that every run it recorded falls in its range.

An open mesh that wraps around something (a hand open at the wrist) is
planned as an object by the engine but estimated as a sheet here: telling
the two apart needs the angle sums, too dear for a panel that redraws.

Other settings keep a model of the stages, fitted to docs/benchmarks.md
(10k-1M faces; one patch's iterations to runs without the polish of the
noisy cylinder patches of bench/scans.py, 2026-12-06: 100k faces 0.25 s for
23 iterations, 1M faces 4.7 s for 22):
  decoupled factorisation   faces * 3 us * (faces / 1e5)^0.35, once
  one iteration             faces * 0.11 us * (faces / 1e5)^0.29 on one
                            patch, ~0.6 us segmented
  iterations                ~25 on one patch, ~300 segmented
  coupled factorisation     faces * 30 us * (faces / 1e4)^0.4: once in paper
                            mode, every iteration with the coupled solver
  angle polish              on one patch the sheets' measured time less the
                            stages above, segmented the objects'
max_iterations caps the iterations."""

LARGE_MESH_FACES = 100_000

# bench/scans.py: begin
# Wall seconds = a * (faces / 1e5)^b; measured runs at 100k faces and more
# over the fit from low to high (bench/scans.py, 2026-12-06 16:41 UTC,
# AMD EPYC, 2 cores).
MEASURED = {
    "sheet": {"a": 3.4, "b": 0.788, "low": 0.513, "high": 2.53},
    "object": {"a": 42.7, "b": 0.996, "low": 0.911, "high": 1.06},
}
# bench/scans.py: end


def boundary_edges(edges, loops):
    """The boundary edges of a manifold polygon mesh from its counts alone:
    every inner edge is a side of two polygons, a boundary edge of one, so
    the polygons' sides (loops) are 2 inner + boundary edges. 0 for a closed
    mesh; edges that belong to no polygon count as boundary."""
    return max(2 * int(edges) - int(loops), 0)


def measured_seconds(faces, kind):
    """(shortest, longest) wall seconds of a default run on a mesh of `faces`
    triangles of `kind` ("sheet" or "object"), from MEASURED."""
    fit = MEASURED[kind]
    middle = fit["a"] * (faces / 1e5) ** fit["b"]
    return middle * fit["low"], middle * fit["high"]


def expected_seconds(faces, closed, mode, solver, segmentation, fixed_patches, max_iterations, polish):
    """(shortest, longest) expected wall time in seconds. closed: the mesh has
    no boundary (boundary_edges); mode: "REFIT" or "PAPER"; solver:
    "DECOUPLED" or "COUPLED"; segmentation: "AUTO", "OFF" or "ON";
    fixed_patches: a number of pieces set by hand (> 1) or 0; polish: "AUTO",
    "ON" or "OFF" (the settings' identifiers)."""
    kind = "object" if closed else "sheet"
    defaults = mode == "REFIT" and solver == "DECOUPLED" and segmentation == "AUTO" and fixed_patches <= 1
    if defaults and polish != "OFF" and int(max_iterations) >= 300:
        return measured_seconds(faces, kind)
    cap = int(max_iterations)
    coupled = faces * 30e-6 * (faces / 1e4) ** 0.4
    if mode == "PAPER":
        return (coupled,) * 2
    decoupled = faces * 3e-6 * (faces / 1e5) ** 0.35

    def run(iterations, per_face, cap=cap):
        iterations = min(cap, iterations)
        if solver == "COUPLED":
            return iterations * (coupled + faces * per_face)
        return decoupled + iterations * faces * per_face

    one_patch_iteration = 0.11e-6 * (faces / 1e5) ** 0.29
    one_patch, segmented = run(25, one_patch_iteration), run(300, 0.6e-6)
    if polish != "OFF":
        # What the measured default runs spent beyond their stages (at least nothing).
        sheet, whole = (sum(measured_seconds(faces, k)) / 2 for k in ("sheet", "object"))
        one_patch += max(sheet - run(25, one_patch_iteration, 25), 0.0)
        segmented += max(whole - run(300, 0.6e-6, 300), 0.0)
    if segmentation == "OFF":
        return one_patch, one_patch
    if segmentation == "ON" or fixed_patches > 1:
        return segmented, segmented
    # An open mesh runs as one patch unless one curve does not carry it.
    return (segmented, segmented) if closed else (one_patch, segmented)

"""The engine through its C ABI: quality bounds, pins, tolerance, modes."""
import numpy as np
import pytest

import geometry
import meshgen


def moved_fraction(result, positions):
    return np.abs(result.positions - positions).max() / geometry.bbox_diagonal(positions)


@pytest.mark.parametrize("name,mesh", [
    ("plane", meshgen.plane()),
    ("cylinder", meshgen.cylinder()),
    ("half cylinder", meshgen.cylinder(angle=np.pi)),
    ("cone", meshgen.cone()),
])
def test_exact_developable_surfaces_come_out_unchanged(engine, name, mesh):
    positions, triangles = mesh
    result = engine.run(positions, triangles)
    assert moved_fraction(result, positions) <= 1e-9, name
    assert result.stats["mean_defect_before"] < 1e-12


def test_noisy_cylinder_patch_becomes_developable(engine):
    positions, triangles = meshgen.noisy_cylinder_patch(noise=0.01)
    result = engine.run(positions, triangles)
    s = result.stats
    assert s["mean_defect_after"] <= 0.05 * s["mean_defect_before"], s
    distance = geometry.hausdorff(positions, triangles, result.positions, triangles)
    assert distance <= 0.01 * geometry.bbox_diagonal(positions)
    # The defects the result reports are the ones of the positions it returns.
    assert np.mean(np.abs(result.defect_after[result.interior])) == pytest.approx(
        s["mean_defect_after"], rel=1e-9)


def test_noisy_closed_cylinder_becomes_developable(engine):
    positions, triangles = meshgen.cylinder(rows=12, cols=48)
    positions = meshgen.add_noise(positions, 0.01, seed=4)
    result = engine.run(positions, triangles)
    s = result.stats
    assert s["mean_defect_after"] <= 0.05 * s["mean_defect_before"], s
    assert geometry.hausdorff(positions, triangles, result.positions, triangles) <= \
        0.01 * geometry.bbox_diagonal(positions)


def test_stalled_one_patch_run_goes_on_with_smoothed_targets(engine):
    """Noise on a bulged band stalls the plain targets at about -80 %; the run
    then goes on with smoothed targets (pipeline.cpp, kSmoothedPhaseShare)."""
    positions, triangles = meshgen.demo_cone_band()
    result = engine.run(positions, triangles)
    plain = engine.run(positions, triangles, target_smoothing=0)
    s = result.stats
    assert s["patches"] == 1
    assert s["mean_defect_after"] <= 0.05 * s["mean_defect_before"], s
    assert s["mean_defect_after"] <= plain.stats["mean_defect_after"]
    assert geometry.hausdorff(positions, triangles, result.positions, triangles) <= \
        0.015 * geometry.bbox_diagonal(positions)


def test_paper_curved_cone_beats_the_paper(engine):
    """Table I's setting: boundary pinned, E_allow = 10 AE, omega = 5; the
    paper removed 67.8 % of the mean |defect|."""
    positions, triangles = meshgen.curved_cone()
    assert (len(positions), len(triangles)) == (720, 1280)
    result = engine.run(positions, triangles, pin_boundary=1, tolerance=10.0, omega=5.0)
    s = result.stats
    assert s["change_percent"] <= -90.0, s
    boundary = ~result.interior
    assert np.array_equal(result.positions[boundary], positions[boundary])


def test_paper_mode_is_selectable_and_refit_is_better(engine):
    positions, triangles = meshgen.curved_cone()
    paper = engine.run(positions, triangles, pin_boundary=1, mode="paper")
    refit = engine.run(positions, triangles, pin_boundary=1, mode="refit")
    assert paper.stats["mean_defect_after"] < paper.stats["mean_defect_before"]
    assert refit.stats["mean_defect_after"] < 0.5 * paper.stats["mean_defect_after"]


@pytest.mark.parametrize("solver", ["decoupled", "coupled"])
def test_both_linear_systems_reduce_the_defect(engine, solver):
    positions, triangles = meshgen.noisy_cylinder_patch(noise=0.01, seed=7)
    result = engine.run(positions, triangles, solver=solver)
    assert result.stats["mean_defect_after"] <= 0.1 * result.stats["mean_defect_before"]


def test_pinned_vertices_do_not_move_at_all(engine):
    positions, triangles = meshgen.noisy_cylinder_patch(noise=0.02, seed=3)
    rng = np.random.default_rng(0)
    pinned = rng.random(len(positions)) < 0.2
    result = engine.run(positions, triangles, pinned=pinned)
    assert np.array_equal(result.positions[pinned].view(np.uint64),
                          positions[pinned].view(np.uint64))
    assert not np.array_equal(result.positions[~pinned], positions[~pinned])


@pytest.mark.parametrize("tolerance", [0.02, 0.33, 1.0])
def test_no_vertex_moves_farther_than_the_tolerance(engine, tolerance):
    positions, triangles = meshgen.noisy_cylinder_patch(noise=0.03, seed=5)
    result = engine.run(positions, triangles, tolerance=tolerance)
    limit = tolerance * result.stats["average_edge_length"]
    moves = np.linalg.norm(result.positions - positions, axis=1)
    assert moves.max() <= limit * (1 + 1e-12)
    assert result.stats["max_vertex_move"] == pytest.approx(moves.max())
    assert result.stats["mean_defect_after"] <= result.stats["mean_defect_before"]


def test_input_buffers_are_not_modified(engine):
    positions, triangles = meshgen.noisy_cylinder_patch()
    before = positions.copy(), triangles.copy()
    engine.run(positions, triangles)
    assert np.array_equal(positions, before[0]) and np.array_equal(triangles, before[1])


def test_runs_are_deterministic(engine):
    positions, triangles = meshgen.noisy_cylinder_patch(seed=9)
    a = engine.run(positions, triangles)
    b = engine.run(positions, triangles)
    assert np.array_equal(a.positions, b.positions)


def test_stats_match_the_mesh(engine):
    positions, triangles = meshgen.curved_cone()
    r = engine.run(positions, triangles, pin_boundary=1)
    s = r.stats
    assert (s["vertices"], s["faces"], s["interior_vertices"]) == (720, 1280, 720 - 160)
    edges = {tuple(sorted((a, b))) for t in triangles for a, b in zip(t, np.roll(t, 1))}
    lengths = [np.linalg.norm(positions[a] - positions[b]) for a, b in edges]
    assert s["average_edge_length"] == pytest.approx(np.mean(lengths), rel=1e-12)
    assert s["time_total_ms"] >= s["time_decompose_ms"] + s["time_iterate_ms"] - 1e-6
    assert 1 <= s["iterations"] <= 100
    assert s["stop_reason"] in ("converged", "iteration_limit", "stalled")
    assert np.allclose(np.linalg.norm(r.target_normals, axis=1), 1.0)
    assert len(r.curves) >= 1
    for curve in r.curves:
        assert np.allclose(np.linalg.norm(curve["points"], axis=1), 1.0)


def test_cone_gauss_image_gives_one_closed_curve(engine):
    positions, triangles = meshgen.curved_cone()
    r = engine.run(positions, triangles, pin_boundary=1, max_iterations=1, segmentation=0)
    assert len(r.curves) == 1 and r.curves[0]["closed"]


def test_progress_reports_and_cancels(engine):
    positions, triangles = meshgen.noisy_cylinder_patch()
    seen = []

    def keep_going(fraction, stage, user):
        seen.append((fraction, stage.decode()))
        return 1

    engine.run(positions, triangles, progress=keep_going)
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert {"ideal curve", "deformation"} <= {s for _, s in seen}

    def stop_at_deformation(fraction, stage, user):
        return 0 if stage == b"deformation" else 1

    with pytest.raises(Exception) as error:
        engine.run(positions, triangles, progress=stop_at_deformation)
    assert error.value.status == "cancelled"

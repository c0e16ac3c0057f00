"""bench/nearest_developable.py, the engine-free measure behind docs/method.md's
claim that irregular triangulations cannot keep issue 11's distance bound: its
defect Jacobian is the derivative of the angle defects, its projection ends
developable, leaves a developable twin where it is, and moves the documented
cylinder band (seed 101) beyond 1.5 times the noise."""
import importlib.util
import pathlib

import numpy as np
import pytest

from devkit.measures import average_edge_length

REPO = pathlib.Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("nearest_developable", REPO / "bench" / "nearest_developable.py")
nearest = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(nearest)
families = nearest.families


def test_jacobian_is_the_derivative_of_the_angle_defects():
    mesh = families.random_case("cone_band", 7, triangulations=["irregular"])
    _, interior = families.angle_defects(mesh.positions, mesh.triangles)
    rows = np.nonzero(interior)[0]
    defect, jacobian = nearest.defects_and_jacobian(mesh.positions, mesh.triangles, rows)
    reference, _ = families.angle_defects(mesh.positions, mesh.triangles)
    np.testing.assert_allclose(defect, reference[rows], atol=1e-12)
    edge = average_edge_length(mesh.positions, mesh.triangles)
    step = np.random.default_rng(0).normal(size=mesh.positions.shape) * 1e-6 * edge
    moved, _ = nearest.defects_and_jacobian(mesh.positions + step, mesh.triangles, rows)
    predicted = jacobian @ step.ravel()
    assert np.abs(moved - defect - predicted).max() < 1e-3 * np.abs(predicted).max()


def test_a_developable_twin_stays_where_it_is():
    mesh = families.random_case("cylinder_patch", 3, triangulations=["grid"])
    result = nearest.measure(mesh)
    assert result["twin_left"] < 1e-6
    assert result["full"] < 1e-6


@pytest.mark.parametrize("family, seed, bound", [("cylinder_band", 101, 1.5), ("cone_patch", 100, 0.5)])
def test_the_projection_ends_developable_at_the_documented_distance(family, seed, bound):
    """cylinder_band 101: no mesh within 1.5 times the noise, even at 95 % down (2.45 documented);
    cone_patch 100: a twin keeping 2 % of the defect needs to move little (0.13)."""
    mesh = families.random_case(family, seed, triangulations=["irregular"])
    result = nearest.measure(mesh)
    assert result["full_left"] < 1e-6
    if bound >= 1.5:
        assert result["best"] > bound and result["full"] > bound
    else:
        assert result["best"] < bound and result["full"] < bound

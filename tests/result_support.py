"""What every result of the engine must satisfy, whatever the mesh (the result
check of issue 11), for the tests that run it on many meshes
(tests/test_result_check.py, tests/test_objects.py)."""
import numpy as np
import pytest

from devkit.binding import native
from devkit.measures import flat_share, seam_vertices, turned_faces


def is_closed(triangles):
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    _, count = np.unique(edges, axis=0, return_counts=True)
    return bool(np.all(count == 2))


def check_honest(positions, triangles, result):
    """What every result must satisfy, whatever the mesh."""
    s = result.stats
    turned = np.sum(turned_faces(positions, result.positions, triangles) < 0)
    assert turned == 0 and s["faces_turned_over"] == 0
    if s["mean_defect_after"] > s["mean_defect_before"]:
        # Only a whole object, whose total curvature cannot go (Gauss-Bonnet),
        # may gather it on the seams of its pieces: the mean |defect| inside
        # them does not grow (a closed one's up to 5 %), and the growth is said.
        closed = is_closed(triangles)
        assert closed or np.sum(result.defect_before[result.interior]) >= np.pi  # is_object
        inside = result.interior & ~seam_vertices(len(positions), triangles, result.patch_ids)
        assert (
            np.mean(np.abs(result.defect_after[inside]))
            <= (1.05 if closed else 1.0) * np.mean(np.abs(result.defect_before[inside])) + 1e-15
        )
        assert "mean |defect| grew" in s["result_message"]
    assert s["flat_share_before"] == pytest.approx(flat_share(result.defect_before, result.interior))
    assert s["flat_share_after"] == pytest.approx(flat_share(result.defect_after, result.interior))
    assert s["flat_share_after"] >= s["flat_share_before"]
    if s["result"] == native.RESULT_UNCHANGED:
        assert np.array_equal(result.positions, positions)
        assert s["result_message"] and s["unchanged_reason"] != native.UNCHANGED_NONE
        # Nothing of a polish that was not kept is reported (boat showed
        # "Angle polish: 11 steps" under "Nothing changed").
        assert s["polish_iterations"] == 0 and s["result_origin"] == 0
    else:
        assert s["result"] == native.RESULT_IMPROVED and s["unchanged_reason"] == native.UNCHANGED_NONE
        # A gain the user sees, not rounding (the engine's kLeastGain).
        assert (
            s["mean_defect_after"] < (1 - 1e-6) * s["mean_defect_before"]
            or s["flat_share_after"] > s["flat_share_before"]
        )

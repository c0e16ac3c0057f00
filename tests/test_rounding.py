"""Whole objects under rounding (issue 11): a user's mesh reaches the engine
rounded (Blender keeps single-precision coordinates, exporters a few digits),
and the figures a user sees must not depend on the last bits. Before the
second polish's largest-|defect| rule had room and the polish went on past a
step that gained next to nothing (docs/method.md, "Nearly flat vertices",
"Rounding"), copies of hand and spot moved by 1e-7 of their coordinates came
back 44 % and 46 % flat instead of 50 % and 52 %. Through the add-on's
binding; the copies are not the ones the rules were measured on."""
import numpy as np
import pytest

from devkit.binding import native
from devkit.obj import read_obj


# Every test here runs the engine of the build under test.
pytestmark = pytest.mark.usefixtures("library")


def rounded_copies(positions):
    """Single precision, and two relative perturbations of 1e-7."""
    yield "single precision", positions.astype(np.float32).astype(np.float64)
    for seed in (12, 13):
        noise = np.random.default_rng(seed).standard_normal(positions.shape)
        yield "seed %d" % seed, positions * (1.0 + 1e-7 * noise)


@pytest.mark.parametrize("name", ["hand_lowres", "spot_low_resolution"])
def test_rounding_does_not_decide_a_whole_objects_developability(meshes_dir, name):
    """The figure the order ranks a closed mesh by (selection.h, more_developable), the
    flat-and-ruled share, within a tenth of the original's on every copy (hand 45.0 %: its
    thinned pieces; spot 42.3 %: its thinned pieces, whose count the last bits move, 27 on
    the original, 20-25 on the copies at 39.3-40.5 %: docs/method.md, "Known limits")."""
    positions, triangles = read_obj(meshes_dir / (name + ".obj"))
    reference = native.run(positions, triangles).stats
    assert reference["result"] == native.RESULT_IMPROVED
    for label, copy in rounded_copies(np.asarray(positions, dtype=np.float64)):
        stats = native.run(copy, triangles).stats
        assert stats["result"] == native.RESULT_IMPROVED, label
        assert stats["faces_turned_over"] == 0, label
        assert (
            stats["ruled_share_after"] >= 0.9 * reference["ruled_share_after"]
        ), "%s %s: %.1f %% flat and ruled against %.1f %%" % (
            name,
            label,
            100 * stats["ruled_share_after"],
            100 * reference["ruled_share_after"],
        )

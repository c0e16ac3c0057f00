"""The paths that need a window (xvfb-run): undo of the operator, and the
modal run on a worker thread with its progress and cancellation."""
import shutil

import pytest

from blender_support import scenario

pytestmark = pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="xvfb-run is missing")


def test_undo_restores_the_mesh(blender_env):
    r = scenario(blender_env, "undo", xvfb=True)
    assert r["result"] == ["FINISHED"], r
    assert r["after_run"]["keys"] == ["Basis", "Developable"]
    assert r["after_undo"]["keys"] == []
    assert r["after_undo"]["attributes"] == []
    assert not r["after_undo"]["has_result"]
    assert r["undo_base_unchanged"]
    assert r["after_redo"] == r["after_run"]


def test_modal_run_on_a_worker_thread(blender_env):
    r = scenario(blender_env, "modal", xvfb=True)
    assert r["started"] == ["RUNNING_MODAL"]
    assert r["last_run"]["status"] == "OK", r["last_run"]
    assert r["last_run"]["progress_calls"] > 1
    assert r["state_after"]["keys"] == ["Basis", "Developable"]
    assert r["base_unchanged"]


def test_modal_cancel_writes_nothing(blender_env):
    r = scenario(blender_env, "modal", 2, xvfb=True)
    assert r["started"] == ["RUNNING_MODAL"]
    assert r["last_run"]["status"] == "CANCELLED", r["last_run"]
    assert r["state_after"] == r["state_before"]
    assert r["base_unchanged"]

"""mesh.make_developable in a real Blender, with the add-on installed from the zip:
the runs on every Blender under test (any_blender_env: 3.4 and the bpy wheels),
the missing/mismatched library on Debian's 3.4."""
import pathlib
import re
import shutil
import subprocess

import pytest

from blender_support import MODULE, install_zip, scenario, several

# The background scenarios of this file, run in one start-up of each Blender.
SHARED = ("run", "rerun", "cancel 0", "cancel 3", "pins", "bad")


@pytest.fixture(scope="module")
def shared(any_blender_env):
    return several(any_blender_env, *SHARED)


def test_noisy_mesh_gets_a_more_developable_shape_key(shared):
    r = shared["run"]
    assert r["result"] == ["FINISHED"], r["error"]
    assert r["state"]["keys"] == ["Basis", "Developable"]
    assert r["base_unchanged"]
    assert r["moved"] > 0
    # measured independently from the shape key's coordinates
    assert r["mean_defect_after"] < 0.5 * r["mean_defect_before"], r
    # Blender keeps float32 coordinates: a nearly flat result's defects differ
    # from the engine's float64 ones by ~1e-7 rad
    assert r["stats"]["e_after"] == pytest.approx(r["mean_defect_after"], rel=1e-3, abs=1e-6)
    assert r["stats"]["e_before"] == pytest.approx(r["mean_defect_before"], rel=1e-3)
    assert r["stats"]["iterations"] >= 1 and r["stats"]["time_ms"] > 0
    assert r["stats"]["change_percent"] < -50
    assert r["key_value"] == 1.0
    # attributes
    assert r["defect_domains"] == ["POINT", "FLOAT"]
    assert r["stored_before_err"] < 1e-4 and r["stored_after_err"] < 1e-4
    assert r["stored_boundary_zero"]
    assert r["colour_domains"] == ["POINT", "FLOAT_COLOR", "POINT", "FLOAT_COLOR"]
    assert r["colours_finite"]
    assert r["scale"] > 0
    assert r["colours_same_scale_err"] < 1e-5  # both maps are the same function of the defect
    assert r["active_colour"] == "Defect After"
    assert r["patch_domain"][:3] == ["FACE", "INT", r["state"]["polygons"]]
    assert 0 <= r["patch_domain"][3] <= r["patch_domain"][4] < max(1, r["stats"]["patches"])


def test_rerun_replaces_the_one_shape_key(shared):
    r = shared["rerun"]
    assert r["results"] == [["FINISHED"]] * 3
    assert r["keys"] == ["Basis", "Developable"]
    assert r["base_unchanged"]
    assert r["second_differs"] > 1e-4  # other parameters, other coordinates
    assert r["third_repeats"] < 1e-5  # same parameters as the first: same result


@pytest.mark.parametrize("cancel_after", [0, 3])
def test_cancel_leaves_nothing_behind(shared, cancel_after):
    r = shared["cancel %d" % cancel_after]
    assert r["result"] == ["CANCELLED"]
    assert r["last_run"]["status"] == "CANCELLED"
    assert r["state_after"] == r["state_before"]
    assert r["state_after"]["keys"] == [] and r["state_after"]["attributes"] == []
    assert r["base_unchanged"]


def test_pins_hold(shared):
    r = shared["pins"]
    for kind in ("group", "boundary", "selection"):
        assert r[kind]["result"] == ["FINISHED"], (kind, r[kind]["error"])
        assert r[kind]["pinned_move"] < 1e-6, kind
        assert r[kind]["free_move"] > 1e-3, kind
    assert r["group"]["pinned"] == 14
    assert r["selection"]["pinned"] == 6
    assert r["selection"]["mode_after"] == "EDIT"
    assert r["selection"]["base_unchanged"]


EXPECTED = {
    "no_faces": "EMPTY_INPUT",
    "loose_edges": "EMPTY_INPUT",
    "nan": "NON_FINITE_COORDINATE",
    "non_manifold": "NON_MANIFOLD",
}


def test_bad_meshes_are_reported_and_untouched(shared):
    r = shared["bad"]
    for kind, status in EXPECTED.items():
        case = r[kind]
        assert case["result"] == ["CANCELLED"], kind
        assert status in case["error"], (kind, case["error"])
        assert "Traceback" not in case["error"]
        assert case["state_after"] == case["state_before"], kind
        assert case["base_unchanged"], kind
    assert "vertex 17" in r["nan"]["error"]


@pytest.fixture(scope="module")
def addon_without_library(addon_zip, tmp_path_factory):
    env = install_zip(addon_zip, tmp_path_factory.mktemp("no_library"))
    folder = tmp_path_factory.getbasetemp()
    addon_dir = next(p for p in folder.glob("no_library*/scripts/addons/" + MODULE))
    for lib in addon_dir.glob("*.so*"):
        lib.unlink()
    return env


def test_missing_library_is_reported_with_advice(addon_without_library):
    r = scenario(addon_without_library, "expect_error")
    assert r["result"] == ["CANCELLED"]
    assert "not found" in r["error"] and "DEVELOPABLE_LIBRARY" in r["error"], r["error"]
    assert "Traceback" not in r["error"]
    assert r["state_after"] == r["state_before"]


def test_abi_mismatch_is_reported(addon_without_library, tmp_path):
    compiler = shutil.which("cc") or shutil.which("gcc") or shutil.which("g++")
    if compiler is None:
        pytest.skip("no C compiler to build a fake library")
    src = tmp_path / "fake.c"
    src.write_text("int dev_abi_version(void) { return 999; }\n")
    lib = tmp_path / "libdevelopable.so"
    subprocess.run([compiler, "-shared", "-fPIC", "-x", "c", str(src), "-o", str(lib)], check=True)
    env = dict(addon_without_library, DEVELOPABLE_LIBRARY=str(lib))
    r = scenario(env, "expect_error")
    assert r["result"] == ["CANCELLED"]
    header = (pathlib.Path(__file__).resolve().parents[1] / "native" / "api" / "developable.h").read_text()
    needed = re.search(r"#define DEV_ABI_VERSION (\d+)", header).group(1)
    assert "ABI version 999" in r["error"] and "needs %s" % needed in r["error"], r["error"]
    assert r["state_after"] == r["state_before"]

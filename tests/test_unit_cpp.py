"""The C++ unit tests of the engine's stages (tests/unit/, GoogleTest),
run through ctest on the build folder. Builds nothing itself: scripts/test.sh
(or cmake --build build) has built bin/developable_unit_tests."""
import shutil
import subprocess
import xml.etree.ElementTree as ElementTree

import pytest


def test_every_cpp_unit_test_passes(build_dir, tmp_path):
    if shutil.which("ctest") is None:
        pytest.fail("ctest (CMake) is missing: scripts/setup.sh installs it")
    if not (build_dir / "bin" / "developable_unit_tests").exists():
        pytest.fail(
            "no bin/developable_unit_tests in %s: build with GoogleTest "
            "(libgtest-dev) and -DDEVELOPABLE_UNIT_TESTS=ON" % build_dir
        )
    report = tmp_path / "ctest.xml"
    run = subprocess.run(
        [
            "ctest",
            "--test-dir",
            str(build_dir),
            "--output-on-failure",
            "--timeout",
            "300",
            "--output-junit",
            str(report),
        ],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    output = run.stdout[-8000:] + run.stderr[-4000:]
    assert report.exists(), output
    cases = ElementTree.parse(report).getroot().iter("testcase")
    failed, ran = [], 0
    for case in cases:
        ran += 1
        if case.get("status") not in ("run", "passed") or case.find("failure") is not None:
            failed.append(case.get("name"))
    assert ran > 0, "ctest ran no unit test\n" + output
    assert run.returncode == 0 and not failed, "failed: %s\n%s" % (failed, output)

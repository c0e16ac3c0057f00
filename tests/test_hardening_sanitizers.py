"""The engine under AddressSanitizer + UndefinedBehaviorSanitizer, and a short
libFuzzer run (docs/hardening.md). Both builds are cached outside the clone,
keyed by a hash of the sources that affect them (devkit/builds.py): the first
run on a machine builds them, later runs and fresh clones of the same sources
reuse them, a change to native/ or CMakeLists.txt builds them anew.

  build-asan  gcc, -DDEVELOPABLE_SANITIZE=ON: the engine test files run again
              against it, each file in its own subprocess (ctypes needs
              libasan preloaded into the uninstrumented Python; one test per
              file, so that pytest-xdist spreads them over the cores); any
              ASan or UBSan report fails;
  build-fuzz  clang, -DDEVELOPABLE_FUZZ=ON: fuzz_c_api for FUZZ_SECONDS
              (default 60) starting from tests/fuzz_corpus/.

DEVELOPABLE_ASAN_BUILD_DIR / DEVELOPABLE_FUZZ_BUILD_DIR point at a build of
your own instead (used as it is). Longer fuzzing: bash scripts/fuzz.sh 600.
Skip both here with DEVELOPABLE_SKIP_SANITIZERS=1 (e.g. while iterating on
something else)."""
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from devkit import builds

REPO = pathlib.Path(__file__).resolve().parent.parent
ENGINE_TESTS = ["tests/test_engine.py", "tests/test_bad_input.py", "tests/test_tool.py", "tests/test_hardening.py"]
REPORT_MARKS = (
    "ERROR: AddressSanitizer",
    "runtime error:",
    "ERROR: LeakSanitizer",
    "ERROR: libFuzzer",
    "SUMMARY: UndefinedBehaviorSanitizer",
)

pytestmark = pytest.mark.skipif(
    os.environ.get("DEVELOPABLE_SKIP_SANITIZERS") == "1", reason="DEVELOPABLE_SKIP_SANITIZERS=1"
)


def cached(make, variable):
    """The build folder: $variable when set, else the cached build (held, so
    that no other run prunes it, until the test session ends)."""
    if os.environ.get(variable):
        yield pathlib.Path(os.environ[variable])
        return
    try:
        with make() as folder:
            yield folder
    except RuntimeError as error:
        pytest.fail(str(error))


# Session-scoped: under pytest-xdist each worker finds (or waits for, devkit/builds.py
# locks) the same cached build, and the tests below are not tied to one worker.
@pytest.fixture(scope="session")
def asan_build():
    if shutil.which("gcc") is None or None in (builds.gcc_runtime("libasan.so"), builds.gcc_runtime("libstdc++.so")):
        pytest.fail("gcc with libasan is needed for the sanitizer run (scripts/setup.sh installs it)")
    yield from cached(builds.asan, "DEVELOPABLE_ASAN_BUILD_DIR")


@pytest.fixture(scope="session")
def fuzz_build():
    if builds.clang_compiler() is None:
        pytest.fail("clang++ is needed for the fuzz run (scripts/setup.sh installs it)")
    yield from cached(builds.fuzz, "DEVELOPABLE_FUZZ_BUILD_DIR")


def sanitizer_env(asan_build):
    env = dict(os.environ)
    env.update(
        DEVELOPABLE_BUILD_DIR=str(asan_build),
        DEVELOPABLE_SANITIZED="1",
        # libstdc++ preloaded too: else ASan's __cxa_throw interceptor finds no
        # real __cxa_throw (the interpreter does not link libstdc++) and the
        # first C++ exception aborts with "CHECK failed: real___cxa_throw".
        LD_PRELOAD=" ".join([builds.gcc_runtime("libasan.so"), builds.gcc_runtime("libstdc++.so")]),
        # The interpreter's own allocations are never freed at exit: no leak
        # check for it (the fuzz run below checks the engine's leaks).
        ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1:"
        "detect_stack_use_after_return=1:check_initialization_order=1",
        UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1",
    )
    env.pop("DEVELOPABLE_LIBRARY", None)
    return env


@pytest.mark.parametrize("tests", ENGINE_TESTS)
def test_engine_suite_under_asan_and_ubsan(asan_build, tests):
    """One of tests/test_engine.py, test_bad_input.py, test_tool.py and
    test_hardening.py against the ASan build: every test passes, no report.
    The tests marked slow (conftest.SLOW: the larger meshes' least motion, the
    two-million-face refusal) are left out here: they run the code paths of the
    smaller ones on more vertices, which the Release run covers."""
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "not slow", tests],
        cwd=REPO,
        env=sanitizer_env(asan_build),
        capture_output=True,
        text=True,
        timeout=3600,
    )
    output = run.stdout + run.stderr
    reports = [line for line in output.splitlines() if any(m in line for m in REPORT_MARKS)]
    assert run.returncode == 0 and not reports, output[-8000:]


def test_the_sanitized_library_really_is_sanitized(asan_build):
    """Guards the run above against silently testing an uninstrumented build."""
    lib = asan_build / "lib" / "libdevelopable.so"
    ldd = subprocess.run(["ldd", str(lib)], capture_output=True, text=True).stdout
    assert "libasan" in ldd and "libubsan" in ldd, ldd


def test_fuzz_for_a_minute(fuzz_build, tmp_path):
    """fuzz_c_api for FUZZ_SECONDS (60) from tests/fuzz_corpus/ ends cleanly:
    no crash, leak, timeout or out-of-memory input, libFuzzer's "Done". New
    inputs go to a temporary folder, not into the repository."""
    seconds = int(os.environ.get("FUZZ_SECONDS", "60"))
    (tmp_path / "corpus").mkdir()
    env = dict(os.environ, UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1", ASAN_OPTIONS="detect_leaks=1")
    with open(tmp_path / "fuzz.log", "w+") as log:
        proc = subprocess.run(
            [
                str(fuzz_build / "bin" / "fuzz_c_api"),
                "-max_total_time=%d" % seconds,
                "-timeout=20",
                "-rss_limit_mb=2048",
                "-max_len=4096",
                "-artifact_prefix=%s/" % tmp_path,
                str(tmp_path / "corpus"),
                str(REPO / "tests" / "fuzz_corpus"),
            ],
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=log,
            timeout=seconds + 600,
        )
        log.seek(0)
        stderr = log.read()
    crashes = [p.name for p in tmp_path.iterdir() if p.name.startswith(("crash-", "leak-", "oom-", "timeout-"))]
    assert proc.returncode == 0 and not crashes, (
        "the fuzzer found a failing input (%s); replay it with %s/bin/fuzz_c_api FILE and "
        "add it to tests/fuzz_corpus once fixed\n%s" % (crashes, fuzz_build, stderr[-6000:])
    )
    assert "Done" in stderr

"""The engine under AddressSanitizer + UndefinedBehaviorSanitizer, and a short
libFuzzer run (docs/hardening.md). Both build their own folder beside build/:

  build-asan/  gcc, -DDEVELOPABLE_SANITIZE=ON: the engine test files run again
               in a subprocess against it (ctypes needs libasan preloaded into
               the uninstrumented Python); any ASan or UBSan report fails;
  build-fuzz/  clang, -DDEVELOPABLE_FUZZ=ON: fuzz_c_api for FUZZ_SECONDS
               (default 60) starting from tests/fuzz_corpus/.

Longer fuzzing: bash scripts/fuzz.sh 600. Skip both here with
DEVELOPABLE_SKIP_SANITIZERS=1 (e.g. while iterating on something else)."""
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
ENGINE_TESTS = ["tests/test_engine.py", "tests/test_bad_input.py", "tests/test_tool.py",
                "tests/test_hardening.py"]
REPORT_MARKS = ("ERROR: AddressSanitizer", "runtime error:", "ERROR: LeakSanitizer",
                "ERROR: libFuzzer", "SUMMARY: UndefinedBehaviorSanitizer")

pytestmark = pytest.mark.skipif(os.environ.get("DEVELOPABLE_SKIP_SANITIZERS") == "1",
                                reason="DEVELOPABLE_SKIP_SANITIZERS=1")


def build(folder, *configure, target=None, env=None, timeout=3600):
    jobs = str(os.cpu_count() or 2)
    subprocess.run(["cmake", "-S", str(REPO), "-B", str(folder), *configure], check=True,
                   capture_output=True, text=True, env=env, timeout=600)
    cmd = ["cmake", "--build", str(folder), "--parallel", jobs]
    if target:
        cmd += ["--target", target]
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]


def gcc_runtime(name):
    path = subprocess.run(["gcc", "-print-file-name=" + name], capture_output=True,
                          text=True).stdout.strip()
    return path if os.path.isabs(path) and os.path.exists(path) else None


@pytest.fixture(scope="module")
def asan_build():
    if shutil.which("gcc") is None or None in (gcc_runtime("libasan.so"), gcc_runtime("libstdc++.so")):
        pytest.fail("gcc with libasan is needed for the sanitizer run (scripts/setup.sh installs it)")
    folder = pathlib.Path(os.environ.get("DEVELOPABLE_ASAN_BUILD_DIR", REPO / "build-asan"))
    build(folder, "-DDEVELOPABLE_SANITIZE=ON", "-DCMAKE_BUILD_TYPE=RelWithDebInfo")
    return folder


def sanitizer_env(asan_build):
    env = dict(os.environ)
    env.update(
        DEVELOPABLE_BUILD_DIR=str(asan_build),
        DEVELOPABLE_SANITIZED="1",
        # libstdc++ preloaded too: else ASan's __cxa_throw interceptor finds no
        # real __cxa_throw (the interpreter does not link libstdc++) and the
        # first C++ exception aborts with "CHECK failed: real___cxa_throw".
        LD_PRELOAD=" ".join([gcc_runtime("libasan.so"), gcc_runtime("libstdc++.so")]),
        # The interpreter's own allocations are never freed at exit: no leak
        # check for it (the fuzz run below checks the engine's leaks).
        ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1:"
                     "detect_stack_use_after_return=1:check_initialization_order=1",
        UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1",
    )
    env.pop("DEVELOPABLE_LIBRARY", None)
    return env


def test_engine_suite_under_asan_and_ubsan(asan_build):
    """tests/test_engine.py, test_bad_input.py, test_tool.py and
    test_hardening.py against build-asan: every test passes, no report."""
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          *ENGINE_TESTS], cwd=REPO, env=sanitizer_env(asan_build),
                         capture_output=True, text=True, timeout=3600)
    output = run.stdout + run.stderr
    reports = [line for line in output.splitlines() if any(m in line for m in REPORT_MARKS)]
    assert run.returncode == 0 and not reports, output[-8000:]


def test_the_sanitized_library_really_is_sanitized(asan_build):
    """Guards the run above against silently testing an uninstrumented build."""
    lib = asan_build / "lib" / "libdevelopable.so"
    ldd = subprocess.run(["ldd", str(lib)], capture_output=True, text=True).stdout
    assert "libasan" in ldd and "libubsan" in ldd, ldd


def fuzz_compiler():
    for name in ("clang++", "clang++-14"):
        if shutil.which(name):
            return shutil.which(name)
    return None


def test_fuzz_for_a_minute(tmp_path):
    """fuzz_c_api for FUZZ_SECONDS (60) from tests/fuzz_corpus/; new inputs go
    to a temporary folder, not into the repository."""
    compiler = fuzz_compiler()
    if compiler is None:
        pytest.fail("clang++ is needed for the fuzz run (scripts/setup.sh installs it)")
    folder = pathlib.Path(os.environ.get("DEVELOPABLE_FUZZ_BUILD_DIR", REPO / "build-fuzz"))
    build(folder, "-DCMAKE_CXX_COMPILER=" + compiler, "-DDEVELOPABLE_FUZZ=ON",
          "-DCMAKE_BUILD_TYPE=RelWithDebInfo", target="fuzz_c_api")
    seconds = int(os.environ.get("FUZZ_SECONDS", "60"))
    work = tmp_path / "corpus"
    work.mkdir()
    env = dict(os.environ, UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1",
               ASAN_OPTIONS="detect_leaks=1")
    run = subprocess.run([str(folder / "bin" / "fuzz_c_api"), "-max_total_time=%d" % seconds,
                          "-timeout=20", "-rss_limit_mb=2048", "-max_len=4096",
                          "-artifact_prefix=%s/" % tmp_path, str(work),
                          str(REPO / "tests" / "fuzz_corpus")],
                         env=env, capture_output=True, text=True, timeout=seconds + 600)
    crashes = [p.name for p in tmp_path.iterdir() if p.name.startswith(("crash-", "leak-", "oom-", "timeout-"))]
    assert run.returncode == 0 and not crashes, (
        "the fuzzer found a failing input (%s); replay it with build-fuzz/bin/fuzz_c_api FILE and "
        "add it to tests/fuzz_corpus once fixed\n%s" % (crashes, run.stderr[-6000:]))
    assert "Done" in run.stderr

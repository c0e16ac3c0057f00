"""Extra engine builds (the ASan/UBSan build, the libFuzzer build), cached
between runs and between clones on one machine.

A build folder is keyed by a hash of everything that affects it: the
contents of the sources it compiles (CMakeLists.txt, native/**), the
compiler (its path and `--version`), CMake's version, the versions of the
libraries it compiles against (Eigen, OpenMesh, clang's fuzzing headers),
the configure options and CXXFLAGS/CPPFLAGS/LDFLAGS. It lives outside the clone, in
$DEVELOPABLE_CACHE_DIR (default ~/.cache/developable), as

    <kind>-<hash>/src/     a copy of those sources (so that the folder does
                           not depend on where the clone is, and make's
                           timestamps stay those of the first build)
    <kind>-<hash>/build/   the CMake build; .complete once it has built

so a fresh clone of the same sources reuses it as it is, and any change to
them builds a new one. Concurrent runs (several checkouts on one machine)
share a folder safely: it is built under an exclusive lock and used under a
shared one, and old folders are removed only when nobody uses them.

    python3 -m devkit.builds asan|fuzz     builds (or finds) one, prints its build/
"""
import contextlib
import fcntl
import hashlib
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

from .paths import REPO

# What the extra builds compile (unit tests and the add-on zip are off there).
SOURCES = ("CMakeLists.txt", "native", "cmake")
# libclang-*: FuzzedDataProvider.h, without which the ASan build has no fuzz_replay
LIBRARY_PACKAGES = ("libeigen3-dev", "libopenmesh-dev", "libclang-common-14-dev", "libclang-rt-14-dev")
FLAG_VARIABLES = ("CXXFLAGS", "CPPFLAGS", "LDFLAGS")
KEEP = 4  # folders of one kind kept (the most recently used), for other checkouts


def cache_root():
    root = os.environ.get("DEVELOPABLE_CACHE_DIR")
    if not root:
        root = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "developable")
    return pathlib.Path(root)


def source_files(repo=REPO):
    """The files of SOURCES under repo, relative, sorted."""
    files = []
    for name in SOURCES:
        path = pathlib.Path(repo) / name
        if path.is_file():
            files.append(pathlib.Path(name))
        elif path.is_dir():
            files += [p.relative_to(repo) for p in path.rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    return sorted(files)


def _output(*command):
    try:
        return subprocess.run(command, capture_output=True, text=True).stdout
    except OSError:
        return ""


def key(compiler, configure, repo=REPO):
    """The hash that names a build folder (see the module's docstring)."""
    h = hashlib.sha256(b"developable extra build 1\0")
    for part in (
        os.path.realpath(compiler),
        _output(compiler, "--version"),
        _output("cmake", "--version"),
        _output("dpkg-query", "-W", *LIBRARY_PACKAGES),
        *configure,
        *("%s=%s" % (v, os.environ.get(v, "")) for v in FLAG_VARIABLES),
    ):
        h.update(part.encode() + b"\0")
    for rel in source_files(repo):
        h.update(str(rel).encode() + b"\0")
        h.update(hashlib.sha256((pathlib.Path(repo) / rel).read_bytes()).digest())
    return h.hexdigest()[:20]


@contextlib.contextmanager
def _locked(path, mode):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a") as f:
        fcntl.flock(f, mode)
        yield f


def _snapshot(repo, target):
    """Copies SOURCES into target atomically (a half copy is never used)."""
    staging = pathlib.Path(tempfile.mkdtemp(prefix="src-", dir=target.parent))
    for rel in source_files(repo):
        (staging / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(pathlib.Path(repo) / rel, staging / rel)
    staging.chmod(0o755)
    staging.rename(target)


def _prune(kind, keep_folder):
    """Removes the least recently used folders of `kind` beyond KEEP, skipping
    any that a run is using (holds its lock)."""
    folders = sorted(
        (p for p in cache_root().glob(kind + "-*") if p.is_dir() and p != keep_folder),
        key=lambda p: p.stat().st_mtime,
        reverse=True,
    )
    for folder in folders[KEEP - 1 :]:
        with open(folder / ".lock", "a") as f:
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                continue  # in use
            shutil.rmtree(folder, ignore_errors=True)


class CachedBuild:
    """One cached build folder; use as a context manager, which holds the
    shared lock that keeps it from being pruned:

        with CachedBuild("asan", ["-DDEVELOPABLE_SANITIZE=ON"], "g++") as build:
            ... build / "lib" / "libdevelopable.so" ...
    """

    def __init__(self, kind, configure, compiler, targets=(), repo=REPO, jobs=None, timeout=3600):
        self.kind, self.compiler, self.targets = kind, compiler, tuple(targets)
        self.configure = ["-DCMAKE_CXX_COMPILER=" + compiler, "-DDEVELOPABLE_UNIT_TESTS=OFF", *configure]
        self.repo, self.jobs, self.timeout = pathlib.Path(repo), jobs or os.cpu_count() or 2, timeout
        self.folder = cache_root() / ("%s-%s" % (kind, key(compiler, self.configure + list(targets), repo)))
        self.build = self.folder / "build"
        self.built_now = False
        self._shared = None

    @property
    def complete(self):
        return (self.build / ".complete").exists()

    def __enter__(self):
        lock = self.folder / ".lock"
        if not self.complete:
            with _locked(lock, fcntl.LOCK_EX):
                if not self.complete:  # another run may have built it meanwhile
                    self._build()
        self._shared = open(lock, "a")
        fcntl.flock(self._shared, fcntl.LOCK_SH)
        os.utime(self.folder)  # most recently used
        _prune(self.kind, self.folder)
        return self.build

    def __exit__(self, *exc):
        self._shared.close()
        self._shared = None

    def _build(self):
        shutil.rmtree(self.build, ignore_errors=True)  # a failed or interrupted earlier try
        src = self.folder / "src"
        if not src.is_dir():
            _snapshot(self.repo, src)
        launcher, env = _ccache(src)
        configure = subprocess.run(
            ["cmake", "-S", str(src), "-B", str(self.build), *self.configure, *launcher],
            capture_output=True,
            text=True,
            timeout=600,
        )
        if configure.returncode != 0:
            raise RuntimeError(
                "configuring %s failed:\n%s%s" % (self.build, configure.stdout[-3000:], configure.stderr[-3000:])
            )
        command = ["cmake", "--build", str(self.build), "--parallel", str(self.jobs)]
        for target in self.targets:
            command += ["--target", target]
        run = subprocess.run(command, capture_output=True, text=True, timeout=self.timeout, env=env)
        if run.returncode != 0:
            raise RuntimeError("building %s failed:\n%s%s" % (self.build, run.stdout[-3000:], run.stderr[-3000:]))
        (self.build / ".complete").write_text(
            json.dumps({"configure": self.configure, "targets": self.targets, "from": str(self.repo)})
        )
        self.built_now = True


def _ccache(src):
    """(configure options, environment) that compile through ccache when it is
    installed, in the cache folder scripts/setup.sh uses too. Paths are hashed
    relative to the folder's copy of the sources and its directory is not
    hashed, so a new folder (sources changed) recompiles only the files whose
    compilation changed. Not part of the key: the objects are the same."""
    env = dict(os.environ)
    if not shutil.which("ccache"):
        return [], env
    env.setdefault("CCACHE_DIR", str(cache_root() / "ccache"))
    env.setdefault("CCACHE_MAXSIZE", "2G")
    env.update(CCACHE_BASEDIR=str(src), CCACHE_NOHASHDIR="1")
    return ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"], env


def gcc_runtime(name):
    """Full path of one of gcc's runtime libraries (libasan.so ...), or None."""
    path = _output("gcc", "-print-file-name=" + name).strip()
    return path if os.path.isabs(path) and os.path.exists(path) else None


def clang_compiler():
    for name in ("clang++", "clang++-14"):
        if shutil.which(name):
            return shutil.which(name)
    return None


def asan(**kw):
    """The ASan + UBSan build (gcc, RelWithDebInfo): library, tool, fuzz_replay."""
    return CachedBuild(
        "build-asan",
        ["-DDEVELOPABLE_SANITIZE=ON", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"],
        shutil.which("g++") or "g++",
        **kw,
    )


def fuzz(**kw):
    """The libFuzzer build (clang, RelWithDebInfo): bin/fuzz_c_api."""
    return CachedBuild(
        "build-fuzz",
        ["-DDEVELOPABLE_FUZZ=ON", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"],
        clang_compiler() or "clang++",
        targets=["fuzz_c_api"],
        **kw,
    )


if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in ("asan", "fuzz"):
        sys.exit("usage: python3 -m devkit.builds asan|fuzz")
    with {"asan": asan, "fuzz": fuzz}[sys.argv[1]]() as folder:
        print(folder)

"""What a benchmark page states about the machine, the engine and the build."""
import datetime
import functools
import os
import pathlib
import platform
import subprocess

from .paths import REPO


@functools.lru_cache(maxsize=None)
def cpu_model():
    """The CPU's model name from /proc/cpuinfo (read once), or "unknown"."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def memory_gib():
    try:
        with open("/proc/meminfo") as f:
            kib = int(next(line for line in f if line.startswith("MemTotal")).split()[1])
        return round(kib / 1024**2, 1)
    except (OSError, StopIteration):
        return None


def load_average():
    return "%.1f %.1f %.1f" % os.getloadavg()


def build_setting(build_dir, name):
    """A value of the build folder's CMakeCache.txt (e.g. CMAKE_BUILD_TYPE), or None."""
    cache = pathlib.Path(build_dir) / "CMakeCache.txt"
    if cache.exists():
        for line in cache.read_text().splitlines():
            if line.startswith(name + ":"):
                return line.split("=", 1)[1]
    return None


def commit(build_dir=None, paths=("native",)):
    """Short commit of the source a build was configured from (this checkout
    without a build folder), with a note when `paths` have uncommitted changes."""
    source = pathlib.Path(build_setting(build_dir, "CMAKE_HOME_DIRECTORY") or REPO) if build_dir else REPO

    def git(*args):
        try:
            return subprocess.run(["git", "-C", str(source), *args], capture_output=True, text=True).stdout.strip()
        except OSError:
            return ""

    head = git("rev-parse", "--short", "HEAD")
    if not head:
        return "unknown (%s)" % source
    if git("status", "--porcelain", "--", *paths):
        head += " + uncommitted changes to " + ", ".join(paths)
    return head


def engine_version(library):
    """(dev_version_string, dev_abi_version) of a library file, read without
    the binding's ABI check (a benchmark may describe any build)."""
    import ctypes

    lib = ctypes.CDLL(str(library))
    lib.dev_version_string.restype = ctypes.c_char_p
    lib.dev_abi_version.restype = ctypes.c_int32
    return lib.dev_version_string().decode(), int(lib.dev_abi_version())


def machine_info(build_dir=None, library=None):
    """dict: date, cpu, cores, memory_gib, os, python, load, and with a build
    folder its build_type and commit, with a library its engine_version and
    abi_version."""
    info = {
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "memory_gib": memory_gib(),
        "os": "%s %s" % (platform.system(), platform.release()),
        "python": platform.python_version(),
        "load_start": load_average(),
    }
    if build_dir is not None:
        info["build_type"] = build_setting(build_dir, "CMAKE_BUILD_TYPE") or "unknown"
        info["commit"] = commit(build_dir)
    if library is not None:
        try:
            info["engine_version"], info["abi_version"] = engine_version(library)
        except (OSError, AttributeError) as error:
            info["engine_version"] = "unloadable: %s" % error
    return info

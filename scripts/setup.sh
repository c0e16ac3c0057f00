#!/usr/bin/env bash
# Shared set-up for scripts/run.sh and scripts/test.sh: installs the Debian
# packages that are missing, then configures and builds into build/.
# Sourced, not run: it sets REPO and BUILD for the caller.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${DEVELOPABLE_BUILD_DIR:-$REPO/build}

# Debian packages the build, the add-on and the tests need.
packages=(cmake g++ make libeigen3-dev libopenmesh-dev libgtest-dev python3-pytest python3-numpy python3-scipy blender xvfb xauth zip
          python3-pytest-xdist      # scripts/test.sh runs the tests on every core
          ccache                    # compiled objects kept between builds and clones (below)
          clang libclang-rt-14-dev  # clang: the fuzz run and fuzz_replay (tests/test_hardening*.py)
          librsvg2-bin              # rsvg-convert: the pattern SVGs rasterised (tests/test_pattern*.py, docs)
          python3-venv)             # the test Blenders' virtual environments (setup_bpy.sh)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

# ccache keeps what the compiler made in the developers' cache folder (beside
# the cached sanitizer and fuzz builds, devkit/builds.py): a fresh clone
# compiles only the sources no earlier build on this machine compiled as they
# are. Paths under the clone are hashed relative to it, so clones elsewhere hit.
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_DIR=${CCACHE_DIR:-${DEVELOPABLE_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/developable}/ccache}
  export CCACHE_BASEDIR=$REPO CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-2G}
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S "$REPO" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build "$BUILD" --parallel "$(nproc)" >&2

# The test-only Blenders (bpy wheels from PyPI, 4.2 LTS and the newest line) in
# cached virtual environments outside the clone; DEVELOPABLE_NO_BPY=1 skips them.
if [ "${DEVELOPABLE_NO_BPY:-0}" != "1" ]; then
  bash "$REPO/scripts/setup_bpy.sh"
fi

#!/usr/bin/env bash
# Test-only Blenders: the `bpy` wheels from PyPI (Blender as a Python module)
# for the 4.2 LTS line and the newest line, each in its own virtual
# environment outside the clone (DEVELOPABLE_BPY_CACHE, default
# ~/.cache/developable), created when missing. Called by scripts/setup.sh;
# the add-on tests run on every environment found there besides Debian's
# blender. No network or a failed install only skips those Blenders.
#   bash scripts/setup_bpy.sh            # creates the missing environments
set -uo pipefail

CACHE=${DEVELOPABLE_BPY_CACHE:-$HOME/.cache/developable}
# line -> pinned version (newest patch release of the line that installs
# with Debian's Python 3.11)
declare -A VERSIONS=([4.2]=4.2.23 [5.0]=5.0.1)
PY=/usr/bin/python3

mkdir -p "$CACHE"
for line in "${!VERSIONS[@]}"; do
  version=${VERSIONS[$line]}
  env="$CACHE/bpy-$line"
  if [ -f "$env/.installed-$version" ]; then
    continue
  fi
  echo "setup_bpy: installing bpy $version into $env" >&2
  rm -rf "$env"
  if "$PY" -m venv "$env" >&2 &&
     "$env/bin/python" -m pip install -q --disable-pip-version-check "bpy==$version" >&2 &&
     "$env/bin/python" -c "import bpy, sys; sys.exit(0 if bpy.app.version_string.startswith('$line') else 1)" >&2; then
    touch "$env/.installed-$version"
  else
    echo "setup_bpy: bpy $version could not be installed; the add-on tests skip Blender $line" >&2
    rm -rf "$env"
  fi
done
exit 0

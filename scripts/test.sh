#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then pytest (the C++
# unit tests through ctest, engine, tool, add-on in a real Blender, benchmark smoke test).
#   bash scripts/test.sh [pytest arguments]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
cd "$REPO"
export DEVELOPABLE_BUILD_DIR="$BUILD"
# Debian's interpreter: the one with python3-pytest and python3-numpy.
exec /usr/bin/python3 -m pytest -q -p no:cacheprovider tests "$@"

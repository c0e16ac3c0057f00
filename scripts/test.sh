#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then pytest (the C++
# unit tests through ctest, engine, tool, add-on in a real Blender, benchmark smoke test).
#   bash scripts/test.sh [--quick] [pytest arguments]
# --quick: the day-to-day tier, without the tests marked slow (tests/conftest.py: SLOW).
set -euo pipefail
tier=()
if [ "${1:-}" = "--quick" ]; then
  shift
  tier=(-m "not slow")
fi
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
cd "$REPO"
export DEVELOPABLE_BUILD_DIR="$BUILD"
# Debian's interpreter: the one with python3-pytest and python3-numpy.
# pytest-xdist: one worker per core, tests sharing a module's fixture kept on
# one worker (tests/conftest.py); `-n 0` among the arguments runs them in turn.
exec /usr/bin/python3 -m pytest -q -p no:cacheprovider -n "$(nproc)" --dist loadgroup "${tier[@]}" tests "$@"

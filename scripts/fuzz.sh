#!/usr/bin/env bash
# Fuzzes the engine's C ABI with libFuzzer (native/fuzz/fuzz_c_api.cpp).
#   bash scripts/fuzz.sh [SECONDS] [--update-corpus] [extra libFuzzer flags]
# SECONDS defaults to 600. Uses the cached fuzz build that pytest uses too
# (clang, ASan + UBSan + libFuzzer; built on first use, see devkit/builds.py;
# its path is printed), starts from tests/fuzz_corpus/ plus the inputs of
# earlier runs (build-fuzz/corpus/), and stops at the first failure: the input
# is saved as build-fuzz/artifacts/crash-* (or timeout-*, oom-*) and the exit
# status is nonzero. Replay one input:  <fuzz build>/bin/fuzz_c_api FILE
# --update-corpus merges what the run found into tests/fuzz_corpus/ (only
# inputs that add coverage); commit them so that pytest replays them.
# FUZZ_BUILD builds into a folder of your own instead (FUZZ_CXX: its compiler).
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SECONDS_TO_RUN=600
UPDATE=0
EXTRA=()
for arg in "$@"; do
  case "$arg" in
    --update-corpus) UPDATE=1 ;;
    [0-9]*) SECONDS_TO_RUN=$arg ;;
    *) EXTRA+=("$arg") ;;
  esac
done

CXX_COMPILER=${FUZZ_CXX:-$(command -v clang++ || command -v clang++-14 || true)}
if [ -z "$CXX_COMPILER" ]; then
  echo "fuzz.sh: clang++ is missing (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi
if [ -n "${FUZZ_BUILD:-}" ]; then
  cmake -S "$REPO" -B "$FUZZ_BUILD" -DCMAKE_CXX_COMPILER="$CXX_COMPILER" -DDEVELOPABLE_FUZZ=ON \
    -DDEVELOPABLE_UNIT_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$FUZZ_BUILD" --parallel "$(nproc)" --target fuzz_c_api >&2
  FUZZ_BIN=$FUZZ_BUILD
else
  FUZZ_BIN=$(cd "$REPO" && /usr/bin/python3 -m devkit.builds fuzz)
  echo "fuzz.sh: fuzz build $FUZZ_BIN" >&2
fi

BUILD=$REPO/build-fuzz   # this checkout's corpus and artifacts
mkdir -p "$BUILD/corpus" "$BUILD/artifacts"
# Stop at the first sanitizer report.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
FUZZER="$FUZZ_BIN/bin/fuzz_c_api"
# Short runs per input (few iterations, coarse grid: see the target), so an
# input that takes 20 s is a hang worth reporting.
FLAGS=(-max_total_time="$SECONDS_TO_RUN" -timeout=20 -rss_limit_mb=2048 -max_len=4096
       -artifact_prefix="$BUILD/artifacts/" -print_final_stats=1)
echo "fuzz.sh: fuzzing for $SECONDS_TO_RUN s (corpus $BUILD/corpus + tests/fuzz_corpus)" >&2
status=0
"$FUZZER" "${FLAGS[@]}" "${EXTRA[@]}" "$BUILD/corpus" "$REPO/tests/fuzz_corpus" || status=$?
# libFuzzer also writes new inputs into the first corpus folder only.
if [ "$UPDATE" = 1 ]; then
  mkdir -p "$REPO/tests/fuzz_corpus"
  "$FUZZER" -merge=1 -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
    "$REPO/tests/fuzz_corpus" "$BUILD/corpus" >&2 || true
  echo "fuzz.sh: tests/fuzz_corpus now holds $(ls "$REPO/tests/fuzz_corpus" | wc -l) inputs" >&2
fi
exit $status

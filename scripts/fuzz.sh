#!/usr/bin/env bash
# Fuzzes the engine's C ABI with libFuzzer (native/fuzz/fuzz_c_api.cpp).
#   bash scripts/fuzz.sh [SECONDS] [--update-corpus] [extra libFuzzer flags]
# SECONDS defaults to 600. Builds build-fuzz/ with clang (ASan + UBSan +
# libFuzzer), starts from tests/fuzz_corpus/ plus the inputs of earlier runs
# (build-fuzz/corpus/), and stops at the first failure: the input is saved
# as build-fuzz/artifacts/crash-* (or timeout-*, oom-*) and the exit status is
# nonzero. Replay one input:  build-fuzz/bin/fuzz_c_api FILE
# --update-corpus merges what the run found into tests/fuzz_corpus/ (only
# inputs that add coverage); commit them so that pytest replays them.
# FUZZ_BUILD overrides the build folder.
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

BUILD=${FUZZ_BUILD:-$REPO/build-fuzz}
CXX_COMPILER=${FUZZ_CXX:-$(command -v clang++ || command -v clang++-14 || true)}
if [ -z "$CXX_COMPILER" ]; then
  echo "fuzz.sh: clang++ is missing (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi
cmake -S "$REPO" -B "$BUILD" -DCMAKE_CXX_COMPILER="$CXX_COMPILER" -DDEVELOPABLE_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD" --parallel "$(nproc)" --target fuzz_c_api >&2

mkdir -p "$BUILD/corpus" "$BUILD/artifacts"
# Stop at the first sanitizer report.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
FUZZER="$BUILD/bin/fuzz_c_api"
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

#!/usr/bin/env bash
# Builds everything (Release) and runs the whole CTest suite; prints CTest's summary.
# Extra arguments go to ctest, e.g. `scripts/test.sh -L unit` or `-R Bvh`.
#
# Skips: CTest lists skipped tests as "Skipped" (tests/CMakeLists.txt). Under CI (CI set, as
# .ci/run runs) or with PHOTONCL_NO_SKIPS=1, any skipped test that is not labelled `gpu` fails the
# run (scripts/check_skips.py on build/ctest-junit.xml): CI has no GPU, so only the GPU-only tests
# (tests/gpu/) may skip there; everything else, the PoCL device tests included, must run.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
[ -f build/build.ninja ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"
# Kernel binaries are cached per user; a fresh machine builds each program once, then reuses it.
junit="$PWD/build/ctest-junit.xml"
status=0
# The whole output of passed tests goes into the JUnit file, so check_skips.py also sees a
# GoogleTest skip that CTest counted as passed.
(cd build && ctest --output-on-failure -j "$jobs" --timeout 600 --output-junit "$junit" \
   --test-output-size-passed 1048576 "$@") || status=$?
if [ -n "${CI:-}" ] || [ "${PHOTONCL_NO_SKIPS:-0}" = 1 ]; then
  python3 scripts/check_skips.py "$junit" build || status=1
fi
exit $status

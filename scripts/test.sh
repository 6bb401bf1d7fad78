#!/usr/bin/env bash
# Builds everything (Release) and runs the whole CTest suite; prints CTest's summary.
# Extra arguments go to ctest, e.g. `scripts/test.sh -L unit` or `-R Bvh`.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
[ -f build/build.ninja ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"
# Kernel binaries are cached per user; a fresh machine builds each program once, then reuses it.
cd build && ctest --output-on-failure -j "$jobs" --timeout 600 "$@"

#!/usr/bin/env bash
# Runs every benchmark in one go and writes one Markdown table of ratios measured in the same
# run (machines here are noisy: only ratios within one run mean anything).
#   scripts/bench.sh [--quick]          results in build/bench/ (JSON per program + bench.md)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
jobs=$(nproc 2>/dev/null || echo 2)
[ -f build/build.ninja ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs" --target bvh_bench photon_pass_bench >&2
out=build/bench
mkdir -p "$out"
filter=()
[ $quick -eq 1 ] && filter=(--benchmark_filter='cornell')
for prog in bvh_bench photon_pass_bench; do
  echo "bench: running $prog" >&2
  "build/tests/bench/$prog" "${filter[@]}" --benchmark_format=console \
      --benchmark_out="$out/$prog.json.tmp" --benchmark_out_format=json >&2
  mv "$out/$prog.json.tmp" "$out/$prog.json"
done
python3 scripts/bench_table.py "$out"/bvh_bench.json "$out"/photon_pass_bench.json > "$out/bench.md.tmp"
mv "$out/bench.md.tmp" "$out/bench.md"
cat "$out/bench.md"

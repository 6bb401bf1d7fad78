#!/usr/bin/env bash
# Runs every benchmark in one go and writes one Markdown table of ratios measured in the same
# run (machines here are noisy: only ratios within one run mean anything).
#   scripts/bench.sh [--quick]          results in build/bench/ (JSON per program + bench.md, and
#                                       the quick speed-against-accuracy sweep: sweep-cornell-box.csv)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
jobs=$(nproc 2>/dev/null || echo 2)
[ -f build/build.ninja ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs" --target bvh_bench photon_pass_bench sort_bench knn_bench estimate_bench irradiance_bench >&2
out=build/bench
mkdir -p "$out"
filter=()
# --quick: the small scenes and sizes only (a minute or two).
[ $quick -eq 1 ] && filter=(--benchmark_filter='cornell|/1048576|/box/k50|cone/k50|walls1M/k50|Build/(grid|kdtree)/box')
programs=(bvh_bench photon_pass_bench sort_bench knn_bench estimate_bench irradiance_bench)
jsons=()
for prog in "${programs[@]}"; do
  echo "bench: running $prog" >&2
  "build/tests/bench/$prog" "${filter[@]}" --benchmark_format=console \
      --benchmark_out="$out/$prog.json.tmp" --benchmark_out_format=json >&2
  mv "$out/$prog.json.tmp" "$out/$prog.json"
  jsons+=("$out/$prog.json")
done
python3 scripts/bench_table.py "${jsons[@]}" > "$out/bench.md.tmp"
mv "$out/bench.md.tmp" "$out/bench.md"
cat "$out/bench.md"
# Speed against accuracy (photoncl sweep, quick form: about a minute): its CSV beside bench.md,
# charted when matplotlib is there (scripts/chart.py; the README's charts come from the full form).
cmake --build build -j "$jobs" --target photoncl >&2
echo "bench: running photoncl sweep --quick" >&2
build/photoncl sweep scenes/cornell-box.json --reference tests/data/ref-cornell-box.exr --quick -o "$out" >&2
# A pyenv python3 first on PATH may lack matplotlib: Debian's has it (setup.sh).
for py in python3 /usr/bin/python3; do
  if "$py" -c 'import matplotlib' 2>/dev/null; then
    "$py" scripts/chart.py "$out/sweep-cornell-box.csv" -o "$out" >&2
    cat "$out/winners.md"
    break
  fi
done

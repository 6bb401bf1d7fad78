#!/usr/bin/env bash
# Builds the libFuzzer harnesses for the scene loaders (tests/fuzz: JSON and glTF, ASan + UBSan,
# -O1) with clang into their own build folder, then runs each for a bounded time on the committed
# corpus, the committed regressions and the dictionary. Exits non-zero on any crash, leak, UBSan
# report, timeout or out-of-memory, and names the input that caused it.
#
#   scripts/fuzz.sh [--seconds N] [--build-dir DIR] [--only json|gltf] [--keep-corpus DIR]
#
#   --seconds N       run each fuzzer N seconds (default 60; CI uses 60)
#   --build-dir DIR   the fuzz build folder (default build-fuzz; never build/, which is gcc's)
#   --only KIND       run one harness (json or gltf) instead of both
#   --keep-corpus DIR keep the inputs the fuzzers found in DIR/<kind>/ (default: a temp folder
#                     removed at the end, so the committed corpus is never written to)
#   FUZZ_CXX=...      the compiler (default clang++-14, else clang++)
#
# With two or more cores the two harnesses run side by side, one core each, so CI waits N
# seconds, not 2N. A crashing input lands in <build-dir>/artifacts/<kind>/: reproduce it with
#   <build-dir>/tests/fuzz/<kind>_loader_fuzz <that file>
# and, once fixed, commit it to tests/fuzz/regressions/<kind>/ (the unit test
# FuzzRegressions.* loads every file there in the normal build).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60
build_dir=build-fuzz
kinds=(json gltf)
keep_corpus=""
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    --only) kinds=("$2"); shift 2 ;;
    --keep-corpus) keep_corpus="$2"; shift 2 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$seconds" =~ ^[0-9]+$ ]] && [ "$seconds" -gt 0 ] || { echo "fuzz.sh: --seconds needs a positive integer, got '$seconds'" >&2; exit 2; }

# clang-14 with its compiler-rt (libclang-rt-14-dev: libFuzzer, ASan, UBSan), as scripts/setup.sh
# installs on Debian 12; a bare clang++ may be another version whose runtime is not installed.
cxx="${FUZZ_CXX:-}"
if [ -z "$cxx" ]; then
  for c in clang++-14 clang++; do
    if command -v "$c" > /dev/null; then cxx="$c"; break; fi
  done
fi
[ -n "$cxx" ] || { echo "fuzz.sh: no clang++ found (scripts/setup.sh installs clang-14 and libclang-rt-14-dev)" >&2; exit 1; }

launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
jobs=$(nproc 2>/dev/null || echo 2)

start=$(date +%s)
if [ ! -f "$build_dir/build.ninja" ]; then
  mkdir -p "$build_dir"
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" "${launcher[@]}" \
        -DPHOTONCL_BUILD_FUZZ=ON -DPHOTONCL_BUILD_TESTS=OFF -DPHOTONCL_BUILD_BENCH=OFF > "$build_dir/configure.log" 2>&1 ||
    { cat "$build_dir/configure.log" >&2; exit 1; }
fi
targets=()
for k in "${kinds[@]}"; do targets+=("${k}_loader_fuzz"); done
cmake --build "$build_dir" -j "$jobs" --target "${targets[@]}" >&2
echo "fuzz: built ${targets[*]} in $(( $(date +%s) - start )) s" >&2

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
artifacts="$build_dir/artifacts"
run_one() {  # kind -> the fuzzer's exit status; its output in $work/<kind>.log
  local k=$1 corpus="$work/corpus/$1"
  [ -n "$keep_corpus" ] && corpus="$keep_corpus/$k"
  rm -rf "$artifacts/$k"  # only this run's findings, so the one named below is this run's
  mkdir -p "$corpus" "$artifacts/$k"
  # The first folder receives new inputs; the committed ones after it are only read.
  local seeds=(tests/fuzz/corpus/"$k")
  [ -d tests/fuzz/regressions/"$k" ] && seeds+=(tests/fuzz/regressions/"$k")
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: a loader asked to allocate from a
  # huge count in the file must refuse, not take the machine's memory.
  "$build_dir/tests/fuzz/${k}_loader_fuzz" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -dict=tests/fuzz/scene.dict -artifact_prefix="$artifacts/$k/" -print_final_stats=1 \
      "$corpus" "${seeds[@]}" > "$work/$k.log" 2>&1
}
declare -A status
if [ "$jobs" -ge 2 ]; then
  declare -A pid
  for k in "${kinds[@]}"; do run_one "$k" & pid[$k]=$!; done
  for k in "${kinds[@]}"; do status[$k]=0; wait "${pid[$k]}" || status[$k]=$?; done
else
  for k in "${kinds[@]}"; do status[$k]=0; run_one "$k" || status[$k]=$?; done
fi

failed=()
for k in "${kinds[@]}"; do
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$k.log" | grep -o '[0-9]*$' || echo "?")
  if [ "${status[$k]}" -ne 0 ]; then
    failed+=("$k")
    echo "fuzz: ${k}_loader_fuzz FAILED (exit ${status[$k]}); the end of its log:" >&2
    tail -n 60 "$work/$k.log" >&2
    echo "fuzz: the failing input: $(ls -t "$artifacts/$k"/* 2>/dev/null | head -1)" >&2
  else
    echo "fuzz: ${k}_loader_fuzz clean: $runs inputs in ${seconds} s" >&2
  fi
done
echo "fuzz: done in $(( $(date +%s) - start )) s" >&2
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: ${#failed[@]} harness(es) failed: ${failed[*]}" >&2
  exit 1
fi

#!/usr/bin/env bash
# scripts/check_skips.py on a tiny CTest project of its own: a skip labelled gpu passes; a skip
# of another test (CTest's "Skipped", by SKIP_REGULAR_EXPRESSION or SKIP_RETURN_CODE) and a
# GoogleTest skip that CTest counted as passed each fail it, by name.
#   tests/skips/check_skips_test.sh SOURCE_DIR
set -euo pipefail
source_dir=$(realpath "$1")
tmp=$(mktemp -d "${TMPDIR:-/tmp}/photoncl-skips.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

make_project() {  # the tests of the project, as CMake lines
  mkdir -p "$tmp/$1"
  { echo 'cmake_minimum_required(VERSION 3.22)'; echo 'project(skips NONE)'; echo 'enable_testing()'
    echo 'add_test(NAME runs COMMAND true)'
    echo 'add_test(NAME gpu_only COMMAND sh -c "echo \"[  SKIPPED ] no GPU\"")'
    echo 'set_tests_properties(gpu_only PROPERTIES LABELS "gpu" SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")'
    cat; } > "$tmp/$1/CMakeLists.txt"
  cmake -S "$tmp/$1" -B "$tmp/$1/build" > /dev/null
  (cd "$tmp/$1/build" && ctest --output-junit "$tmp/$1/junit.xml" --test-output-size-passed 1048576 > /dev/null)
  python3 "$source_dir/scripts/check_skips.py" "$tmp/$1/junit.xml" "$tmp/$1/build" 2> "$tmp/$1/report" && echo 0 || echo $?
}

failed=0
expect() {  # name, expected status, got status, report file, fragments the report must hold
  local name=$1 want=$2 got=$3 report=$4; shift 4
  if [ "$got" != "$want" ]; then echo "FAIL: $name: exit $got, expected $want"; cat "$report"; failed=1; fi
  for f in "$@"; do
    grep -qF -- "$f" "$report" || { echo "FAIL: $name: report lacks '$f'"; cat "$report"; failed=1; }
  done
}

got=$(make_project only_gpu < /dev/null)
expect only_gpu 0 "$got" "$tmp/only_gpu/report" "1 ran, 1 GPU-only skipped, 0 other skipped"
# gpu_only is a skip in CTest's own count, not only in its output.
grep -q 'name="gpu_only".*status="notrun"' "$tmp/only_gpu/junit.xml" ||
  { echo "FAIL: gpu_only is not 'notrun' in CTest's JUnit file"; failed=1; }

got=$(make_project others <<'EOS'
add_test(NAME unit_skip COMMAND sh -c "echo 'x.cpp:1: Skipped'; echo 'PoCL missing'; echo '[  SKIPPED ] unit_skip'")
set_tests_properties(unit_skip PROPERTIES LABELS "unit;stages" SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
add_test(NAME script_skip COMMAND sh -c "echo 'SKIP: slurm not installed'; exit 77")
set_tests_properties(script_skip PROPERTIES SKIP_RETURN_CODE 77)
add_test(NAME hidden_skip COMMAND sh -c "echo '[  SKIPPED ] hidden_skip'")
EOS
)
expect others 1 "$got" "$tmp/others/report" "unit_skip skipped" "PoCL missing" "script_skip skipped" \
  "SKIP: slurm not installed" "hidden_skip skipped" "1 ran, 1 GPU-only skipped, 3 other skipped"

[ $failed -eq 0 ] && echo "check_skips: a gpu skip passes; unit, script and hidden skips fail, each named"
exit $failed

#!/usr/bin/env bash
# Renders every shipped scene with every method (the photon methods with and without AOVs) by two
# photoncl binaries (same settings and seed) and checks that the pixels are identical (idiff with
# zero tolerance). For refactors that must not change behaviour:
#   scripts/bit_identical.sh OLD/photoncl build/photoncl [--width W] [--passes N]
# Exit 0 when every image matches bit for bit, 1 when one differs, 2 on bad arguments.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 OLD_BINARY NEW_BINARY [--width W] [--passes N]" >&2; exit 2; }
old=$(realpath "$1"); new=$(realpath "$2"); shift 2
width=96 passes=2
while [ $# -gt 0 ]; do
  case "$1" in
    --width) width=$2; shift 2 ;;
    --passes) passes=$2; shift 2 ;;
    *) echo "$0: unknown option $1" >&2; exit 2 ;;
  esac
done
for b in "$old" "$new"; do [ -x "$b" ] || { echo "$0: $b is not an executable" >&2; exit 2; }; done
command -v idiff >/dev/null || { echo "$0: idiff (openimageio-tools) not found" >&2; exit 2; }

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failed=0 compared=0
for scene in scenes/*.json scenes/*.gltf; do
  name=$(basename "${scene%.*}")
  # fg-aov and the like: AOVs read each part apart (readChunk), the plain render their sums.
  for method in fg direct progressive path fg-aov direct-aov progressive-aov; do
    args=(render "$scene" --method "${method%-aov}" --width "$width" --seed 7 --no-png -q)
    [ "${method%-aov}" != "$method" ] && args+=(--aov direct,caustic,indirect)
    if [ "$method" = path ]; then args=(render "$scene" --method path --width "$width" --seed 7 --no-png -q
                                      --passes $((passes * 2))); else args+=(--passes "$passes"); fi
    # The two binaries run interleaved, each with the same arguments.
    # A scene the old binary refuses (a feature it lacks, e.g. a sky before photons came from it)
    # has nothing to compare.
    if ! "$old" "${args[@]}" -o "$out/$name-$method-old.exr" 2>/dev/null; then
      echo "skipped    $name $method (the old binary refuses it)"; continue
    fi
    "$new" "${args[@]}" -o "$out/$name-$method-new.exr" 2>/dev/null
    compared=$((compared + 1))
    if idiff -fail 0 -failpercent 0 -warn 0 -a "$out/$name-$method-new.exr" "$out/$name-$method-old.exr" \
         >"$out/diff.txt" 2>&1; then
      echo "identical  $name $method"
    else
      echo "DIFFERENT  $name $method"; sed 's/^/    /' "$out/diff.txt"; failed=$((failed + 1))
    fi
  done
done
echo "$((compared - failed)) identical, $failed different (${width} px wide, $passes passes, seed 7)"
[ "$failed" -eq 0 ]

#!/usr/bin/env bash
# Issue 15's table: `render` (method auto, the default) against the path tracer at equal wall time,
# 10, 30 and 60 s, at 256², on every shipped scene with a 256² reference (tests/data/ref256-*.exr)
# and on the furnaces, whose reference is exact (rho / (1 - rho) in every pixel, made here with
# oiiotool), interleaved per budget by scripts/equal_time.py. Each row also holds the error without the pixels
# that see mirrors or glass first (*_masked: there the path- and light-traced references lack
# L S...S E light). One CSV per scene in OUT (default scripts/charts/equal-time), named
# <scene>-256-auto-vs-path.csv; about 4 minutes a scene.
#   scripts/equal_time_all.sh [--photoncl BIN] [--out DIR] [--budgets "10 30 60"] [SCENE...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
photoncl="$root/build/photoncl"
out="$root/scripts/charts/equal-time"
budgets="10 30 60"
scenes=()
while [ $# -gt 0 ]; do
    case "$1" in
        --photoncl) photoncl="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --budgets) budgets="$2"; shift 2 ;;
        -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
        -*) echo "equal_time_all.sh: unknown option $1" >&2; exit 2 ;;
        *) scenes+=("$1"); shift ;;
    esac
done
[ -x "$photoncl" ] || { echo "equal_time_all.sh: no photoncl binary at $photoncl (build first or pass --photoncl)" >&2; exit 2; }
if [ ${#scenes[@]} -eq 0 ]; then
    for ref in "$root"/tests/data/ref256-*.exr; do
        name="$(basename "$ref" .exr)"
        scenes+=("${name#ref256-}")
    done
    scenes+=(furnace-0.5 furnace-0.8)
fi
mkdir -p "$out"
# A copy of the binary, so a rebuild during the runs changes nothing.
bin="$(mktemp -d)/photoncl"
cp "$photoncl" "$bin"
for name in "${scenes[@]}"; do
    scene="$root/scenes/$name.json"
    [ -f "$scene" ] || scene="$root/scenes/$name.gltf"
    [ -f "$scene" ] || scene="$root/scenes/$name/$name.json"
    [ -f "$scene" ] || scene="$root/scenes/media/$name.json"
    [ -f "$scene" ] || { echo "equal_time_all.sh: no scene file for $name" >&2; exit 2; }
    echo "== $name" >&2
    reference="$root/tests/data/ref256-$name.exr"
    if [[ "$name" =~ ^furnace-([0-9.]+)$ ]]; then
        rho="${BASH_REMATCH[1]}"
        value="$(python3 -c "print(repr($rho / (1.0 - $rho)))")"
        reference="$(dirname "$bin")/ref256-$name.exr"
        oiiotool --create 256x256 3 --fill:color="$value,$value,$value" 256x256 -d float -o "$reference"
    fi
    [ -f "$reference" ] || { echo "equal_time_all.sh: no reference $reference" >&2; exit 2; }
    # shellcheck disable=SC2086
    python3 "$root/scripts/equal_time.py" "$scene" --reference "$reference" \
        --budgets $budgets --photoncl "$bin" --skip-specular-pixels \
        --contender auto='' --contender path='--method path' -o "$out/$name-256-auto-vs-path.csv"
done

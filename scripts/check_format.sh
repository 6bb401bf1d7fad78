#!/usr/bin/env bash
# Checks that the host and test C++ sources follow .clang-format (clang-format 14); with --fix,
# formats them in place. Exit 0: all formatted; 1: some file is not; 2: clang-format missing.
# Usage: scripts/check_format.sh [--fix]
set -euo pipefail
cd "$(dirname "$0")/.."

fix=0
case "${1:-}" in
    "") ;;
    --fix) fix=1 ;;
    *) echo "usage: scripts/check_format.sh [--fix]" >&2; exit 2 ;;
esac

cf=""
for c in clang-format clang-format-14; do
    if command -v "$c" >/dev/null 2>&1; then cf=$c; break; fi
done
if [ -z "$cf" ]; then
    echo "error: clang-format not found (install clang-format 14, e.g. apt-get install clang-format-14)" >&2
    exit 2
fi
version=$("$cf" --version)
case "$version" in *"version 14."*) ;; *) echo "warning: $version is not clang-format 14; it may format differently" >&2 ;; esac
if [ ! -f .clang-format ] || ! "$cf" --dump-config >/dev/null; then
    echo "error: $cf cannot read .clang-format" >&2
    exit 2
fi

# Tracked files and new ones not yet added (but not ignored ones, such as build outputs).
mapfile -t files < <(git ls-files --cached --others --exclude-standard -- 'host/*.cpp' 'host/*.h' 'tests/*.cpp' 'tests/*.h')
[ "${#files[@]}" -gt 0 ] || exit 0

if [ "$fix" = 1 ]; then
    "$cf" -i "${files[@]}"
    exit 0
fi

bad=()
for f in "${files[@]}"; do
    "$cf" --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ "${#bad[@]}" -gt 0 ]; then
    echo "not formatted (${#bad[@]} of ${#files[@]} files):"
    printf '  %s\n' "${bad[@]}"
    echo "fix with: scripts/check_format.sh --fix"
    exit 1
fi
echo "all ${#files[@]} files formatted"

#!/usr/bin/env bash
# scripts/check_layers.py must refuse a forbidden include: on a copy of host/, each of these is
# added in turn and the check must exit 1 naming the file and the rule; the clean copy passes.
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
expect() {  # expect STATUS PATTERN: run the check on $tmp, compare status and output
    set +e
    out=$(python3 "$src/scripts/check_layers.py" "$tmp" 2>&1)
    status=$?
    set -e
    if [ "$status" -ne "$1" ] || ! grep -q -- "$2" <<<"$out"; then
        echo "expected status $1 and '$2', got status $status:"; echo "$out"; exit 1
    fi
}
fresh() { rm -rf "$tmp/host"; cp -r "$src/host" "$tmp/host"; }

fresh
expect 0 "0 forbidden include"
# the twin including the device stages (pipeline ∥ reference)
fresh; echo '#include "pipeline/estimate.h"' >>"$tmp/host/reference/estimate.cpp"
expect 1 "host/reference/estimate.cpp:.*layer reference may not include layer pipeline"
# the device stages including the twin
fresh; echo '#include "reference/knn.h"' >>"$tmp/host/pipeline/knn.cpp"
expect 1 "host/pipeline/knn.cpp:.*layer pipeline may not include layer reference"
# OpenCL below the device layer
fresh; echo '#include <CL/opencl.hpp>' >>"$tmp/host/prep/plan.cpp"
expect 1 "host/prep/plan.cpp:.*OpenCL in layer prep"
# prep including the device layer
fresh; echo '#include "device/device.h"' >>"$tmp/host/prep/plan.h"
expect 1 "host/prep/plan.h:.*layer prep may not include layer device"
# climbing out of the layer root
fresh; echo '#include "../pipeline/knn.h"' >>"$tmp/host/reference/knn.cpp"
expect 1 "climbs out"
# a folder the table does not know
fresh; mkdir "$tmp/host/extra"; echo 'int x;' >"$tmp/host/extra/x.cpp"
expect 1 "host/extra/: a folder that host/layers.txt does not name"
echo "forbidden includes refused: 6 of 6"

#!/usr/bin/env bash
# GPU figures in one go, for a lent GPU machine (issue 14): the kernels cross-checked against their
# CPU twins on the GPU, photon paths/s, rays/s and a 256² pass per method, every log under OUT.
#   scripts/gpu_report.sh [BUILD_DIR] [OUT_DIR]     (defaults: build-gpu, $OUT or /tmp/gpu-report)
# BUILD_DIR is a build without OpenImageIO and tinygltf (the GPU machine has neither):
#   cmake -S . -B build-gpu -G Ninja -DPHOTONCL_WITH_OIIO=OFF -DPHOTONCL_WITH_GLTF=OFF
# Shared libraries the machine lacks (the OpenCL ICD loader, spdlog, fmt, ...) may travel in
# BUILD_DIR/lib. Where no OpenCL ICD names the NVIDIA driver, one is written (the machine runs
# commands as root). Each step has its own time limit, so one that hangs costs only its share.
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-gpu}
dest=${2:-${OUT:-/tmp/gpu-report-out}}
out=$(mktemp -d /tmp/gpu-report.XXXX)  # logs; packed after every step into dest/gpu-report.tgz (one file travels back)
mkdir -p "$out" "$dest"
export LD_LIBRARY_PATH="$PWD/$build/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PHOTONCL_CACHE_DIR=/tmp/photoncl-cache
bin="$build/photoncl"
dev=${PHOTONCL_REPORT_DEVICE:-gpu}  # cpu: a dry run of this script on PoCL
steps=",${PHOTONCL_REPORT_STEPS:-render,bench,check,stages},"  # a subset, comma-separated
want() { [[ $steps == *",$1,"* ]]; }
# Embree travels compressed (the working tree that travels is capped): unpacked beside the logs.
mkdir -p /tmp/gpu-report-lib
for xz in "$build"/lib/*.xz; do [ -e "$xz" ] && xz -dc "$xz" > "/tmp/gpu-report-lib/$(basename "$xz" .xz)"; done
export LD_LIBRARY_PATH="/tmp/gpu-report-lib:$LD_LIBRARY_PATH"
start=$SECONDS
# Packed after every step and scene: a run cut short by its time limit still brings back its logs.
pack() { tar czf "$dest/gpu-report.tgz.tmp" -C "$out" . && mv "$dest/gpu-report.tgz.tmp" "$dest/gpu-report.tgz"; }
step() {
  pack
  echo "== $* ($((SECONDS - start)) s)"
}

step "machine"
exec > >(tee "$out/report.log") 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>&1
nproc
# The test programs name the checkout's path on the machine that built them (scenes, the binary).
built_in=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt")
if [ -n "$built_in" ] && [ ! -e "$built_in" ]; then mkdir -p "$(dirname "$built_in")" && ln -s "$PWD" "$built_in"; fi
# The NVIDIA driver's OpenCL library is mounted with the driver, but no ICD file may name it (the
# machine may hold only PoCL's): one is written, so the ICD loader sees both platforms.
ls -l /etc/OpenCL/vendors/ 2>&1
cat /etc/OpenCL/vendors/*.icd 2>&1
nvlib=$(find / -xdev \( -path /proc -o -path /sys \) -prune -o -name 'libnvidia-opencl.so*' -print 2> /dev/null | sort | tail -1)
[ -z "$nvlib" ] && nvlib=$(find /usr/local/nvidia -name 'libnvidia-opencl.so*' 2> /dev/null | sort | tail -1)
echo "NVIDIA OpenCL library: ${nvlib:-not found}"
ls /usr/local/nvidia/lib64 2>&1 | head -40
if [ -n "$nvlib" ] && ! grep -qs nvidia /etc/OpenCL/vendors/*.icd; then
  mkdir -p /etc/OpenCL/vendors && echo "$nvlib" > /etc/OpenCL/vendors/nvidia.icd
fi
timeout 60 "$bin" devices 2>&1 | tee "$out/devices.txt"
trap pack EXIT
if [ "$dev" = gpu ] && ! grep -qE 'type: +GPU' "$out/devices.txt"; then
  echo "no OpenCL GPU: nothing to measure"
  exit 1
fi

want render && step "render: a 256² pass per method on the GPU (--profile: device seconds per kernel)"
want render && for scene in cornell-box cornell-spheres; do
  for method in fg direct progressive; do
    echo "-- $scene $method"
    timeout 90 "$bin" render "scenes/$scene.json" --device "$dev" --method "$method" --passes "${PHOTONCL_REPORT_PASSES:-6}" --profile \
      --no-png -o "/tmp/$scene-$method.exr" > "$out/render-$scene-$method.log" 2>&1
    echo "rc $?"
    grep -E "pass|total|all kernels|photon pass" "$out/render-$scene-$method.log" | tail -8
    pack
  done
done

want bench && step "benchmarks (the device auto opens: the GPU)"
filter='cornell|/1048576|/box/k50|cone/k50|walls1M/k50|Build/(grid|kdtree)/box'
want bench && for prog in photon_pass_bench bvh_bench sort_bench knn_bench estimate_bench irradiance_bench; do
  echo "-- $prog"
  timeout 120 "$build/tests/bench/$prog" --benchmark_filter="$filter" --benchmark_min_time=0.2 \
    --benchmark_out="$out/$prog.json" --benchmark_out_format=json > "$out/$prog.txt" 2>&1
  echo "rc $?"
  tail -25 "$out/$prog.txt"
  pack
done

want check && step "photoncl check --stage all --device $dev on every JSON scene"
want check && for scene in scenes/*.json scenes/media/*.json scenes/courtyard/courtyard.json; do
  name=$(basename "$scene" .json)
  timeout 120 "$bin" check "$scene" --device "$dev" --stage all > "$out/check-$name.log" 2>&1
  echo "$scene: rc $? $(grep -cE 'FAIL|fail' "$out/check-$name.log") lines with FAIL; last: $(tail -1 "$out/check-$name.log")"
  pack
done

if want stages; then
  step "stage tests (every kernel against its twin) on the GPU"
  PHOTONCL_TEST_DEVICE=$dev timeout 240 "$build/tests/stages_tests" --gtest_brief=1 > "$out/stages_tests.log" 2>&1
  echo "rc $?"
  grep -E "^\[  FAILED|^\[  PASSED|tests from .* ran" "$out/stages_tests.log" | tail -20
fi
step "done"

#!/usr/bin/env bash
# Installs every dependency with apt-get (Debian 12), then configures and builds photoncl (Release)
# into build/. Safe to run again: apt-get skips what is installed, CMake rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake g++ ninja-build python3 git
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libopenimageio-dev openimageio-tools
  libtinygltf-dev libstb-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-matplotlib python3-numpy
  libembree-dev libnanoflann-dev
  slurm-wlm munge  # tests/batch/slurm_test.sh: a single-node cluster started by hand
  clang-format     # scripts/check_format.sh (CTest format): the tree against .clang-format
  clang-14 libclang-rt-14-dev  # scripts/fuzz.sh: libFuzzer, ASan and UBSan live in libclang-rt-14-dev,
                               # only a Recommends of clang-14, so --no-install-recommends needs it named
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
cmake --build build -j "$jobs" --target photoncl >&2
echo "setup: built build/photoncl" >&2

#!/usr/bin/env bash
# Scree quick start, step 1: install what Scree needs from Debian 12 packages, build it
# (with the CUDA backend when nvcc is found), and run the default case.
#
#   scripts/setup.sh              # everything
#   SCREE_NO_APT=1 scripts/setup.sh   # skip apt-get (dependencies already installed)
#
# Builds into build/ (CMake + Ninja, Release); executables in build/bin, plugins in
# build/lib/scree/plugins. Re-running only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build g++ libeigen3-dev libboost-dev libboost-program-options-dev
          libvtk9-dev libgtest-dev libopenmpi-dev openmpi-bin python3-numpy python3-matplotlib python3-vtk9
          xvfb xauth)
if [ -z "${SCREE_NO_APT:-}" ]; then
  missing=()
  for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "scree: installing ${missing[*]}"
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
fi

cuda=OFF
if command -v nvcc >/dev/null 2>&1 || [ -x /usr/local/cuda/bin/nvcc ]; then
  cuda=ON
  export PATH="/usr/local/cuda/bin:$PATH"
fi
build=${SCREE_BUILD_DIR:-build}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSCREE_WITH_CUDA=$cuda ${SCREE_CMAKE_ARGS:-}
cmake --build "$build" -j "$(nproc)"

[ -n "${SCREE_NO_RUN:-}" ] && exit 0
echo "scree: running the default case (cases/elasticColumn)"
# --overwrite: the demonstration case's results are this script's own, reproduced
# identically by every run, so a second setup.sh replaces them (scree otherwise refuses
# to run over the results of an earlier run).
"$build/bin/scree" --case cases/elasticColumn --overwrite
echo "scree: done. Open cases/elasticColumn/VTK/particles.pvd in ParaView."

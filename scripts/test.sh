#!/usr/bin/env bash
# Scree quick start, step 2: run the test suite on the CPU backend.
#
#   scripts/test.sh            # build if needed, then ctest (every test but the gpu and long ones)
#   scripts/test.sh -L gpu     # extra ctest arguments (here: the GPU tests, on a GPU machine)
#   scripts/test.sh -L long    # the CPU tests that take many minutes of a core
#
# CI (.ci/run) calls this. It also compiles the CUDA build when nvcc is present (the
# GPU tests themselves run on a GPU machine: see docs/gpu.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${SCREE_BUILD_DIR:-build}
if [ ! -f "$build/build.ninja" ]; then
  SCREE_NO_RUN=1 scripts/setup.sh >/dev/null
fi
cmake --build "$build" -j "$(nproc)"
args=("$@")
[ ${#args[@]} -eq 0 ] && args=(-LE "gpu|long")
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "${args[@]}"

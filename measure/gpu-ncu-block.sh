#!/usr/bin/env bash
# Nsight Compute detail of the fused particle pass on the benchmark's granular block (the
# scaling case of docs/performance.md: phaseTransition, linear shapes, USL, 4 particles per
# cell, at rest under gravity), on a lent GPU machine: where the bandwidth-bound regime loses
# time.
#
#   measure/gpu-ncu-block.sh <particles> <out-dir> [kernel-regex]
#
# Writes the case that scree-bench's scaling series times at that size (scree-bench
# --write-block), runs 30 steps without output and without graphs, and profiles one launch
# (the 21st) of the kernels matching kernel-regex (default: the elastic-only kernel of the
# split stress pass) with `--set full` and source counters. Leaves <out-dir>/pass.ncu-rep (open it in Nsight
# Compute) and <out-dir>/pass.txt (the details page as text).
set -euo pipefail
n=$1 out=$2 regex=${3:-for_each_warp_kernel_bounded}
src=$(cd "$(dirname "$0")/.." && pwd)
build=${SCREE_BUILD_DIR:-$src/build}
mkdir -p "$out"
# the very case scree-bench times (write_block_case in utilities/scree-bench/main.cpp)
case_dir=$("$build/bin/scree-bench" --write-block "$(mktemp -d)" --max-particles "$n" --materials phaseTransition \
  --shapes linear --schemes USL)
bin=$build/bin/scree
ncu --set full --import-source yes --kernel-name "regex:$regex" --launch-skip 20 --launch-count 1 \
  -f -o "$out/pass" "$bin" --case "$case_dir" --no-output --no-graphs --max-steps 30 >"$out/run.log" 2>&1 || {
  tail -30 "$out/run.log"
  exit 1
}
ncu --import "$out/pass.ncu-rep" --page details >"$out/pass.txt"
ncu --import "$out/pass.ncu-rep" --page source --csv --print-source sass >"$out/source.csv" 2>/dev/null || true
grep -E "Duration|Registers|Achieved Occupancy|Memory Throughput|DRAM Throughput|L1/TEX Hit|L2 Hit|Compute \(SM\)|Local|Spill|Warp Cycles|Eligible|Issued Warp" \
  "$out/pass.txt" | head -60

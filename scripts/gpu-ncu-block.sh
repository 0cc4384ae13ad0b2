#!/usr/bin/env bash
# Nsight Compute detail of the fused particle pass on the benchmark's granular block (the
# issue-6 scaling case: phaseTransition, linear shapes, USL, 4 particles per cell, at rest
# under gravity), on a lent GPU machine: where the bandwidth-bound regime loses time.
#
#   scripts/gpu-ncu-block.sh <particles> <out-dir> [kernel-regex]
#
# Writes the case that scree-bench's scaling series writes for that size, runs 30 steps
# without output and without graphs, and profiles one launch (the 21st) of the kernels
# matching kernel-regex (default: the elastic-only kernel of the split stress pass) with
# `--set full` and source counters. Leaves <out-dir>/pass.ncu-rep (open it in Nsight
# Compute) and <out-dir>/pass.txt (the details page as text).
set -euo pipefail
n=$1 out=$2 regex=${3:-for_each_warp_kernel_bounded}
src=$(cd "$(dirname "$0")/.." && pwd)
bin=${SCREE_BUILD_DIR:-$src/build}/bin/scree
side=$(python3 -c "import math; print(max(4, round(math.sqrt(max(1, $n // 4)))))")
h=$(python3 -c "print(repr(1.0 / $side))")
dt=$(python3 -c "print(repr(0.2 * $h / 60.0))")
case_dir=$(mktemp -d)/block
mkdir -p "$case_dir/system" "$case_dir/constant" "$out"
printf 'endTime 100;\ndeltaT %s;\nwriteInterval 100;\n' "$dt" >"$case_dir/system/controlDict"
printf 'dimension 2;\nlower (0 0);\nupper (1.5 1.2);\ncellSize %s;\n' "$h" >"$case_dir/system/gridDict"
printf 'updateScheme USL;\nshapeFunction linear;\nsortInterval 50;\n' >"$case_dir/system/mpmSchemes"
printf 'value (0 -9.81);\n' >"$case_dir/constant/g"
cp "$src/cases/columnCollapse/constant/materialProperties" "$case_dir/constant/"
printf 'block { material sand; region { type rectangle; lower (0 0); upper (1 1); } particlesPerCell 2; initialStress { type geostatic; K0 0.5; } }\n' \
  >"$case_dir/constant/bodies"
printf 'floor { type fixed; face yMin; } left { type slip; face xMin; }\n' >"$case_dir/constant/boundaryConditions"
ncu --set full --import-source yes --kernel-name "regex:$regex" --launch-skip 20 --launch-count 1 \
  -f -o "$out/pass" "$bin" --case "$case_dir" --no-output --no-graphs --max-steps 30 >"$out/run.log" 2>&1 || {
  tail -30 "$out/run.log"
  exit 1
}
ncu --import "$out/pass.ncu-rep" --page details >"$out/pass.txt"
ncu --import "$out/pass.ncu-rep" --page source --csv --print-source sass >"$out/source.csv" 2>/dev/null || true
grep -E "Duration|Registers|Achieved Occupancy|Memory Throughput|DRAM Throughput|L1/TEX Hit|L2 Hit|Compute \(SM\)|Local|Spill|Warp Cycles|Eligible|Issued Warp" \
  "$out/pass.txt" | head -60

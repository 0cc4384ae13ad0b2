#!/usr/bin/env bash
# A decomposed run's speed on the GPUs of one machine: weak scaling (the same points per
# GPU, the block longer with the GPUs), strong scaling (one block of STRONG_POINTS over 1
# to G GPUs), a one-rank run against the same case run without mpirun, and where a step's
# time goes on each rank (--profile: the passes, the wait for the slowest rank, the halo
# sum, the clock reduction, the chunk agreement and the migrations of points).
#
#   measure/gpu-mpi-scaling.sh BIN_DIR OUT_DIR [POINTS_PER_GPU] [STEPS] [GPUS] [STRONG_POINTS]
#
# The block is 3D phase-transition sand (USL, linear shapes, 8 points per cell, geostatic
# stress, K0 0.5) on a fixed floor. By default it fills the grid across, between
# frictionless walls, so it stays at rest and every point costs the same wherever the
# cuts fall: the weak-scaling runs then do the same work per GPU. SCREE_SCALING_BLOCK=free
# gives the block free ends instead, which slump: its end points cost more, and a longer
# block has fewer of them per GPU (weak scaling above 100%).
#
# BIN_DIR holds scree (a CUDA build with MPI); POINTS_PER_GPU defaults to 1e7, STEPS to
# 300, GPUS to "1 2" (the GPU counts to run; the machine must have the largest),
# STRONG_POINTS to POINTS_PER_GPU. Each run is one `mpirun -np G scree --no-output
# --max-steps STEPS`; the figures come from its last line (steps/s over the chunks of
# steps, setup excluded). Writes OUT_DIR/<run>.log and OUT_DIR/scaling.csv (run, gpus,
# points, steps_per_s, particle_steps_per_s_per_gpu). SCREE_DEVICE=cpu runs it on CPU
# ranks (a check of the script anywhere); SCREE_RUN_TIMEOUT (seconds, default 280) bounds
# each run.
set -euo pipefail
bin=$(cd "$1" && pwd); out=$2; per=${3:-10000000}; steps=${4:-300}; gpus=${5:-"1 2"}; strong=${6:-$per}
block=${SCREE_SCALING_BLOCK:-confined}
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
h=0.005
# The block: C x C cells across (y, z), L cells along x per GPU, 8 points per cell.
C=$(python3 -c "import math; print(max(8, round((${per}/8/2.5) ** (1/3))))")
L=$(python3 -c "print(max(8, round(${per}/8/${C}/${C})))")
Ls=$(python3 -c "print(max(8, round(${strong}/8/${C}/${C})))")
make_case() {  # dir, cells along x
  local d=$1 lx=$2
  mkdir -p "$d/system" "$d/constant"
  python3 - "$d" "$lx" "$C" "$h" "$block" <<'PY'
import sys
d, lx, c, h, block = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
X, Y = lx * h, c * h
open(f"{d}/system/controlDict", "w").write("endTime 10; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 10;\n")
open(f"{d}/system/mpmSchemes", "w").write("updateScheme USL; shapeFunction linear; transfer FLIP;\n")
if block == "free":  # two cells of grid around the block: its ends and sides slump
    grid, lo, hi = (X + 4*h, Y + 4*h), (2*h, 2*h), (X + 2*h, Y + 2*h)
    walls = ""
else:  # the block fills the grid across, between frictionless walls: at rest
    grid, lo, hi = (X, Y), (0, 0), (X, Y)
    walls = "".join(f"{f} {{ type slip; face {f}; }}\n" for f in ("xMin", "xMax", "yMin", "yMax"))
open(f"{d}/system/gridDict", "w").write(
    f"dimension 3; lower (0 0 0); upper ({grid[0]:.6g} {grid[1]:.6g} {Y + 4*h:.6g}); cellSize {h};\n")
open(f"{d}/constant/g", "w").write("value (0 0 -9.81);\n")
open(f"{d}/constant/bodies", "w").write(
    f"block {{ material sand; region {{ type box; lower ({lo[0]:.6g} {lo[1]:.6g} 0); upper ({hi[0]:.6g} {hi[1]:.6g} {Y:.6g}); }} "
    "particlesPerCell 2; initialStress { type geostatic; K0 0.5; } }\n")
open(f"{d}/constant/boundaryConditions", "w").write("floor { type fixed; face zMin; }\n" + walls)
PY
  cp "$repo/cases/axisymmetricCollapse/constant/materialProperties" "$d/constant/"
}
run() {  # name, gpus (0: one process without mpirun), cells along x, extra args
  local name=$1 g=$2 lx=$3; shift 3
  make_case "$out/case-$name" "$lx"
  local launch=(mpirun --allow-run-as-root -np "$g" --bind-to none)
  [ "$g" -eq 0 ] && launch=()
  timeout "${SCREE_RUN_TIMEOUT:-280}" "${launch[@]}" "$bin/scree" --case "$out/case-$name" --device "${SCREE_DEVICE:-cuda}" \
    --no-output --max-steps "$steps" "$@" > "$out/$name.log" 2>&1 || echo "gpu-mpi-scaling: $name failed (see $out/$name.log)"
  [ "$g" -eq 0 ] && g=1
  local pts sps
  pts=$(grep -o '[0-9]* particles, ' "$out/$name.log" | head -1 | awk '{print $1}')
  sps=$(grep -o 'at [0-9.e+-]* steps/s' "$out/$name.log" | tail -1 | awk '{print $2}')
  echo "$name,$g,${pts:-0},${sps:-0},$(awk -v s="${sps:-0}" -v p="${pts:-0}" -v g="$g" 'BEGIN { printf "%.4g", s * p / g }')" >> "$out/scaling.csv"
}
echo "run,gpus,points,steps_per_s,particle_steps_per_s_per_gpu" > "$out/scaling.csv"
run "single-process" 0 "$L"  # the one-rank runs' reference: the same block without mpirun
for g in $gpus; do
  run "weak-$g" "$g" $((L * g))
  [ "$Ls" -ne "$L" ] || [ "$g" -gt 1 ] && run "strong-$g" "$g" "$Ls"
done
for g in $gpus; do
  [ "$g" -gt 1 ] && run "profile-$g" "$g" $((L * g)) --profile
done
cat "$out/scaling.csv"

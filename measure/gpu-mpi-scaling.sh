#!/usr/bin/env bash
# A decomposed run's speed on the GPUs of one machine: weak scaling (the same points per
# GPU, the block longer with the GPUs) and strong scaling (one block over more GPUs) of a
# 3D phase-transition block resting on a floor (USL, linear shapes, 8 points per cell,
# geostatic stress), and where a step's time goes on 2 GPUs (--profile: the ranks' halo
# sum and clock reduction against the passes and grid updates).
#
#   measure/gpu-mpi-scaling.sh BIN_DIR OUT_DIR [POINTS_PER_GPU] [STEPS] [GPUS]
#
# BIN_DIR holds scree (a CUDA build with MPI); POINTS_PER_GPU defaults to 1e7, STEPS to
# 300, GPUS to "1 2" (the GPU counts to run; the machine must have the largest). Each run
# is one `mpirun -np G scree --no-output --max-steps STEPS`; the figures come from its last
# line (steps/s over the chunks of steps, setup excluded). Writes OUT_DIR/<run>.log and
# OUT_DIR/scaling.csv (run, gpus, points, steps_per_s, particle_steps_per_s_per_gpu).
# SCREE_DEVICE=cpu runs it on CPU ranks (a check of the script anywhere); SCREE_RUN_TIMEOUT
# (seconds, default 280) bounds each run.
set -euo pipefail
bin=$(cd "$1" && pwd); out=$2; per=${3:-10000000}; steps=${4:-300}; gpus=${5:-"1 2"}
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
h=0.005
# The block: C x C cells across (y, z), L cells along x per GPU, 8 points per cell.
C=$(python3 -c "import math; print(max(8, round((${per}/8/2.5) ** (1/3))))")
L=$(python3 -c "print(max(8, round(${per}/8/${C}/${C})))")
make_case() {  # dir, cells along x
  local d=$1 lx=$2
  mkdir -p "$d/system" "$d/constant"
  python3 - "$d" "$lx" "$C" "$h" <<'PY'
import sys
d, lx, c, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
X, Y = lx * h, c * h
open(f"{d}/system/controlDict", "w").write("endTime 10; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 10;\n")
open(f"{d}/system/mpmSchemes", "w").write("updateScheme USL; shapeFunction linear; transfer FLIP;\n")
open(f"{d}/system/gridDict", "w").write(
    f"dimension 3; lower (0 0 0); upper ({X + 4*h:.6g} {Y + 4*h:.6g} {Y + 4*h:.6g}); cellSize {h};\n")
open(f"{d}/constant/g", "w").write("value (0 0 -9.81);\n")
open(f"{d}/constant/bodies", "w").write(
    f"block {{ material sand; region {{ type box; lower ({2*h:.6g} {2*h:.6g} 0); upper ({X + 2*h:.6g} {Y + 2*h:.6g} {Y:.6g}); }} "
    "particlesPerCell 2; initialStress { type geostatic; K0 0.5; } }\n")
open(f"{d}/constant/boundaryConditions", "w").write("floor { type fixed; face zMin; }\n")
PY
  cp "$repo/cases/axisymmetricCollapse/constant/materialProperties" "$d/constant/"
}
run() {  # name, gpus, cells along x, extra args
  local name=$1 g=$2 lx=$3; shift 3
  make_case "$out/case-$name" "$lx"
  timeout "${SCREE_RUN_TIMEOUT:-280}" mpirun --allow-run-as-root -np "$g" --bind-to none "$bin/scree" --case "$out/case-$name" --device "${SCREE_DEVICE:-cuda}" \
    --no-output --max-steps "$steps" "$@" > "$out/$name.log" 2>&1 || echo "gpu-mpi-scaling: $name failed (see $out/$name.log)"
  local pts sps
  pts=$(grep -o '[0-9]* particles, ' "$out/$name.log" | head -1 | awk '{print $1}')
  sps=$(grep -o 'at [0-9.e+-]* steps/s' "$out/$name.log" | tail -1 | awk '{print $2}')
  echo "$name,$g,${pts:-0},${sps:-0},$(awk -v s="${sps:-0}" -v p="${pts:-0}" -v g="$g" 'BEGIN { printf "%.4g", s * p / g }')" >> "$out/scaling.csv"
}
echo "run,gpus,points,steps_per_s,particle_steps_per_s_per_gpu" > "$out/scaling.csv"
for g in $gpus; do
  run "weak-$g" "$g" $((L * g))
  [ "$g" -gt 1 ] && run "strong-$g" "$g" "$L"
done
last=$(echo $gpus | awk '{print $NF}')
[ "$last" -gt 1 ] && run "profile-$last" "$last" $((L * last)) --profile
cat "$out/scaling.csv"

#!/usr/bin/env bash
# The 2.5e8-point valleyCollapse (cases/valleyCollapse/variants/quarterBillion) on N GPUs,
# one rank each, for STEPS steps: the setup's and the steps' wall time, the time per step,
# the GPU memory each rank holds (nvidia-smi every 2 s), the last frame drawn by
# utilities/render/plan_view.py (FIRST=1: the first too). PROFILE=1 adds --profile (per-rank phases; its
# barriers slow the step a little) and writes no frames.
#
#   measure/gpu-valley.sh BIN_DIR OUT_DIR [N] [STEPS]
#
# The run writes no checkpoint (the variant's is 95 GB over the ranks): checkpointInterval
# is set to 0 in the run's copy of the case. Everything lands in OUT_DIR: log, memory.csv,
# valley-last.png (valley-first.png).
set -euo pipefail
bin=$(cd "$1" && pwd); out=$2; n=${3:-4}; steps=${4:-200}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
work=$(mktemp -d /tmp/scree-valley.XXXXXX)
cp -r "$here/cases/valleyCollapse" "$work/"
v=$work/valleyCollapse/variants/quarterBillion
sed -i -E 's/^(checkpointInterval[[:space:]]+)[^;]+;/\10;/' "$v/system/controlDict"
# The frames as raw single precision: 9 GB each, written fast.
sed -i -E 's/particles \{ type vtk; fields \(velocity\); \}/particles { type vtk; fields (velocity); precision single; compression none; }/' \
  "$v/system/controlDict"
extra=()
[ "${PROFILE:-0}" = 1 ] && extra=(--profile)
[ "${PROFILE:-0}" = 1 ] && [ "${FRAMES:-0}" != 1 ] && extra+=(--no-output)
nvidia-smi --query-gpu=timestamp,index,memory.used,utilization.gpu --format=csv -l 2 > "$out/memory.csv" 2>&1 &
smi=$!
start=$(date +%s.%N)
rc=0
mpirun --allow-run-as-root -np "$n" --bind-to none "$bin/scree" --case "$v" --max-steps "$steps" "${extra[@]}" \
  > "$out/log" 2>&1 || rc=$?
end=$(date +%s.%N)
kill $smi || true
echo "mpirun wall: $(python3 -c "print(round($end - $start, 1))") s, exit $rc" | tee -a "$out/log"
if [ -f "$v/VTK/particles.pvd" ]; then
  stl=$work/valleyCollapse/constant/triSurface/valley.stl
  [ "${FIRST:-0}" = 1 ] && { python3 "$here/utilities/render/plan_view.py" "$v/VTK/particles.pvd" "$out/valley-first.png" \
    --time 0 --ground "$stl" --axis-y 6 --bin 0.1 --title "valleyCollapse, quarterBillion" || rc=1; }
  python3 "$here/utilities/render/plan_view.py" "$v/VTK/particles.pvd" "$out/valley-last.png" \
    --ground "$stl" --axis-y 6 --bin 0.1 --title "valleyCollapse, quarterBillion" || rc=1
  du -sh "$v/VTK" | tee -a "$out/log"
fi
rm -rf "$work"
exit $rc

#!/usr/bin/env bash
# The measurements of docs/performance.md in one device call.
#
#   measure/gpu-perf.sh [SECTION...]    on the GPU machine, from the repository root
#
# Sections (default: all, in this order): tests paper variants scaling base output cpu ncu
# stalls. Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda) and, for `base`,
# .gpu-base: the executables and plugins of the commit to compare against, built the same
# way, with that commit's cases/.
# Device call: carry [".gpu-bundle", ".gpu-base"]. Output under $OUT (at most 8 files come
# back): log.txt (everything), CSVs of the benchmark and ncu.txt. Each command has its own
# time limit so that the call ends inside the device's 10 minutes.
set -uo pipefail
out=${OUT:-gpu-perf-out}
mkdir -p "$out"
log=$out/log.txt
: > "$log"
source .gpu-bundle/env.sh
bin=build-cuda/bin
base=.gpu-base/build/bin
sections=${*:-tests paper variants scaling base output cpu ncu stalls}
want() { [[ " $sections " == *" $1 "* ]]; }
say() { echo "$*" | tee -a "$log"; }
step() {  # step LIMIT_S CMD...: run with a time limit, all output to the log
  local lim=$1
  shift
  say "== [$(date +%T)] $*"
  timeout "$lim" "$@" >> "$log" 2>&1
  local rc=$?
  [ $rc -ne 0 ] && say "   (exit $rc)"
  return 0
}

nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm,clocks.sm --format=csv | tee -a "$log"

# The GPU tests: fast vs reference kernels, CPU vs CUDA, transfers.
want tests && step 180 ctest --test-dir build-cuda -L gpu --output-on-failure --timeout 170

# The paper's cases: at rest and flowing; every kernel variant over the same windows.
want paper && step 150 $bin/scree-bench --device cuda --cases column,flume --kernels fast --column-steps 2000 \
  --flume-steps 1000 --csv "$out/paper.csv" --json /dev/null
want variants && step 120 $bin/scree-bench --device cuda --cases column --kernels uncapped,reference \
  --column-steps 2000 --csv "$out/variants.csv" --json /dev/null

# Large problems: throughput and memory.
want scaling && step 150 $bin/scree-bench --device cuda --cases scaling --kernels fast,uncapped \
  --materials phaseTransition,linearElastic --shapes linear --schemes USL,USF --max-particles 10000000 --steps 400 \
  --csv "$out/scaling.csv" --json /dev/null

# The base commit on its own case files (and the new code on them, for comparison).
if want base; then
  step 60 $base/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 10000
  step 100 $base/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 12000
  step 40 $base/scree --case .gpu-base/cases/flume --device cuda --no-output --max-steps 2000
  step 60 $base/scree-bench --device cuda --cases scaling --source-dir .gpu-base --max-particles 100000 --steps 200 \
    --csv /dev/null --json /dev/null
  step 60 $bin/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 10000
  step 60 $bin/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 12000
fi

# Output on its own stream: the column with its own schedule (snapshots at 0.05 s, probes
# every 0.002 s, run-out every 0.005 s) and at ten times the snapshot rate, against none.
if want output; then
  rm -rf /tmp/cc /tmp/cc10 && cp -r cases/columnCollapse /tmp/cc && cp -r cases/columnCollapse /tmp/cc10
  sed -i 's/^writeInterval .*/writeInterval 0.005;/' /tmp/cc10/system/controlDict
  for c in /tmp/cc /tmp/cc10; do
    step 90 bash -c "time $bin/scree --case $c --device cuda --max-steps 12000 --overwrite 2>&1 | tail -1"
  done
  step 60 bash -c "time $bin/scree --case /tmp/cc --device cuda --no-output --max-steps 12000 | tail -1"
fi

# The CPU backend on the GPU machine's cores against the scalar loop.
want cpu && step 150 $bin/scree-bench --device cpu --cases cpu --cpu-particles 100000 --cpu-steps 20 \
  --threads "$(nproc)" --csv "$out/cpu.csv" --json /dev/null

# Kernel facts: one launch of each kernel of a USF step of the column at rest.
if want ncu; then
  step 120 ncu --clock-control none -k regex:"for_each|sparse" --launch-skip 40 --launch-count 4 \
    --section SpeedOfLight --section Occupancy --section LaunchStats \
    --metrics sm__inst_executed_pipe_fp64.sum,smsp__sass_thread_inst_executed_op_dfma_pred_on.sum,smsp__sass_thread_inst_executed_op_dadd_pred_on.sum,smsp__sass_thread_inst_executed_op_dmul_pred_on.sum,dram__bytes.sum,lts__t_bytes.sum \
    $bin/scree --case cases/columnCollapse --device cuda --no-output --max-steps 20 --no-graphs
fi
# Why the stress kernel waits: warp states of the column's stress pass, at rest and flowing.
if want stalls; then
  for skip in 42 40042; do
    step 150 ncu --clock-control none -k regex:"for_each_warp" --launch-skip $((skip / 2)) --launch-count 1 \
      --section WarpStateStats --section SchedulerStats --section Occupancy --section SpeedOfLight \
      --metrics smsp__average_warps_issue_stalled_long_scoreboard_per_issue_active.ratio,smsp__average_warps_issue_stalled_short_scoreboard_per_issue_active.ratio,smsp__average_warps_issue_stalled_wait_per_issue_active.ratio,smsp__average_warps_issue_stalled_math_pipe_throttle_per_issue_active.ratio,smsp__average_warps_issue_stalled_not_selected_per_issue_active.ratio,smsp__average_warps_issue_stalled_selected_per_issue_active.ratio,smsp__average_warps_issue_stalled_lg_throttle_per_issue_active.ratio,smsp__average_warps_issue_stalled_mio_throttle_per_issue_active.ratio,smsp__average_warps_issue_stalled_no_instruction_per_issue_active.ratio,smsp__average_warps_issue_stalled_branch_resolving_per_issue_active.ratio,smsp__average_warps_issue_stalled_dispatch_stall_per_issue_active.ratio,smsp__average_warps_issue_stalled_drain_per_issue_active.ratio,smsp__average_warps_issue_stalled_imc_miss_per_issue_active.ratio,smsp__average_warps_issue_stalled_membar_per_issue_active.ratio,smsp__average_warps_issue_stalled_sleeping_per_issue_active.ratio,smsp__average_warps_issue_stalled_barrier_per_issue_active.ratio \
      $bin/scree --case cases/columnCollapse --device cuda --no-output \
      --max-steps $((skip / 4 + 5)) --no-graphs
  done
fi
grep -E "for_each|sparse_kernel|Duration|Registers Per|Achieved Occupancy|Theoretical Occupancy|Compute \(SM\) Thr|DRAM Thr|Memory Thr|pipe_fp64|op_d|dram__bytes|lts__t_bytes|Stall|stall|Warp Cycles|Issued Warp|No Eligible|Active Warps|Eligible Warps|Executed Ipc|issue_stalled" \
  "$log" | sed -E 's/void scree::detail::(for_each_[a-z_]*kernel[^<]*)<(.{0,100}).*/\1 \2/' > "$out/ncu.txt"

say "==== summary"
grep -E "tests passed|Failed|FAILED" "$log" | tail -6
grep -E "done:" "$log" | tail -12
grep -E "^  (column|flume|block)|estimated|memory:|scalar loop /|^real" "$log" | tail -80

#!/usr/bin/env bash
# The measurements of docs/performance.md in one device call (issue 6).
#
#   scripts/gpu-perf.sh            on the GPU machine, from the repository root
#
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda) and, for the "before" column,
# .gpu-base: the executables and plugins of commit de3498e (the code before this work)
# built the same way, with that commit's cases/ (see docs/performance.md, "Reproducing").
# Device call: carry [".gpu-bundle", ".gpu-base"]. Everything is logged under $OUT (at
# most 8 files come back): log.txt (all output), the benchmark CSVs and ncu.txt.
# Each step has its own time limit so that the call ends inside the device's 10 minutes.
set -uo pipefail
out=${OUT:-gpu-perf-out}
mkdir -p "$out"
log=$out/log.txt
: > "$log"
source .gpu-bundle/env.sh
bin=build-cuda/bin
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
summary() { grep -E "$1" "$log" | tail -${2:-40}; }

nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm,clocks.sm --format=csv | tee -a "$log"

# 1. The GPU tests: fast vs reference kernels, CPU vs CUDA, transfers.
step 180 ctest --test-dir build-cuda -L gpu --output-on-failure --timeout 170

# 2. The paper's cases, before (commit de3498e, its own case files) and after.
base=.gpu-base/build/bin
step 60 $base/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 10000
step 90 $base/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 12000
step 40 $base/scree --case .gpu-base/cases/flume --device cuda --no-output --max-steps 2000
step 60 $bin/scree --case .gpu-base/cases/columnCollapse --device cuda --no-output --max-steps 12000
step 150 $bin/scree-bench --device cuda --cases column,flume --kernels fast --column-steps 2000 \
  --flume-steps 1000 --csv "$out/paper.csv" --json /dev/null
step 90 $bin/scree-bench --device cuda --cases column --kernels capped,reference --column-steps 1000 \
  --csv "$out/paper_variants.csv" --json /dev/null

# 3. Large problems: throughput and memory.
step 150 $bin/scree-bench --device cuda --cases scaling --kernels fast --materials phaseTransition,linearElastic \
  --shapes linear --schemes USL,USF --max-particles 10000000 --steps 400 --csv "$out/scaling.csv" --json /dev/null
step 60 $bin/scree-bench --device cuda --cases scaling --kernels capped,reference --materials phaseTransition \
  --shapes linear,bspline2 --schemes USL --max-particles 1000000 --steps 200 --csv "$out/scaling_variants.csv" \
  --json /dev/null
step 40 $base/scree-bench --device cuda --cases scaling --source-dir .gpu-base --max-particles 100000 --steps 200 \
  --csv /dev/null --json /dev/null

# 4. Output on its own stream: the column with snapshots every 0.005 s and function objects.
rm -rf /tmp/cc && cp -r cases/columnCollapse /tmp/cc && sed -i 's/^writeInterval .*/writeInterval 0.005;/' /tmp/cc/system/controlDict
step 60 bash -c "time $bin/scree --case /tmp/cc --device cuda --max-steps 5000 > /tmp/cc_output.txt 2>&1; tail -2 /tmp/cc_output.txt; ls /tmp/cc/VTK | wc -l"
step 30 bash -c "time $bin/scree --case /tmp/cc --device cuda --no-output --max-steps 5000 | tail -1"

# 5. Kernel facts: one launch of each kernel of a USF step of the column.
step 120 ncu --clock-control none -k regex:"for_each|sparse" --launch-skip 40 --launch-count 4 \
  --section SpeedOfLight --section Occupancy --section LaunchStats \
  --metrics sm__inst_executed_pipe_fp64.sum,smsp__sass_thread_inst_executed_op_dfma_pred_on.sum,smsp__sass_thread_inst_executed_op_dadd_pred_on.sum,smsp__sass_thread_inst_executed_op_dmul_pred_on.sum,dram__bytes.sum,lts__t_bytes.sum \
  $bin/scree --case cases/columnCollapse --device cuda --no-output --max-steps 20 --no-graphs
grep -E "for_each|sparse_kernel|Duration|Registers Per|Achieved Occupancy|Theoretical Occupancy|Compute \(SM\) Thr|DRAM Thr|Memory Thr|pipe_fp64|op_d|dram__bytes|lts__t_bytes" "$log" \
  | sed -E 's/void scree::detail::(for_each_[a-z_]*kernel[^<]*)<(.{0,100}).*/\1 \2/' > "$out/ncu.txt"

say "==== summary"
summary "tests passed|Failed|FAILED|Passed" 12
summary "done:" 12
summary "^  (column|flume|block)|estimated|memory:" 80
summary "^real" 4

#!/usr/bin/env bash
# Whole runs of the paper's cases, timed end to end, against the targets of the
# performance work (docs/performance.md): what a user waits for, not a step.
#
#   measure/whole-runs.sh [--device cuda|cpu] [--threads N] [--build DIR] [--out DIR] [--bench]
#                         [--bench-kernels LIST] [--scree-args "ARGS"] [RUN...]
#
# RUN is column (cases/columnCollapse, 1 mm, 1.1 s), flume (cases/flume, 5 mm, 3.05 s), or
# CASE[:LABEL] for any other case directory (a variant: cases/flume/variants/S-1:S-1). Default:
# column flume. Each runs in a copy under OUT/runs/ (the case's own results are not touched),
# one after another, as shipped: its writers and function objects on, its own end time.
# Prints the targets table last (now / target) and writes OUT/whole-runs.csv and .json:
#
#   wall time of the whole run    column < 60 s (moonshot 15), flume < 120 s (moonshot 30);
#                                 a variant labelled column* or flume* too (whole-runs-table.py)
#   late step / resting step      at most 2: ms per step over the run's dearest progress
#                                 interval (about 10 s of wall time) and over its last one,
#                                 against the case's resting step
#   large 2D blocks (1e7 points)  phaseTransition >= 4e9 particle-steps/s, linearElastic >= 6e9
#
# --bench (GPU) first runs scree-bench on the idle GPU, before the runs: the paper cases' resting
# windows (the resting step: a run's first progress interval already holds flow) and the 1e7
# blocks (OUT/bench.csv; --bench-kernels: scree-bench's variants, fast first; the table reads
# fast). --scree-args: more arguments for every run's scree (e.g. --no-output).
# Kernel variants of KernelPolicy are scree-bench's (--kernels); scree's own few (--no-graphs,
# --no-refill) go through --scree-args. Each run's profile (ms per step and mean dt per interval) is
# OUT/runs/<label>/profile.csv (measure/whole-run-profile.py).
#
# On a lent GPU machine: carry the bundle (../shared/gpu/bundle.sh build-cuda) and run
#   source .gpu-bundle/env.sh && measure/whole-runs.sh --device cuda --out $OUT
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
device=cuda threads= build=${SCREE_BUILD_DIR:-$here/build-cuda} out=$PWD/whole-runs bench=0 bench_kernels=fast scree_args=
runs=()
while [ $# -gt 0 ]; do
  case $1 in
    --device) device=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --bench) bench=1; shift ;;
    --bench-kernels) bench_kernels=$2; shift 2 ;;
    --scree-args) scree_args=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d'; exit 0 ;;
    *) runs+=("$1"); shift ;;
  esac
done
[ ${#runs[@]} -eq 0 ] && runs=(column flume)
scree=$build/bin/scree
[ -x "$scree" ] || { echo "whole-runs.sh: no $scree (build first, or --build DIR)" >&2; exit 2; }
mkdir -p "$out/runs"
csv=$out/whole-runs.csv
echo "run,case,device,particles,steps,simulated_s,wall_s,mean_ms_per_step,dearest_ms_per_step,last_ms_per_step,exit" > "$csv"
rm -f "$out/bench.csv"
if [ $bench = 1 ]; then
  # the resting windows and the blocks, on the idle GPU before the runs (scree-bench's own
  # windows: 8,000 resting steps of the column, 2,500 of the flume; blocks of 500 steps)
  "$build/bin/scree-bench" --device "$device" --cases column,flume,scaling --materials linearElastic,phaseTransition \
    --shapes linear --schemes USL --steps 500 --kernels "$bench_kernels" --column-late-at 0 --flume-late-at 0 --csv "$out/bench.csv" \
    --json "$out/bench.json" > "$out/bench.log" 2>&1 || echo "whole-runs.sh: scree-bench failed (exit $?): $out/bench.log"
fi

for r in "${runs[@]}"; do
  case $r in
    column) src=$here/cases/columnCollapse label=column ;;
    flume) src=$here/cases/flume label=flume ;;
    *:*) src=${r%%:*} label=${r##*:} ;;
    *) src=$r label=$(basename "$r") ;;
  esac
  [ -d "$src/system" ] || { echo "whole-runs.sh: $src is not a case directory" >&2; exit 2; }
  # copy the case with what it includes from above: a variant's "../../../system/controlDict",
  # written in its system/, reaches 3 - 1 = 2 folders above the case
  src=$(cd "$src" && pwd)
  up=$(grep -rhoE '"(\.\./)+' "$src/system" "$src/constant" 2>/dev/null | awk '{print gsub(/\.\.\//, "")}' |
    sort -n | tail -1)
  root=$src rel=
  for ((k = 1; k < ${up:-0}; k++)); do rel=/$(basename "$root")$rel; root=$(dirname "$root"); done
  rm -rf "$out/runs/$label" && mkdir -p "$out/runs/$label"
  cp -r "$root" "$out/runs/$label/case"
  rm -rf "$out/runs/$label/case"/{VTK,postProcessing,checkpoints} "$out/runs/$label/case$rel"/{VTK,postProcessing,checkpoints}
  d=$out/runs/$label/case$rel
  echo "$d" > "$out/runs/$label/case.dir"
  args=(--case "$d" --device "$device")
  [ -n "$threads" ] && args+=(--threads "$threads")
  # shellcheck disable=SC2206  # words, as on a command line
  [ -n "$scree_args" ] && args+=($scree_args)
  log=$out/runs/$label/run.log
  t0=$(date +%s.%N)
  "$scree" "${args[@]}" > "$log" 2>&1
  rc=$?
  wall=$(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")
  # progress lines: "t = ... s  step N  R steps/s ..." (carriage returns on a terminal)
  /usr/bin/env python3 "$here/measure/whole-run-profile.py" "$log" "$out/runs/$label/profile.csv" > "$out/runs/$label/facts.txt"
  read -r parts steps sim mean dear last < "$out/runs/$label/facts.txt"
  echo "$label,$d,$device,$parts,$steps,$sim,$wall,$mean,$dear,$last,$rc" >> "$csv"
  echo "$label: exit $rc, $steps steps, $wall s wall"
done

/usr/bin/env python3 "$here/measure/whole-runs-table.py" "$out"

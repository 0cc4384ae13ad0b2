#!/usr/bin/env bash
# measure/whole-runs.sh on a lent GPU machine, in the background, so that its runs (one after
# another, each alone on the GPU: these are the wall times a user waits for) outlast one device
# call.
#
#   measure/gpu-whole-runs.sh start [--gpu K] ARG...
#                                             launch whole-runs.sh ARG... (returns at once);
#                                             --gpu K: on GPU K alone (CUDA_VISIBLE_DEVICES),
#                                             so that a machine of several GPUs runs one
#                                             series per GPU side by side, each run alone on
#                                             its GPU (one start per K)
#   measure/gpu-whole-runs.sh wait SECONDS    until every series is done or SECONDS have
#                                             passed; prints the newest progress lines
#   measure/gpu-whole-runs.sh collect         $OUT/whole-runs.tar.gz (the table of all
#                                             series, CSV, JSON, logs, profiles, device,
#                                             scree-bench's figures)
#                                             and per run $OUT/<label>.tar.gz (postProcessing/,
#                                             VTK/particles.pvd, system/stages) and
#                                             $OUT/<label>-frames-K.tar.gz, the frames at the
#                                             times FRAMES names (the flume's figures' by
#                                             default: 0 0.05 0.15 0.45 0.85 3.05 s) in parts
#                                             under 16 MiB (all frames of a whole run were
#                                             230-280 MB; a call brings back 8 files;
#                                             FRAME_PART_BYTES sets the part size)
#
# RUN as whole-runs.sh takes it: column, flume, or CASE:LABEL. Run other CUDA programs (ctest
# -L gpu, scree-bench) before `start` or after the runs: they would share the GPU with them.
# A lent machine goes back about 30 s after a call returns, and with it a background run: make
# the calls back to back (start + wait 500, wait 570, ..., collect). Needs .gpu-bundle
# (../shared/gpu/bundle.sh build-cuda).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/gpu-common.sh"
W=/tmp/scree-whole-runs  # one folder per series: W/all, or W/gpuK with --gpu K
frames=${FRAMES-0 0.05 0.15 0.45 0.85 3.05}
out=${OUT:-$PWD/gpu-whole-runs-out}
here=$(cd "$(dirname "$0")/.." && pwd)

case ${1:-} in
  start)
    shift
    slot=all pin=()
    if [ "${1:-}" = --gpu ]; then
      # GPU K alone, and its share of the host's cores (the scree processes of the other
      # series would otherwise share them: the OpenMP threads of four runs on one set of cores)
      slot=gpu$2
      export CUDA_VISIBLE_DEVICES=$2
      ngpu=$(nvidia-smi -L 2> /dev/null | wc -l)
      per=$(($(nproc) / (ngpu > 0 ? ngpu : 1)))
      pin=(taskset -c $(($2 * per))-$(($2 * per + per - 1)))
      shift 2
    fi
    S=$W/$slot
    rm -rf $S && mkdir -p $S
    source "$here/.gpu-bundle/env.sh"
    nvidia-smi --query-gpu=index,name,memory.total,driver_version --format=csv > $S/device.txt 2>&1
    setsid "${pin[@]}" bash "$here/measure/whole-runs.sh" --device cuda --out $S "$@" > $S/whole-runs.log 2>&1 < /dev/null &
    disown -a
    echo "started on $slot${pin:+ (${pin[*]})}: $*"; cat $S/device.txt ;;
  wait)
    end=$(($(date +%s) + ${2:-500}))
    while [ "$(date +%s)" -lt $end ]; do
      done=1
      for S in $W/*/; do [ -f $S/whole-runs.json ] || done=0; done
      [ $done = 1 ] && break
      sleep 5
    done
    for S in $W/*/; do
      echo "== $(basename $S)"
      cat $S/whole-runs.log
      for f in $S/runs/*/run.log; do
        [ -f "$f" ] && echo "$(basename "$(dirname "$f")"): $(tail -c 300 "$f" | tr '\r' '\n' | grep -v '^$' | tail -1)"
      done
    done ;;
  collect)
    mkdir -p "$out"
    slots=$(cd $W && ls -d */ | tr -d /)
    # one table over every series: the resting step and the blocks from the one with --bench
    first=$(for s in $slots; do [ -f $W/$s/bench.csv ] && echo $s; done)
    others=$(for s in $slots; do [ -f $W/$s/bench.csv ] || echo $s; done)
    (cd $W && /usr/bin/env python3 "$here/measure/whole-runs-table.py" --json whole-runs.json $first $others > table.md)
    cat $W/table.md
    (cd $W && tar -czf "$out/whole-runs.tar.gz" table.md whole-runs.json $(for s in $slots; do ls $s/device.txt $s/whole-runs.log \
      $s/whole-runs.csv $s/whole-runs.json $s/runs/*/run.log $s/runs/*/profile.csv $s/bench.csv $s/bench.json \
      $s/bench.log 2> /dev/null; done))
    for r in $W/*/runs/*/; do
      label=$(basename "$r")
      d=$(cat "$r"case.dir 2> /dev/null) && [ -d "$d" ] || continue
      stages=$(cd "$r"case && ls system/stages 2> /dev/null)
      (cd "$d" && tar -czf "$out/$label.tar.gz" $(ls -d postProcessing VTK/particles.pvd 2> /dev/null) \
        ${stages:+-C "$r"case $stages})
      # the frames in parts of at most 15 MiB: a call brings back no file over 16 MiB (three
      # 5 mm flume frames made 18.6 MB), and at most 8 files
      part=0 size=0 group=()
      for f in $(gpu_frames_near "$d" $frames) ""; do
        s=$([ -n "$f" ] && stat -c %s "$d/$f" || echo 0)
        if [ ${#group[@]} -gt 0 ] && { [ -z "$f" ] || [ $((size + s)) -gt ${FRAME_PART_BYTES:-15728640} ]; }; then
          (cd "$d" && tar -czf "$out/$label-frames-$part.tar.gz" "${group[@]}")
          part=$((part + 1)) size=0 group=()
        fi
        [ -n "$f" ] && group+=("$f") && size=$((size + s))
      done
    done
    ls -la "$out" ;;
  *) sed -n '2,/^set -/p' "$0" | sed '$d'; exit 2 ;;
esac

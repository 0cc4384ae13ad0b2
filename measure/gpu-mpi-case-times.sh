#!/usr/bin/env bash
# One case's whole run on one GPU and then on N GPUs (mpirun -np N, one rank each), one
# after the other on an otherwise idle machine: the wall times a user waits for, and what
# the decomposed run spends per step (--profile's phases, the halo sums among them).
#
#   measure/gpu-mpi-case-times.sh BIN_DIR CASE OUT_DIR [N] [END_TIME]
#
# END_TIME replaces the case's endTime. OUT_DIR/<run>/log holds each run's log with its
# profile; OUT_DIR/times.txt the "scree: done" line of each.
set -euo pipefail
bin=$(cd "$1" && pwd); case_dir=$(cd "$2" && pwd); out=$3; n=${4:-2}; end=${5:-}
work=$(mktemp -d /tmp/scree-times.XXXXXX)
mkdir -p "$out"
: > "$out/times.txt"
for r in gpus-1 gpus-$n; do
  cp -r "$case_dir" "$work/$r"
  rm -rf "$work/$r/VTK" "$work/$r/postProcessing" "$work/$r/checkpoints"
  [ -n "$end" ] && sed -i -E "s/^(endTime[[:space:]]+)[^;]+;/\1$end;/" "$work/$r/system/controlDict"
  if [ "$r" = gpus-1 ]; then
    CUDA_VISIBLE_DEVICES=0 "$bin/scree" --case "$work/$r" --profile > "$work/$r.log" 2>&1 || true
  else
    mpirun --allow-run-as-root -np "$n" --bind-to none "$bin/scree" --case "$work/$r" --profile > "$work/$r.log" 2>&1 || true
  fi
  mkdir -p "$out/$r"
  cp "$work/$r.log" "$out/$r/log"
  cp -r "$work/$r/postProcessing" "$out/$r/" 2>/dev/null || true
  echo "$r: $(grep -a 'scree: done\|scree: error' "$work/$r.log" | tail -n 1)" | tee -a "$out/times.txt"
done
rm -rf "$work"

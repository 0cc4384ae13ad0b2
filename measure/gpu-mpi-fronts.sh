#!/usr/bin/env bash
# One case's fronts on one GPU, twice (their difference is the run-to-run spread of the
# GPU's floating-point atomics), and on N GPUs (mpirun -np N), side by side: whether a
# decomposed run gives the same flow within that spread.
#
#   measure/gpu-mpi-fronts.sh BIN_DIR CASE OUT_DIR [N] [END_TIME]
#
# The three runs start together: the one-GPU runs on GPUs 0 and N-1, the decomposed one on
# GPUs 0..N-1 (one rank each), so they share GPUs and their wall times are not performance
# figures. END_TIME replaces the case's endTime. Each run's postProcessing/ and log land in
# OUT_DIR/<run>/; OUT_DIR/fronts.txt compares every column of every function object's CSVs
# at every row: the largest difference between the one-GPU runs and between the decomposed
# run and the first one-GPU run (measure/compare_fronts.py).
set -euo pipefail
bin=$(cd "$1" && pwd); case_dir=$(cd "$2" && pwd); out=$3; n=${4:-2}; end=${5:-}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/scree-fronts.XXXXXX)
mkdir -p "$out"
for r in one-a one-b ranks-$n; do
  cp -r "$case_dir" "$work/$r"
  rm -rf "$work/$r/VTK" "$work/$r/postProcessing" "$work/$r/checkpoints"
  [ -n "$end" ] && sed -i -E "s/^(endTime[[:space:]]+)[^;]+;/\1$end;/" "$work/$r/system/controlDict"
done
CUDA_VISIBLE_DEVICES=0 "$bin/scree" --case "$work/one-a" > "$work/one-a.log" 2>&1 &
a=$!
CUDA_VISIBLE_DEVICES=$((n - 1)) "$bin/scree" --case "$work/one-b" > "$work/one-b.log" 2>&1 &
b=$!
mpirun --allow-run-as-root -np "$n" --bind-to none "$bin/scree" --case "$work/ranks-$n" > "$work/ranks-$n.log" 2>&1 &
c=$!
rc=0
wait $a || rc=1; wait $b || rc=1; wait $c || rc=1
for r in one-a one-b ranks-$n; do
  mkdir -p "$out/$r"
  cp -r "$work/$r/postProcessing" "$out/$r/" 2>/dev/null || true
  cp "$work/$r.log" "$out/$r/log"
done
/usr/bin/env python3 "$here/compare_fronts.py" "$out/one-a" "$out/one-b" "$out/ranks-$n" | tee "$out/fronts.txt"
rm -rf "$work"
exit $rc

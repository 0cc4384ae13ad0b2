#!/bin/bash
# Run the cases that generate.py wrote, several at once on one GPU (the cases are small
# 2D runs that do not fill a GPU alone), and pack their function-object results.
#
#   ./run-series.sh RUNS [JOBS] [SECONDS]
#
# RUNS     the folder generate.py wrote (its cases.txt gives the order; a case with a
#          log.txt from an earlier run is skipped)
# JOBS     cases at once (default 12)
# SECONDS  wall-clock budget of the whole batch: a case still running then is stopped
#          (its CSVs so far are kept, its status says "stopped"); default: none
# Environment: SCREE (default: scree on PATH), SCREE_DEVICE (default cuda), SCREE_ARGS
# (more options for every run, e.g. "--threads 1" on the CPU).
# Writes RUNS/<case>/log.txt and status.txt, and RUNS/results.tar.gz with every case's
# postProcessing/ CSVs, status and the last lines of its log.
set -u
runs=$(cd "${1:?usage: run-series.sh RUNS [JOBS] [SECONDS]}" && pwd)
jobs=${2:-12}
budget=${3:-0}
export SCREE=${SCREE:-scree}
export SCREE_DEVICE=${SCREE_DEVICE:-cuda}
export SCREE_ARGS=${SCREE_ARGS:-}
export OMP_NUM_THREADS=1
start=$(date +%s)
if [ "$budget" -gt 0 ]; then export DEADLINE=$((start + budget)); else export DEADLINE=0; fi

one() {
    local c=$1 t0 t1 rc left
    [ -e "$c/log.txt" ] && return 0
    t0=$(date +%s)
    if [ "$DEADLINE" -gt 0 ]; then
        left=$((DEADLINE - t0))
        if [ "$left" -le 5 ]; then echo "not started (no time left)" > "$c/status.txt"; return 0; fi
        timeout -s INT -k 20 "$left" "$SCREE" --case "$c" --device "$SCREE_DEVICE" $SCREE_ARGS > "$c/log.txt" 2>&1
    else
        "$SCREE" --case "$c" --device "$SCREE_DEVICE" $SCREE_ARGS > "$c/log.txt" 2>&1
    fi
    rc=$?
    t1=$(date +%s)
    case $rc in 0) s=finished ;; 124|130) s=stopped ;; *) s="failed rc=$rc" ;; esac
    echo "$s wall_s=$((t1 - t0))" > "$c/status.txt"
    echo "$(basename "$c"): $s in $((t1 - t0)) s; $(grep -o 'done: .*' "$c/log.txt" | tail -1)"
}
export -f one

cd "$runs"
if [ -f cases.txt ]; then list=$(cat cases.txt); else list=$(ls -d */ | tr -d /); fi
printf '%s\n' $list | xargs -P "$jobs" -I{} bash -c 'one "$PWD/{}"'
for c in $list; do [ -f "$c/log.txt" ] && tail -n 20 "$c/log.txt" > "$c/log-tail.txt"; done
files=$(for c in $list; do
    ls "$c"/status.txt "$c"/log-tail.txt "$c"/postProcessing/*/*.csv 2>/dev/null
done)
tar czf results.tar.gz $files
echo "batch: $(printf '%s\n' $list | wc -l) cases, $(($(date +%s) - start)) s wall; $runs/results.tar.gz"

#!/usr/bin/env bash
# The two-phase showcase's step on one GPU, drawn as it ships (cases/rainfallSlope: one
# polygon body tracing a staircase of whole cells) and as the staircase's 18 rectangles
# (variants/columns: the same 3,408 points): each body is launched on its own in every
# phase of the step, so the difference is what 17 more bodies' launches cost.
# Each run alone on the GPU, STEPS steps, with and without --profile; writes no output.
#
#   measure/gpu-slope-bodies.sh BIN_DIR OUT_DIR [STEPS]
#
# OUT_DIR gets one log per run and summary.txt (wall time per step of each run).
set -euo pipefail
bin=$(cd "$1" && pwd); out=$2; steps=${3:-20000}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
work=$(mktemp -d /tmp/scree-slope.XXXXXX)
cp -r "$here/cases/rainfallSlope" "$work/"
: > "$out/summary.txt"
for run in columns onePolygon; do
  dir=$work/rainfallSlope
  [ "$run" = columns ] && dir=$work/rainfallSlope/variants/columns
  for profile in no yes; do
    extra=(--no-output)
    [ "$profile" = yes ] && extra+=(--profile)
    log=$out/$run-profile-$profile.log
    "$bin/scree" --case "$dir" --device cuda --max-steps "$steps" "${extra[@]}" > "$log" 2>&1
    # "done: N steps, ... (steps S s at R steps/s, ...)": the steps' own time.
    echo "$run, profile $profile: $(grep -o 'done: .*' "$log" | sed -E 's/.*done: ([0-9]+) steps.*steps ([0-9.e+-]+) s at ([0-9.e+-]+) steps\/s.*/\1 steps in \2 s, \3 steps\/s/')" \
      | tee -a "$out/summary.txt"
  done
done
rm -rf "$work"

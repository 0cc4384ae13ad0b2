#!/usr/bin/env bash
# Run a fixed set of CPU cases with one build of Scree and collect every output file, so
# that two builds can be compared byte for byte (a refactor must not change a bit):
#
#   scripts/reference-outputs.sh BIN_DIR OUT_DIR        # e.g. build/bin /tmp/outputs-new
#   diff -r /tmp/outputs-old /tmp/outputs-new && echo identical
#
# Single-threaded CPU runs only: with several threads the order of the atomic additions
# into grid nodes changes the last bits from run to run. The column collapses run with
# `sortInterval 0`, so that outputs compare across commits whatever their sort schedule.
# The set: the elastic column (the
# default case), the column collapse meshes C-1 and C-2 with the phase-transition model and
# C-2 with the frictional model (cases/columnCollapse/variants), the flume at 20 mm cells,
# the infiltration column (both shortened), and every element test of
# cases/elementTests (frictional, collisional and combined models).
set -euo pipefail
bin=$(cd "$1" && pwd)
out=$2
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
work=$(mktemp -d /tmp/scree-ref-XXXXXX)
trap 'rm -rf "$work"' EXIT

run_case() {  # name, case root (copied, so the repository stays clean), case inside it
  local name=$1 root=$2 rel=${3:-.}
  mkdir -p "$work/$name"
  cp -r "$root/." "$work/$name/"  # variants #include their parent case's files
  local dir="$work/$name/$rel"
  rm -rf "$dir/VTK" "$dir/postProcessing" "$dir/checkpoints"  # what an earlier run in the source tree left
  if [ -n "${4:-}" ]; then echo "$4" >> "$dir/system/mpmSchemes"; fi
  if [ -n "${5:-}" ]; then printf '\n#inputMode overwrite\n%s\n' "$5" >> "$dir/system/controlDict"; fi
  if [ -n "${6:-}" ]; then printf '\n#inputMode overwrite\n%s\n' "$6" >> "$dir/system/gridDict"; fi
  "$bin/scree" --case "$dir" --device cpu --threads 1 > "$out/$name.log" 2>&1 ||
    { echo "reference-outputs: $name failed (see $out/$name.log)" >&2; exit 1; }
  mkdir -p "$out/$name"
  for d in VTK postProcessing; do
    if [ -d "$dir/$d" ]; then cp -r "$dir/$d" "$out/$name/"; fi
  done
}

run_case elasticColumn "$repo/cases/elasticColumn"
for v in C-1 C-2 frictional-C-2; do
  run_case "columnCollapse-$v" "$repo/cases/columnCollapse" "variants/$v" "sortInterval 0;"
done

# The flume at 20 mm cells to 0.45 s (every function object of the shipped case: run-out,
# probes, surface profile, energies with the budget) and the two-phase infiltration column
# to 0.5 s of rain (the pore liquid's passes, rainfall, the drained base).
run_case flume-coarse "$repo/cases/flume" . "sortInterval 0;" "endTime 0.45; writeInterval 0.05;" "cellSize 0.02;"
run_case infiltration1D "$repo/cases/infiltration1D" . "sortInterval 0;" "endTime 0.5; writeInterval 0.1;"

mkdir -p "$out/elementTests"
for dir in "$repo"/cases/elementTests/fig*/; do
  fig=$(basename "$dir")
  for f in "$dir"e0_* "$dir"steady_*; do
    [ -f "$f" ] || continue
    (cd "$dir" && "$bin/scree-element" "$(basename "$f")" -o "$out/elementTests/${fig}_$(basename "$f").csv") \
      > /dev/null 2>&1 || { echo "reference-outputs: element test $fig/$(basename "$f") failed" >&2; exit 1; }
  done
done
# The logs carry wall times: keep only what the run computed.
for l in "$out"/*.log; do
  grep -v -E 'wall|steps/s|elapsed|ETA|thread' "$l" > "$l.tmp" || true
  mv "$l.tmp" "$l"
done
echo "reference-outputs: $(find "$out" -type f | wc -l) files in $out"

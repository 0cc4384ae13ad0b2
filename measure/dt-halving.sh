#!/usr/bin/env bash
# Run a case at its time step and at half of it, and compare the deposits: the check that
# the numerical knobs (the PIC blend, damping) act per unit time, not per step.
#
#   measure/dt-halving.sh CASE WORK DT MAXCO [MPMSCHEMES_ENTRIES]
#
#   CASE   a case directory under cases/ (a variant too: cases/columnCollapse/variants/C-2)
#   WORK   where the two runs go: WORK/dt and WORK/dt-half, each a copy of the case's top
#          directory (variants include their parent's files)
#   DT, MAXCO   the case's deltaT and maxCo; the second run takes DT/2 and MAXCO/2, so that
#          the adaptive step and its cap are both halved
#   MPMSCHEMES_ENTRIES  entries that replace the case's own in system/mpmSchemes for both
#          runs, e.g. "picRate 0; picFraction 1e-4;" (the per-step blend, for contrast)
#
# Environment: SCREE (default build-cpu/bin/scree), SCREE_ARGS (default "--device cpu
# --threads 1"). The two runs go side by side. Prints the last row of each run's
# postProcessing/deposit/runOut.csv, the step count, and the relative change of the run-out
# and height when the step is halved, for the deposit (the furthest point) and, where the
# case has one, the massFront (a mass quantile: single grains thrown ahead do not move it).
#
# Example (CPU, 5 mm column):
#   measure/dt-halving.sh cases/columnCollapse/variants/C-2 /tmp/halving 1e-5 0.5
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 4 ] || { sed -n 2,22p "$0" >&2; exit 2; }
case_in=$(cd "$1" && pwd) work=$2 dt=$3 co=$4 schemes=${5:-}
scree=${SCREE:-$root/build-cpu/bin/scree}
args=${SCREE_ARGS:---device cpu --threads 1}
rel=${case_in#"$root"/cases/}
[ "$rel" != "$case_in" ] || { echo "dt-halving: $1 is not under $root/cases" >&2; exit 2; }
top=${rel%%/*}
sub=${rel#"$top"}
mkdir -p "$work"
run() {  # run NAME DT MAXCO
  local d="$work/$1"
  rm -rf "$d" && mkdir -p "$d" && cp -r "$root/cases/$top" "$d/"
  local c="$d/$top$sub"
  rm -rf "$c/VTK" "$c/postProcessing" "$c/checkpoints"
  # '#inputMode overwrite': these entries replace the case's own (also where the case sets
  # them in this very file).
  printf '\n#inputMode overwrite\ndeltaT %s;\nmaxCo %s;\nwriteInterval 0.5;\n' "$2" "$3" >> "$c/system/controlDict"
  [ -n "$schemes" ] && printf '\n#inputMode overwrite\n%s\n' "$schemes" >> "$c/system/mpmSchemes"
  # shellcheck disable=SC2086
  "$scree" --case "$c" $args > "$d/log" 2>&1 || { echo "dt-halving: $1 failed, see $d/log" >&2; return 1; }
}
half_dt=$(awk "BEGIN{print $dt/2}") half_co=$(awk "BEGIN{print $co/2}")
run dt "$dt" "$co" &
p1=$!
run dt-half "$half_dt" "$half_co" &
p2=$!
wait $p1 && wait $p2
for r in dt dt-half; do
  f="$work/$r/$top$sub/postProcessing/deposit/runOut.csv"
  echo "$r: $(tail -1 "$f") | $(grep -o 'done: [0-9]* steps' "$work/$r/log" | tail -1)"
done
for fo in deposit massFront; do
[ -f "$work/dt/$top$sub/postProcessing/$fo/runOut.csv" ] || continue
printf '%s: ' "$fo"
awk -F, 'FNR == 1 { next } { last[FILENAME] = $0 } END {
  n = 0; for (f in last) { split(last[f], v, ","); r[++n] = v[2]; h[n] = v[3]; name[n] = f }
  i = (name[1] ~ /dt-half/) ? 2 : 1; j = 3 - i
  printf "dt halved: run-out %+.2f%%, height %+.2f%%\n", 100 * (r[j] / r[i] - 1), 100 * (h[j] / h[i] - 1) }' \
  "$work/dt/$top$sub/postProcessing/$fo/runOut.csv" "$work/dt-half/$top$sub/postProcessing/$fo/runOut.csv"
done

#!/usr/bin/env bash
# Whole runs of the paper's cases, timed end to end, against the targets of the
# performance work (docs/performance.md): what a user waits for, not a step.
#
#   scripts/whole-runs.sh [--device cuda|cpu] [--threads N] [--build DIR] [--out DIR] [RUN...]
#
# RUN is column (cases/columnCollapse, 1 mm, 1.1 s), flume (cases/flume, 5 mm, 3.05 s), or
# CASE[:LABEL] for any other case directory (a variant: cases/flume/variants/S-1:S-1). Default:
# column flume. Each runs in a copy under OUT/runs/ (the case's own results are not touched),
# one after another, as shipped: its writers and function objects on, its own end time.
# Prints the targets table last (now / target) and writes OUT/whole-runs.csv and .json:
#
#   wall time of the whole run    column < 60 s (moonshot 15), flume < 120 s (moonshot 30)
#   late step / resting step      at most 2 (ms per step over the last progress interval, about
#                                 10 s of wall time, against the first)
#
# On a lent GPU machine: carry the bundle (../shared/gpu/bundle.sh build-cuda) and run
#   source .gpu-bundle/env.sh && scripts/whole-runs.sh --device cuda --out $OUT
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
device=cuda threads= build=${SCREE_BUILD_DIR:-$here/build-cuda} out=$PWD/whole-runs
runs=()
while [ $# -gt 0 ]; do
  case $1 in
    --device) device=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) runs+=("$1"); shift ;;
  esac
done
[ ${#runs[@]} -eq 0 ] && runs=(column flume)
scree=$build/bin/scree
[ -x "$scree" ] || { echo "whole-runs.sh: no $scree (build first, or --build DIR)" >&2; exit 2; }
mkdir -p "$out/runs"
csv=$out/whole-runs.csv
echo "run,case,device,particles,steps,simulated_s,wall_s,first_ms_per_step,last_ms_per_step,late_over_rest,target_wall_s,moonshot_wall_s,exit" > "$csv"

for r in "${runs[@]}"; do
  target= moon=
  case $r in
    column) src=$here/cases/columnCollapse label=column target=60 moon=15 ;;
    flume) src=$here/cases/flume label=flume target=120 moon=30 ;;
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
  args=(--case "$d" --device "$device")
  [ -n "$threads" ] && args+=(--threads "$threads")
  log=$out/runs/$label/run.log
  t0=$(date +%s.%N)
  "$scree" "${args[@]}" > "$log" 2>&1
  rc=$?
  wall=$(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")
  # progress lines: "t = ... s  step N  R steps/s ..." (carriage returns on a terminal)
  tr '\r' '\n' < "$log" | /usr/bin/env python3 -c '
import re, sys
lines = sys.stdin.read().splitlines()
# progress lines: steps and the elapsed wall time (m:ss or h:mm:ss) when each was printed
prog = []
for l in lines:
    m = re.search(r"step\s+(\d+).*elapsed ([\d:]+)", l)
    if m:
        sec = 0
        for part in m.group(2).split(":"):
            sec = 60 * sec + int(part)
        prog.append((int(m.group(1)), sec))
head = re.search(r"(\d+) particles", "\n".join(lines))
done = re.search(r"done: (\d+) steps, ([\d.e+-]+) s simulated", "\n".join(lines))
n = int(done.group(1)) if done else (prog[-1][0] if prog else 0)
def ms(a, b):  # ms per step between two progress lines
    return 1e3 * (b[1] - a[1]) / (b[0] - a[0]) if b[0] > a[0] else float("nan")
pts = [(0, 0)] + prog
first = ms(pts[0], pts[1]) if len(pts) > 1 else float("nan")   # the first interval (~10 s)
last = ms(pts[-2], pts[-1]) if len(pts) > 2 else float("nan")  # the last one
print(head.group(1) if head else "", n, done.group(2) if done else "", "%.4g" % first, "%.4g" % last,
      "%.3g" % (last / first) if first == first and first > 0 else "nan")
' > "$out/runs/$label/facts.txt"
  read -r parts steps sim first last ratio < "$out/runs/$label/facts.txt"
  echo "$label,$d,$device,$parts,$steps,$sim,$wall,$first,$last,$ratio,$target,$moon,$rc" >> "$csv"
  echo "$label: exit $rc, $steps steps, $wall s wall"
done

/usr/bin/env python3 - "$csv" "$out/whole-runs.json" <<'EOF'
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
json.dump(rows, open(sys.argv[2], "w"), indent=1)
print("\n| run | device | points | steps | wall now | target | moonshot | late/rest step now | target |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows:
    t = ("< %s s" % r["target_wall_s"]) if r["target_wall_s"] else ""
    m = ("%s s" % r["moonshot_wall_s"]) if r["moonshot_wall_s"] else ""
    bad = "" if r["exit"] == "0" else " (exit %s)" % r["exit"]
    print("| %s | %s | %s | %s | %s s%s | %s | %s | %s | <= 2 |" % (r["run"], r["device"], r["particles"], r["steps"],
          r["wall_s"], bad, t, m, r["late_over_rest"]))
EOF

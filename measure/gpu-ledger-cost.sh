#!/usr/bin/env bash
# What the energy ledger costs a step of a case, and where it goes: the case as shipped (an
# `energies` function object with `budget yes` keeps the ledger) against a copy of it with
# `budget no`, the only difference, run one after the other on the same GPU:
#   1. `scree --profile`: each phase of the step timed, synchronising after each;
#   2. Nsight Compute's own time of every kernel over a window of launches (no
#      synchronisation between kernels; graphs off, as ncu needs).
#
#   measure/gpu-ledger-cost.sh <case-dir> <steps> <out-dir> [<ncu-skip> <ncu-count>]
#
# <steps>: steps of each profiled run (from t = 0: the resting step of a case that starts
# at rest); the ncu window skips <ncu-skip> launches and times <ncu-count> (default 4000
# and 120: a few dozen steps after the first thousand). Writes into <out-dir>:
# profile-{ledger,plain}.txt, kernels-{ledger,plain}.csv (per kernel: launches, mean / min /
# max us) and prints both tables. SCREE_BUILD_DIR: the build (default build).
set -euo pipefail
case_dir=$1 steps=$2 out=$3 skip=${4:-4000} count=${5:-120}
bin=${SCREE_BUILD_DIR:-build}/bin/scree
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$case_dir" "$work/ledger"
cp -r "$case_dir" "$work/plain"
grep -rl 'budget[[:space:]]*yes' "$work/plain/system" | xargs -r sed -i 's/budget\([[:space:]]*\)yes/budget\1no/'
if ! grep -rq 'budget[[:space:]]*yes' "$work/ledger/system"; then
  echo "gpu-ledger-cost.sh: $case_dir keeps no energy ledger (no 'budget yes' in system/)" >&2
  exit 2
fi
for v in ledger plain; do
  "$bin" --case "$work/$v" --profile --max-steps "$steps" --overwrite >"$out/profile-$v.txt" 2>&1
  echo "== $v: scree --profile, $steps steps"
  grep -v '^t = ' "$out/profile-$v.txt" | tail -30
done
if command -v ncu >/dev/null; then
  for v in ledger plain; do
    ncu --clock-control none --launch-skip "$skip" --launch-count "$count" --csv --page raw \
      --metrics gpu__time_duration.sum "$bin" --case "$work/$v" --no-graphs --overwrite \
      --max-steps $((steps)) >"$out/kernels-$v.raw" 2>"$out/kernels-$v.log" || {
      tail -5 "$out/kernels-$v.log"
      continue
    }
    /usr/bin/env python3 - "$out/kernels-$v.raw" "$out/kernels-$v.csv" <<'PY'
import collections, csv, re, sys
rows = list(csv.reader(open(sys.argv[1])))
rows = rows[next(i for i, r in enumerate(rows) if r[:1] == ["ID"]):]  # after the program's own output
head, units = rows[0], rows[1]
ix = {k: head.index(k) for k in head}
scale = 1e-3 if units[ix["gpu__time_duration.sum"]] in ("ns", "nsecond") else 1.0
agg = collections.OrderedDict()
for r in rows[2:]:
    name = re.sub(r"\s+", " ", r[ix["Kernel Name"]]).strip()[:120]
    if not name:
        continue
    t = float(r[ix["gpu__time_duration.sum"]].replace(",", "")) * scale
    a = agg.setdefault(name, [0, 0.0, 1e30, 0.0])
    a[0] += 1; a[1] += t; a[2] = min(a[2], t); a[3] = max(a[3], t)
with open(sys.argv[2], "w") as f:
    f.write("kernel,launches,mean_us,min_us,max_us\n")
    for k, a in agg.items():
        f.write('"%s",%d,%.3f,%.3f,%.3f\n' % (k, a[0], a[1] / a[0], a[2], a[3]))
total = sum(a[1] for a in agg.values())
print("%-120s %8s %9s %9s" % ("kernel", "launches", "mean us", "sum us"))
for k, a in sorted(agg.items(), key=lambda kv: -kv[1][1]):
    print("%-120s %8d %9.2f %9.1f" % (k, a[0], a[1] / a[0], a[1]))
print("total %.1f us over %d launches" % (total, sum(a[0] for a in agg.values())))
PY
    echo "== $v: ncu, launches $skip .. $((skip + count))"
  done
else
  echo "(ncu not found: per-kernel times skipped)"
fi

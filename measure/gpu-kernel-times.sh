#!/usr/bin/env bash
# Per-kernel GPU times of a window of a case's steps, from Nsight Compute (ncu), on a lent
# GPU machine: which kernel of a step costs what, with no synchronisation between kernels.
#
#   measure/gpu-kernel-times.sh <case-dir> <max-steps> <skip-launches> <count> <out.csv>
#
# The case runs <max-steps> steps without output, its kernels launched one by one
# (--no-graphs: a USF step is four to six launches, a sort every 200 steps adds four);
# ncu times <count> launches after skipping <skip-launches>, with the clocks left alone
# (--clock-control none). ncu slows every launch it intercepts: keep max-steps just past
# the window. Writes <out.csv> (per kernel name: launches, mean / min / max duration
# in us, registers, grid) and <out.csv>.raw (ncu's own CSV), and prints the table.
# Example (the column at rest, steps ~1,000-1,015): gpu-kernel-times.sh cases/columnCollapse 1100 5000 60 k.csv
# SCREE_ARGS adds options to scree's command line (e.g. SCREE_ARGS="--threads 1"; kernel
# variants are scree-bench's --kernels, not scree's).
set -euo pipefail
case_dir=$1 max_steps=$2 skip=$3 count=$4 out=$5
bin=${SCREE_BUILD_DIR:-build}/bin/scree
ncu --clock-control none --launch-skip "$skip" --launch-count "$count" --csv --page raw \
  --metrics gpu__time_duration.sum,launch__registers_per_thread,launch__grid_size,launch__block_size \
  "$bin" --case "$case_dir" --no-output --no-graphs --max-steps "$max_steps" ${SCREE_ARGS:-} >"$out.raw" 2>"$out.log" || {
  tail -20 "$out.log"
  exit 1
}
python3 - "$out.raw" "$out" <<'PY'
import collections, csv, re, sys
rows = [r for r in csv.reader(open(sys.argv[1])) if len(r) > 5]
head, units = rows[0], rows[1]
ix = {k: head.index(k) for k in head}
scale = 1e-3 if units[ix["gpu__time_duration.sum"]] in ("ns", "nsecond") else 1.0  # to us
agg = collections.OrderedDict()
for r in rows[2:]:
    if not r[ix["Kernel Name"]]:
        continue
    name = re.sub(r"\s+", " ", r[ix["Kernel Name"]]).strip()[:110]
    t = float(r[ix["gpu__time_duration.sum"]].replace(",", "")) * scale
    a = agg.setdefault(name, [0, 0.0, 1e30, 0.0, r[ix["launch__registers_per_thread"]], r[ix["launch__grid_size"]]])
    a[0] += 1; a[1] += t; a[2] = min(a[2], t); a[3] = max(a[3], t)
with open(sys.argv[2], "w") as f:
    f.write("kernel,launches,mean_us,min_us,max_us,registers,grid\n")
    for n, a in agg.items():
        f.write(f"\"{n}\",{a[0]},{a[1]/a[0]:.2f},{a[2]:.2f},{a[3]:.2f},{a[4]},{a[5].replace(',', '')}\n")
        print(f"{a[0]:4d} x {a[1]/a[0]:9.2f} us (min {a[2]:8.2f}, max {a[3]:8.2f})  regs {a[4]:>3} grid {a[5]:>6}  {n}")
PY

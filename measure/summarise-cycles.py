#!/usr/bin/env python3
"""Summarise the log of a diagnostic build with SCREE_REPORT_CYCLES (scree/core/report_cycles.hpp):
per window of steps, the slow warps of the particle pass and whether their cycles follow the
largest or the summed substeps of their lanes: whether a warp waits for its longest chain.

    measure/summarise-cycles.py LOG [WINDOW_STEPS]
"""
import collections, sys

window = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
rows = []  # (step, cycles, elastic_first, lanes, sum, max, p1, p2, p4)
for line in open(sys.argv[1], errors="replace"):
    w = line.split()
    if len(w) == 18 and w[0] == "pass-cycles":
        try:
            rows.append((int(w[3]), int(w[1]), int(w[5]), int(w[9]), int(w[11]), int(w[13]),
                         int(w[15]), int(w[16]), int(w[17])))
        except ValueError:
            pass
print(f"{len(rows)} slow warps")
by = collections.defaultdict(list)
for r in rows:
    by[r[0] // window * window].append(r)
print("steps            warps/step  cycles(med,max)      lanes  sum-substeps  max-substeps  stiff apex-search at-apex  cyc/sum  cyc/max")
for b in sorted(by):
    v = by[b]
    nsteps = len({r[0] for r in v})
    med = lambda i: sorted(r[i] for r in v)[len(v) // 2]
    cs = sum(r[1] for r in v); ss = sum(r[4] for r in v); sm = sum(r[5] for r in v)
    print(f"{b:7d}-{b+window-1:7d} {len(v)/nsteps:8.1f}  {med(1):9d} {max(r[1] for r in v):9d}  {med(3):5d}  {med(4):8d}  {med(5):8d}"
          f"  {sum(r[6] for r in v)/len(v):5.1f} {sum(r[7] for r in v)/len(v):5.1f} {sum(r[8] for r in v)/len(v):5.1f}"
          f"  {cs/max(ss,1):7.0f}  {cs/max(sm,1):7.0f}")
# correlation of cycles with the sum and with the max over the slowest warps
if rows:
    import statistics
    top = sorted(rows, key=lambda r: -r[1])[:2000]
    def corr(i):
        x = [r[i] for r in top]; y = [r[1] for r in top]
        try:
            return statistics.correlation(x, y)
        except Exception:
            return float("nan")
    print(f"slowest {len(top)} warps: corr(cycles, sum substeps) {corr(4):.3f}, corr(cycles, max substeps) {corr(5):.3f}, corr(cycles, lanes) {corr(3):.3f}")
    for r in top[:12]:
        print("  step %d cycles %d elastic-first %d lanes %d sum %d max %d paths %d %d %d" % r)

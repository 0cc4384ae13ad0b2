#!/usr/bin/env python3
"""The targets table of measure/whole-runs.sh, from one or more of its output folders.

    measure/whole-runs-table.py [--json FILE] OUT [OUT...]

Each OUT holds whole-runs.csv (one row per run) and perhaps bench.csv (scree-bench's resting
windows and 1e7 blocks, --bench). Several OUTs: runs made side by side, one GPU each
(measure/gpu-whole-runs.sh start --gpu K); their rows are joined, and the resting step and the
blocks come from the first OUT that has a bench.csv. Writes the rows and the bench as JSON
(FILE; by default whole-runs.json in the first OUT) and prints the table (markdown). A run whose label starts with column or flume is a paper case
(or a variant of one): it is held against that case's target and resting step.
"""
import csv
import json
import os
import sys

TARGETS = {"column": (60, 15), "flume": (120, 30)}  # wall-time target and moonshot [s]
REST = {"column": "column 1 mm (paper) at rest", "flume": "flume 5 mm (paper) at rest"}

args = sys.argv[1:]
json_file = None
if args[:1] == ["--json"]:
    json_file, args = args[1], args[2:]
outs = args
if not outs:
    sys.exit(__doc__)
json_file = json_file or os.path.join(outs[0], "whole-runs.json")
rows, bench = [], []
for o in outs:
    f = os.path.join(o, "whole-runs.csv")
    if os.path.exists(f):
        rows += list(csv.DictReader(open(f)))
    b = os.path.join(o, "bench.csv")
    if not bench and os.path.exists(b):
        bench = list(csv.DictReader(open(b)))


def bench_value(name, key, kernels="fast"):
    v = [float(b[key]) for b in bench if b["case"] == name and b["kernels"] == kernels]
    return v[0] if v else None


def paper_case(label):
    return next((c for c in TARGETS if label.startswith(c)), None)


for r in rows:
    c = paper_case(r["run"])
    r["target_wall_s"], r["moonshot_wall_s"] = (str(x) for x in TARGETS[c]) if c else ("", "")
    rest = bench_value(REST[c], "ms_per_step") if c else None
    r["rest_ms_per_step"] = "%.4g" % rest if rest else ""
    for k in ("dearest", "last"):
        ok = rest and r[k + "_ms_per_step"]
        r[k + "_over_rest"] = "%.3g" % (float(r[k + "_ms_per_step"]) / rest) if ok else ""
json.dump({"runs": rows, "bench": bench}, open(json_file, "w"), indent=1)
print("\n| run | device | points | steps | wall now | target | moonshot | ms/step: mean / dearest interval / last"
      " / at rest | dearest / rest now | last / rest now | target |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows:
    t = ("< %s s" % r["target_wall_s"]) if r["target_wall_s"] else ""
    m = ("%s s" % r["moonshot_wall_s"]) if r["moonshot_wall_s"] else ""
    bad = "" if r["exit"] == "0" else " (exit %s)" % r["exit"]
    print("| %s | %s | %s | %s | %s s%s | %s | %s | %s / %s / %s / %s | %s | %s | <= 2 |" % (
        r["run"], r["device"], r["particles"], r["steps"], r["wall_s"], bad, t, m, r["mean_ms_per_step"],
        r["dearest_ms_per_step"], r["last_ms_per_step"], r["rest_ms_per_step"] or "-",
        r["dearest_over_rest"] or "-", r["last_over_rest"] or "-"))
blocks = [(m, t, bench_value("block %s linear USL 10000000" % m, "particle_steps_per_s"))
          for m, t in (("phaseTransition", 4e9), ("linearElastic", 6e9))]
if any(v for _, _, v in blocks):
    print("\n| 2D block, 1e7 points, linear, USL, 500 steps | particle-steps/s now | target |")
    print("| --- | --- | --- |")
    for m, t, v in blocks:
        print("| %s | %s | >= %.0e |" % (m, "%.3g" % v if v else "-", t))
variants = sorted({b["kernels"] for b in bench} - {"fast"})
if variants:  # the other kernel variants' resting steps, beside fast's
    print("\n| resting step [ms] | fast | %s |" % " | ".join(variants))
    print("| --- | --- |" + " --- |" * len(variants))
    for c, name in REST.items():
        vals = [bench_value(name, "ms_per_step", k) for k in ["fast"] + variants]
        print("| %s | %s |" % (c, " | ".join("%.4g" % v if v else "-" for v in vals)))

#!/usr/bin/env python3
"""Tests of the whole-run timing scripts.

profile: measure/whole-run-profile.py on a log written here, whose progress lines come from a
         run whose wall time per step is known (a step of 0.5 ms for 1,000 steps, then 2 ms for
         500, at dt = 1e-5 s): the profile must give those figures back, the dearest interval
         and the last, to the four digits the log's steps/s carries.
run:     measure/whole-runs.sh --device cpu on cases/elasticColumn: exit 0, and the steps its
         controlDict implies (endTime 3 s at a fixed deltaT of 2e-4 s: 15,000).
table:   measure/whole-runs-table.py over two series written here (one GPU each, the bench in
         the second): one table of both; the resting step and the ratios from the series with
         the bench (0.8 / 0.05 = 16), a paper case's variant held against its case's target.
"""

import argparse
import csv
import os
import shutil
import subprocess
import sys


def check(cond, what):
    if not cond:
        print("FAILED:", what)
        sys.exit(1)
    print("ok:", what)


def profile(a):
    os.makedirs(a.work, exist_ok=True)
    log = os.path.join(a.work, "run.log")
    # progress lines as scree writes them (framework/src/solver/progress.cpp): steps/s is the
    # step count over the wall time since the start
    lines, step, wall, t = ["Running case: 2D, 1 body, 1234 particles, 100 grid nodes, backend cpu"], 0, 0.0, 0.0
    for n, ms in [(250, 0.5)] * 4 + [(125, 2.0)] * 4:
        step += n
        wall += n * ms / 1e3
        t += n * 1e-5
        lines.append("t = %10.6g s  step %9d  %.4g steps/s  50.0%%  elapsed 0:00  ETA 0:00" % (t, step, step / wall))
    lines.append("scree: done: %d steps, %g s simulated in %g s wall" % (step, t, wall))
    open(log, "w").write("\n".join(lines) + "\n")
    out = os.path.join(a.work, "profile.csv")
    r = subprocess.run([sys.executable, os.path.join(a.source, "measure", "whole-run-profile.py"), log, out],
                       capture_output=True, text=True)
    check(r.returncode == 0, "whole-run-profile.py exits 0 (%s)" % r.stderr.strip())
    parts, steps, sim, mean, dear, last = r.stdout.split()
    check(parts == "1234" and steps == "1500", "particles and steps read back: %s %s" % (parts, steps))
    check(abs(float(sim) - 0.015) < 1e-12, "simulated time 0.015 s: %s" % sim)
    check(abs(float(mean) - 1.5 / 1.5) < 1e-3, "mean 1.0 ms per step (1.5 s over 1,500 steps): %s" % mean)
    check(abs(float(dear) - 2.0) < 2e-3 and abs(float(last) - 2.0) < 2e-3, "dearest and last 2 ms: %s %s" % (dear, last))
    rows = list(csv.DictReader(open(out)))
    check(len(rows) == 8, "a row per progress interval: %d" % len(rows))
    check(all(abs(float(x["ms_per_step"]) - ms) < 2e-3 * ms for x, ms in zip(rows, [0.5] * 4 + [2.0] * 4)),
          "ms per step per interval: %s" % [x["ms_per_step"] for x in rows])
    check(all(abs(float(x["mean_dt_s"]) - 1e-5) < 1e-9 for x in rows[1:]), "mean dt 1e-5 s per interval")


def listing(d):
    return sorted((os.path.relpath(os.path.join(r, f), d), os.path.getmtime(os.path.join(r, f)))
                  for r, _, fs in os.walk(d) for f in fs)


def run(a):
    shutil.rmtree(a.work, ignore_errors=True)
    case = os.path.join(a.source, "cases", "elasticColumn")
    before = listing(case)
    r = subprocess.run(["bash", os.path.join(a.source, "measure", "whole-runs.sh"), "--device", "cpu", "--threads", "1",
                        "--build", a.build, "--out", a.work, case + ":ec"],
                       capture_output=True, text=True)
    print(r.stdout[-2000:], r.stderr[-2000:])
    check(r.returncode == 0, "whole-runs.sh exits 0")
    rows = list(csv.DictReader(open(os.path.join(a.work, "whole-runs.csv"))))
    check(len(rows) == 1 and rows[0]["exit"] == "0", "one run, exit 0")
    check(rows[0]["steps"] == "15000", "15,000 steps (3 s at 2e-4 s): %s" % rows[0]["steps"])
    check(rows[0]["particles"] == "1280", "1,280 particles: %s" % rows[0]["particles"])
    check("| ec | cpu | 1280 | 15000 |" in r.stdout, "the table printed")
    check(os.path.exists(os.path.join(a.work, "runs", "ec", "profile.csv")), "the run's profile written")
    check(listing(case) == before, "the case's own directory untouched (the run is in a copy)")


HEADER = ("run,case,device,particles,steps,simulated_s,wall_s,mean_ms_per_step,dearest_ms_per_step,"
          "last_ms_per_step,exit\n")


def table(a):
    shutil.rmtree(a.work, ignore_errors=True)
    one, two = os.path.join(a.work, "gpu0"), os.path.join(a.work, "gpu1")
    for d in (one, two):
        os.makedirs(d)
    open(os.path.join(one, "whole-runs.csv"), "w").write(
        HEADER + "column-0.01,/c,cuda,80000,300000,1.1,90.0,0.3,0.8,0.2,0\n")
    open(os.path.join(two, "whole-runs.csv"), "w").write(
        HEADER + "flume,/f,cuda,19952,400000,3.05,400.0,1.0,3.0,1.5,0\n")
    open(os.path.join(two, "bench.csv"), "w").write(
        "case,kernels,ms_per_step,particle_steps_per_s\n"
        "column 1 mm (paper) at rest,fast,0.05,\n"
        "column 1 mm (paper) at rest,ledger,0.07,\n"
        "flume 5 mm (paper) at rest,fast,0.3,\n"
        "flume 5 mm (paper) at rest,ledger,0.4,\n"
        "block phaseTransition linear USL 10000000,fast,,2.5e9\n")
    js = os.path.join(a.work, "all.json")
    r = subprocess.run([sys.executable, os.path.join(a.source, "measure", "whole-runs-table.py"), "--json", js, two, one],
                       capture_output=True, text=True)
    print(r.stdout, r.stderr)
    check(r.returncode == 0, "whole-runs-table.py exits 0")
    check("| column-0.01 | cuda | 80000 | 300000 | 90.0 s | < 60 s | 15 s | 0.3 / 0.8 / 0.2 / 0.05 | 16 | 4 |"
          in r.stdout, "the variant against the column's target and resting step (0.8 / 0.05 = 16)")
    check("| flume | cuda | 19952 | 400000 | 400.0 s | < 120 s | 30 s | 1.0 / 3.0 / 1.5 / 0.3 | 10 | 5 |" in r.stdout,
          "the flume from the other series (3.0 / 0.3 = 10)")
    check("| phaseTransition | 2.5e+09 | >= 4e+09 |" in r.stdout, "the block's figure")
    check("| --- | --- | --- |\n| column | 0.05 | 0.07 |" in r.stdout and "| flume | 0.3 | 0.4 |" in r.stdout,
          "the other kernel variants' resting steps beside fast's")
    check(len(__import__("json").load(open(js))["runs"]) == 2, "both series' rows in the JSON")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["profile", "run", "table"])
    ap.add_argument("--source", required=True)
    ap.add_argument("--build")
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    {"profile": profile, "run": run, "table": table}[a.what](a)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Where a whole run of scree spent its wall time, from its log alone.

    whole-run-profile.py LOG PROFILE_CSV

Reads the progress lines of a scree log ("t = T s  step N  R steps/s ..."; carriage returns
of a terminal are read as line ends) and writes PROFILE_CSV, a row per progress interval
(about 10 s of wall time): simulated time, steps, wall time, mean dt and ms per step. Prints
one line for measure/whole-runs.sh: particles, steps, simulated time, and ms per step over
the whole run, over its dearest interval and over its last one.
"""

import re
import sys

lines = open(sys.argv[1], errors="replace").read().replace("\r", "\n").splitlines()
# progress lines "t = T s  step N  R steps/s ...": R is N over the wall time since the start, to
# four digits, so N / R gives the wall time of each line more finely than its "elapsed m:ss"
prog = []
for l in lines:
    m = re.search(r"t =\s*([\d.e+-]+) s\s+step\s+(\d+)\s+([\d.e+-]+) steps/s", l)
    if m and int(m.group(2)) > 0 and float(m.group(3)) > 0:
        prog.append((float(m.group(1)), int(m.group(2)), int(m.group(2)) / float(m.group(3))))
head = re.search(r"(\d+) particles", "\n".join(lines))
done = re.search(r"done: (\d+) steps, ([\d.e+-]+) s simulated", "\n".join(lines))
n = int(done.group(1)) if done else (prog[-1][1] if prog else 0)
# one interval per pair of progress lines (the first from the start): about 10 s of wall time each
intervals = []
for a, b in zip([(None, 0, 0.0)] + prog, prog):
    if b[1] > a[1]:
        intervals.append({"t0": a[0], "t1": b[0], "steps": b[1] - a[1], "wall": b[2] - a[2],
                          "ms": 1e3 * (b[2] - a[2]) / (b[1] - a[1])})
with open(sys.argv[2], "w") as f:
    f.write("t_start_s,t_end_s,steps,wall_s,mean_dt_s,ms_per_step\n")
    for i in intervals:
        first = i["t0"] is None  # the run's start time is not in its log
        f.write("%s,%.6g,%d,%.4g,%s,%.5g\n" % ("" if first else "%.6g" % i["t0"], i["t1"], i["steps"], i["wall"],
                "" if first else "%.4g" % ((i["t1"] - i["t0"]) / i["steps"]), i["ms"]))
nan = float("nan")
mean = 1e3 * prog[-1][2] / prog[-1][1] if prog else nan
print(head.group(1) if head else "", n, done.group(2) if done else "", "%.4g" % mean,
      "%.4g" % max((i["ms"] for i in intervals), default=nan), "%.4g" % (intervals[-1]["ms"] if intervals else nan))

#!/usr/bin/python3
"""Where whole runs spend their wall time: ms per step and the mean time step against simulated
time, from the profiles measure/whole-runs.sh writes (measure/whole-run-profile.py: one row per
progress interval of about 10 s of wall time).

    whole_run_profile.py LABEL=PROFILE.csv [LABEL=PROFILE.csv ...] [--rest LABEL=MS ...] -o OUT.png

--rest draws a run's resting step (ms, from scree-bench's "at rest" window) as a line.
Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy).
"""

import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = list(csv.DictReader(open(path)))
    t0 = [float(r["t_start_s"]) if r["t_start_s"] else 0.0 for r in rows]
    t1 = [float(r["t_end_s"]) for r in rows]
    ms = [float(r["ms_per_step"]) for r in rows]
    dt = [(b - a) / int(r["steps"]) for a, b, r in zip(t0, t1, rows)]
    return t0, t1, ms, dt


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--rest", action="append", default=[])
    ap.add_argument("-o", "--out", default="whole-run-profile.png")
    a = ap.parse_args()
    rest = {k: float(v) for k, v in (r.split("=", 1) for r in a.rest)}
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for spec in a.runs:
        label, path = spec.split("=", 1)
        t0, t1, ms, dt = read(path)
        xs = [x for a_, b in zip(t0, t1) for x in (a_, b)]
        line, = ax1.plot(xs, [m for m in ms for _ in (0, 1)], label=label)
        ax2.plot(xs, [d for d in dt for _ in (0, 1)], color=line.get_color(), label=label)
        if label in rest:
            ax1.axhline(rest[label], color=line.get_color(), ls=":", lw=1,
                        label="%s at rest (scree-bench)" % label)
    ax1.set_yscale("log")
    ax1.set_ylabel("wall time per step [ms]")
    ax1.legend(fontsize=7)
    ax1.grid(alpha=0.3)
    ax2.set_yscale("log")
    ax2.set_ylabel("mean time step [s]")
    ax2.set_xlabel("simulated time [s]")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)


if __name__ == "__main__":
    main()

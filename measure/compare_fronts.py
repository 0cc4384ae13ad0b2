#!/usr/bin/env python3
"""Compare the function objects' CSVs (run-out, water balance, probes, ...) of three runs of one case: A and B (the same configuration run
twice: their difference is the run-to-run spread) and C (another configuration, e.g. on
several ranks). For each function object and column, prints the largest |B - A| and
|C - A| over the rows the runs share, and the values of the last shared row.

    compare_fronts.py RUN_A RUN_B RUN_C      (each a directory holding postProcessing/)
"""
import csv
import os
import sys


def number(x):
    try:
        return float(x)
    except ValueError:  # a column of names (a body's): compared as equal
        return 0.0


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], {row[0]: [number(x) for x in row[1:]] for row in rows[1:] if row}


def main():
    a, b, c = sys.argv[1:4]
    base = os.path.join(a, "postProcessing")
    if not os.path.isdir(base):
        print("no postProcessing in", a)
        return 1
    paths = [os.path.join(fo, f) for fo in sorted(os.listdir(base)) if os.path.isdir(os.path.join(base, fo))
             for f in sorted(os.listdir(os.path.join(base, fo))) if f.endswith(".csv")]
    for path in paths:
        fo = path
        runs = []
        for r in (a, b, c):
            p = os.path.join(r, "postProcessing", path)
            runs.append(read(p) if os.path.exists(p) else None)
        if any(r is None for r in runs):
            print(f"{fo}: missing in", [r for r, x in zip((a, b, c), runs) if x is None])
            continue
        header = runs[0][0]
        times = sorted(set(runs[0][1]) & set(runs[1][1]) & set(runs[2][1]), key=lambda t: (number(t), t))
        print(f"{path}: {len(times)} rows shared, last t = {times[-1] if times else '-'} s")
        print(f"  {'column':32s} {'max|B-A|':>12s} {'max|C-A|':>12s}   last row A / B / C")
        for k, name in enumerate(header[1:]):
            dba = max(abs(runs[1][1][t][k] - runs[0][1][t][k]) for t in times) if times else 0
            dca = max(abs(runs[2][1][t][k] - runs[0][1][t][k]) for t in times) if times else 0
            last = times[-1] if times else None
            vals = " / ".join(f"{runs[i][1][last][k]:.6g}" for i in range(3)) if last else "-"
            print(f"  {name:32s} {dba:12.4g} {dca:12.4g}   {vals}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

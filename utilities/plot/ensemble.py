#!/usr/bin/python3
"""An ensemble's results (scree/ensemble/ensemble.hpp) in one figure: for each summary
quantity, its histogram over the members that finished, its empirical exceedance curve
(the fraction of members above each value, ensemble/exceedance.csv), and its scatter
against each parameter that was drawn or listed as a number.

    ensemble.py CASE [--quantities a,b] [--offset massFront=-0.2] [--scale massFront=5] [-o OUT.png]

--offset and --scale turn a quantity into the one to show (the run-out from the column's
toe in column heights: the front minus L0, over H0) before anything is drawn; the axis
label then says what was done. Members that did not finish are counted in the title.

Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy).
"""

import argparse
import csv
import os
import re
import sys

import numpy as np


def parse_map(items):
    out = {}
    for it in items or []:
        for part in it.split(","):
            k, v = part.split("=")
            out[k] = float(v)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--quantities", help="comma-separated summary quantities (default: all)")
    ap.add_argument("--offset", action="append", help="name=value added to a quantity")
    ap.add_argument("--scale", action="append", help="name=value a quantity is multiplied by (after the offset)")
    ap.add_argument("-o", "--output", default=None)
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = os.path.join(a.case, "ensemble", "members.csv")
    if not os.path.exists(path):
        sys.exit(f"{path}: no such file (run the ensemble first: scree --case {a.case})")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    head = list(rows[0].keys()) if rows else []
    cut = head.index("status")
    params, quantities = head[1:cut], head[cut + 3:]
    if a.quantities:
        quantities = [q for q in a.quantities.split(",") if q in quantities]
    done = [r for r in rows if r["status"] == "done"]
    offset, scale = parse_map(a.offset), parse_map(a.scale)
    numeric = [p for p in params if all(re.fullmatch(r"[-+0-9.eE]+", r[p] or "x") for r in done)]

    def values(q):
        v = np.array([float(r[q]) for r in done if r[q] != ""])
        return (v + offset.get(q, 0.0)) * scale.get(q, 1.0)

    def label(q):
        s = q
        if q in offset:
            s = f"({s} {'+' if offset[q] >= 0 else '-'} {abs(offset[q]):g})"
        if q in scale:
            s = f"{s} x {scale[q]:g}"
        return s

    ncol = 2 + len(numeric)
    fig, axes = plt.subplots(len(quantities), ncol, figsize=(3.6 * ncol, 3.0 * len(quantities)), squeeze=False)
    for i, q in enumerate(quantities):
        v = values(q)
        ax = axes[i][0]
        ax.hist(v, bins=max(5, int(np.sqrt(len(v)))), color="#4c72b0", edgecolor="white")
        ax.axvline(np.median(v), color="k", lw=1, ls="--")
        ax.set_xlabel(label(q))
        ax.set_ylabel("members")
        ax = axes[i][1]
        s = np.sort(v)
        ax.step(s, [(s > x).mean() for x in s], where="post", color="#c44e52")
        ax.set_xlabel(label(q))
        ax.set_ylabel("P(exceeded)")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
        for j, p in enumerate(numeric):
            ax = axes[i][2 + j]
            x = np.array([float(r[p]) for r in done if r[q] != ""])
            ax.scatter(x, v, s=8, color="#55a868")
            if len(x) > 2 and np.ptp(x) > 0:
                r = np.corrcoef(x, v)[0, 1]
                ax.set_title(f"r = {r:.2f}", fontsize=9)
            ax.set_xlabel(p)
            ax.set_ylabel(label(q))
    fig.suptitle(f"{os.path.basename(os.path.abspath(a.case))}: {len(done)} of {len(rows)} members finished")
    fig.tight_layout()
    out = a.output or os.path.join(a.case, "ensemble", "ensemble.png")
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()

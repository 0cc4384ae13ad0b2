#!/usr/bin/python3
"""The energy budget of a run (Feng et al. 2025, Appendix B) from its own output:
postProcessing/<name>/energies.csv of the function object `energies` with `budget yes`
(plugins/functionObjects/Energies.hpp says what each column is).

    energy_budget.py CASE [--name energy] [--release T] [-o OUT.png] [--json OUT.json]

The figure: the potential energy released since the first row (PE0 - PE), against the stack
of where it went (kinetic, stored elastic, granular temperature, plastic and collisional
dissipation, the PIC, damping and wall losses); the gap between the line and the stack is the
residual, shown below as a fraction of the potential energy at the first row. Times are
shifted by --release (the gate's opening, to show times after it). The JSON holds each term
at the last row and the largest |residual fraction|.

Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy).
"""

import argparse
import csv
import json
import os
import sys

import numpy as np

TERMS = [  # column, label, colour
    ("kinetic", "kinetic", "#1f77b4"),
    ("elastic", "stored elastic", "#9467bd"),
    ("granular", "granular temperature", "#e377c2"),
    ("plastic", "plastic (frictional) dissipation", "#8c564b"),
    ("collisional", "collisional dissipation", "#d62728"),
    ("picLoss", "PIC blend loss", "#ff7f0e"),
    ("dampingLoss", "damping loss", "#bcbd22"),
    ("wallLoss", "wall loss", "#7f7f7f"),
]


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head = [h.split(" [")[0] for h in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:] if len(r) == len(head)])
    return {h: data[:, i] for i, h in enumerate(head)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--name", default="energy", help="the function object's name (postProcessing/<name>)")
    ap.add_argument("--release", type=float, default=0.0, help="time shown as 0 [s]")
    ap.add_argument("-o", "--out", default=None, help="the PNG (default CASE/energy_budget.png)")
    ap.add_argument("--json", default=None, help="the numbers at the last row")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    path = os.path.join(a.case, "postProcessing", a.name, "energies.csv")
    if not os.path.exists(path):
        sys.exit(f"energy_budget.py: {path} not found (a function object `energies` with `budget yes`?)")
    d = read(path)
    if "residual" not in d:
        sys.exit(f"energy_budget.py: {path} has no budget columns (set `budget yes;` in its dictionary)")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = d["time"] - a.release
    released = d["potential"][0] - d["potential"]
    # stored terms as changes since the first row; dissipations and losses are cumulative already
    parts = []
    for col, label, colour in TERMS:
        v = d[col] - d[col][0] if col in ("kinetic", "elastic", "granular") else d[col]
        parts.append((v, label, colour))
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(8, 7), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    pos = [np.clip(v, 0, None) for v, _, _ in parts]
    ax.stackplot(t, *pos, labels=[l for _, l, _ in parts], colors=[c for _, _, c in parts], alpha=0.85)
    ax.plot(t, released, "k-", lw=1.6, label="potential energy released")
    unit = "J/m" if "J/m" in open(path).readline() else "J"
    ax.set_ylabel(f"energy [{unit}]")
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    if a.title:
        ax.set_title(a.title)
    axr.plot(t, 100 * d["residualFraction"], "k-")
    axr.axhline(0, color="0.5", lw=0.8)
    for s in (-2, 2):
        axr.axhline(s, color="r", lw=0.8, ls="--")
    axr.set_ylabel("residual [% of PE0]")
    axr.set_xlabel("time" + (" after the release" if a.release else "") + " [s]")
    axr.grid(alpha=0.3)
    fig.tight_layout()
    out = a.out or os.path.join(a.case, "energy_budget.png")
    fig.savefig(out, dpi=120)
    last = {col: float(d[col][-1]) for col in ["time", "kinetic", "potential"] + [c for c, _, _ in TERMS[1:]]}
    last["released"] = float(released[-1])
    last["potential0"] = float(d["potential"][0])
    last["residual"] = float(d["residual"][-1])
    last["residualFraction"] = float(d["residualFraction"][-1])
    last["maxAbsResidualFraction"] = float(np.max(np.abs(d["residualFraction"])))
    last["residualOfReleased"] = float(d["residual"][-1] / released[-1]) if released[-1] else 0.0
    if a.json:
        with open(a.json, "w") as f:
            json.dump(last, f, indent=1)
    print(json.dumps(last, indent=1))


if __name__ == "__main__":
    main()

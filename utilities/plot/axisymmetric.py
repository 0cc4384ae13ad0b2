#!/usr/bin/python3
"""Figures of the axisymmetric collapse series (cases/axisymmetricCollapse) against the
scaling laws of Lube, Huppert, Sparks & Hallworth (2004, J. Fluid Mech. 508: 175-199):

  run-out   (r_inf - r0) / r0 = 1.24 a        for a < 1.7
                              = 1.6 a^(1/2)   for a > 1.7
  height    h_inf / r0        = a             for a < 0.74 (the top of the column is left)
                              = 0.88 a^(1/6)  for a > 0.74

with a = h0 / r0 the column's aspect ratio. Each run is given as A=DIR (DIR holds the run's
postProcessing/), e.g.

  axisymmetric.py 0.5=runs/a0.5 1=runs/a1 2=runs/a2 4=runs/a4 --r0 0.05 -o figures

Reads postProcessing/runOut/runOut.csv (the 0.99 mass quantile of the distance from the
axis, and the fronts in sectors around x and z), postProcessing/edge/runOut.csv (the
furthest point) and the height field postProcessing/surface/<time>.csv of the last write.
Writes runout_scaling.png, deposits.png, runout_history.png, plan_a<max>.png and
summary.json (the fitted exponents, the symmetry check, the final values).

Run with Debian's /usr/bin/python3 (python3-numpy, python3-matplotlib).
"""
import argparse
import csv
import glob
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

A_RUNOUT_BREAK = 1.7  # Lube et al. 2004: the run-out law changes here
A_HEIGHT_BREAK = 0.74  # and the height law here


def lube_runout(a):
    a = np.asarray(a, dtype=float)
    return np.where(a < A_RUNOUT_BREAK, 1.24 * a, 1.6 * np.sqrt(a))


def lube_height(a):
    a = np.asarray(a, dtype=float)
    return np.where(a < A_HEIGHT_BREAK, a, 0.88 * a ** (1.0 / 6.0))


def read_csv(path):
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    head = rows[0]
    data = np.array([[float(v) if v not in ("", "nan") else math.nan for v in r] for r in rows[1:]])
    return {h.split(" [")[0]: data[:, i] for i, h in enumerate(head)}


def last_surface(run):
    files = glob.glob(os.path.join(run, "postProcessing", "surface", "*.csv"))
    if not files:
        return None, None
    t, f = max((float(os.path.basename(p)[:-4]), p) for p in files)
    return t, read_csv(f)


def radial_profile(surf, width):
    """The height field binned by the distance from the axis (x = z = 0): the highest
    point of each ring of the given width."""
    keys = [k for k in surf if k not in ("height", "particles")]
    a, b = surf[keys[0]], surf[keys[1]]
    h = surf["height"]
    ok = np.isfinite(h)
    r = np.hypot(a[ok], b[ok])
    h = h[ok]
    edges = np.arange(0.0, r.max() + 2 * width, width)
    idx = np.digitize(r, edges) - 1
    prof = np.full(len(edges) - 1, math.nan)
    for i in range(len(prof)):
        sel = idx == i
        if sel.any():
            prof[i] = h[sel].max()
    return 0.5 * (edges[1:] + edges[:-1]), prof


def finish(fig, ax, xlabel, ylabel, title, path):
    """Labels, legend and the saved figure."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)


def fit_exponent(a, y):
    """Least-squares slope of log y against log a."""
    return float(np.polyfit(np.log(a), np.log(y), 1)[0]) if len(a) >= 2 else math.nan


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", help="A=DIR: the aspect ratio and the run's directory")
    p.add_argument("--r0", type=float, default=0.05, help="the columns' radius [m] (system/geometry)")
    p.add_argument("--bin", type=float, default=0.005, help="the surface profile's binWidth [m]")
    p.add_argument("-o", "--out", default=".", help="output directory")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    r0 = args.r0
    runs = sorted((float(s.split("=", 1)[0]), s.split("=", 1)[1]) for s in args.runs)

    summary = {"r0_m": r0, "runs": {}}
    fig_h, ax_h = plt.subplots(figsize=(6.5, 4))
    for a, run in runs:
        ro = read_csv(os.path.join(run, "postProcessing", "runOut", "runOut.csv"))
        edge_path = os.path.join(run, "postProcessing", "edge", "runOut.csv")
        edge = read_csv(edge_path) if os.path.exists(edge_path) else None
        sectors = {k: ro[k][-1] for k in ro if k.startswith("runout_")}
        t_s, surf = last_surface(run)
        rec = {
            "a": a,
            "h0_m": a * r0,
            "end_time_s": float(ro["time"][-1]),
            "kinetic_energy_end_J": float(ro["kinetic_energy"][-1]) if "kinetic_energy" in ro else None,
            "max_speed_end_m_s": float(ro["max_speed"][-1]) if "max_speed" in ro else None,
            "runout_q99_m": float(ro["runout"][-1]),
            "sector_fronts_m": {k: float(v) for k, v in sectors.items()},
            "runout_edge_m": float(edge["runout"][-1]) if edge is not None else None,
        }
        if len(sectors) >= 2:
            v = list(sectors.values())
            rec["sector_difference_m"] = float(max(v) - min(v))
        if surf is not None:
            rr, prof = radial_profile(surf, args.bin)
            rec["surface_time_s"] = t_s
            rec["height_on_axis_m"] = float(np.nanmax(prof[:2]))
            ax_h.plot(rr / r0, prof / r0, label="a = %g" % a)
        ax_h.plot([0, 1, 1], [a, a, 0], ":", color=ax_h.lines[-1].get_color() if ax_h.lines else "k", lw=0.8)
        summary["runs"]["%g" % a] = rec
        print("a = %-4g run-out (q99) %.4f m, edge %s m, sectors %s, height %s m" % (
            a, rec["runout_q99_m"], rec["runout_edge_m"], rec["sector_fronts_m"], rec.get("height_on_axis_m")))
    finish(fig_h, ax_h, "r / r0", "h / r0", "Deposits (dotted: the initial columns)",
           os.path.join(args.out, "deposits.png"))

    # ---- the scaling laws ----
    a = np.array([x for x, _ in runs])
    recs = [summary["runs"]["%g" % x] for x in a]
    rq = np.array([(r["runout_q99_m"] - r0) / r0 for r in recs])
    re = np.array([((r["runout_edge_m"] or math.nan) - r0) / r0 for r in recs])
    hh = np.array([(r.get("height_on_axis_m") or math.nan) / r0 for r in recs])
    lo, hi = a < A_RUNOUT_BREAK, a > A_RUNOUT_BREAK
    summary["exponents"] = {
        "runout_q99_below_1.7": fit_exponent(a[lo], rq[lo]),
        "runout_q99_above_1.7": fit_exponent(a[hi], rq[hi]),
        "runout_edge_below_1.7": fit_exponent(a[lo], re[lo]),
        "runout_edge_above_1.7": fit_exponent(a[hi], re[hi]),
        "height_above_0.74": fit_exponent(a[a > A_HEIGHT_BREAK], hh[a > A_HEIGHT_BREAK]),
        "lube_2004": {"runout_below_1.7": 1.0, "runout_above_1.7": 0.5, "height_above_0.74": 1.0 / 6.0},
    }
    summary["against_lube_2004"] = {
        "%g" % x: {"runout_q99": float(rq[i] / lube_runout(x)), "runout_edge": float(re[i] / lube_runout(x)),
                   "height": float(hh[i] / lube_height(x))}
        for i, x in enumerate(a)}
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    aa = np.geomspace(0.3, 6, 100)
    axs[0].loglog(aa, lube_runout(aa), "k-", lw=1, label="Lube et al. 2004")
    axs[0].loglog(a, rq, "o", label="Scree, 0.99 mass quantile")
    axs[0].loglog(a, re, "s", mfc="none", label="Scree, furthest point")
    axs[0].set_xlabel("a = h0 / r0")
    axs[0].set_ylabel("(r_inf - r0) / r0")
    axs[0].legend(fontsize=8)
    axs[1].loglog(aa, lube_height(aa), "k-", lw=1, label="Lube et al. 2004")
    axs[1].loglog(a, hh, "o", label="Scree")
    axs[1].set_xlabel("a = h0 / r0")
    axs[1].set_ylabel("h_inf / r0")
    axs[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "runout_scaling.png"), dpi=150)

    # ---- run-out over time ----
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for x, run in runs:
        ro = read_csv(os.path.join(run, "postProcessing", "runOut", "runOut.csv"))
        ax.plot(ro["time"], (ro["runout"] - r0) / r0, label="a = %g" % x)
        for k in ro:
            if k.startswith("runout_"):
                ax.plot(ro["time"], (ro[k] - r0) / r0, ":", color=ax.lines[-1].get_color(), lw=0.8)
    finish(fig, ax, "t [s]", "(r - r0) / r0", "Run-out (solid: all directions; dotted: the x and z sectors)",
           os.path.join(args.out, "runout_history.png"))

    # ---- plan view of the tallest column's deposit ----
    x_max, run_max = runs[-1]
    _, surf = last_surface(run_max)
    if surf is not None:
        keys = [k for k in surf if k not in ("height", "particles")]
        fig, ax = plt.subplots(figsize=(5.5, 4.5))
        sc = ax.scatter(surf[keys[0]], surf[keys[1]], c=surf["height"], s=6, marker="s", cmap="viridis")
        fig.colorbar(sc, label="height [m]")
        th = np.linspace(0, math.pi / 2, 50)
        r_law = r0 * (1 + lube_runout(x_max))
        ax.plot(r_law * np.cos(th), r_law * np.sin(th), "r--", lw=1, label="Lube et al. 2004")
        ax.plot(r0 * np.cos(th), r0 * np.sin(th), "w:", lw=1, label="the column")
        ax.set_aspect("equal")
        ax.set_xlabel(keys[0] + " [m]")
        ax.set_ylabel(keys[1] + " [m]")
        ax.set_title("Deposit of a = %g (one quarter)" % x_max)
        ax.legend(fontsize=7, loc="upper right")
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "plan_a%g.png" % x_max), dpi=150)

    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print(json.dumps(summary["exponents"], indent=1))


if __name__ == "__main__":
    main()

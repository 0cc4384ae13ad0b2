#!/usr/bin/python3
"""The axisymmetric collapse series (cases/axisymmetricCollapse) at two cell sizes and two
critical friction angles, against Lube, Huppert, Sparks & Hallworth (2004): one figure and
one table.

    cd cases/axisymmetricCollapse/series
    /usr/bin/python3 plot_series.py [--out results] [--label "devices, dates"]

Reads reference/<family>.tar.gz (each run's runOut, edge and energy CSVs and its last
surface profile, as the runs left them; unpacked to a temporary folder) and, for the
shipped 2.5 mm series with phi_c = 19.8 degrees, ../figures/summary.json (its runs' data
are not kept). Each family goes through utilities/plot/axisymmetric.py (the same measures:
the 0.99 mass quantile of the distance from the axis, the furthest point, the height on
the axis of the last surface profile), whose summary.json lands in OUT/<family>/. Writes
OUT/series.png and OUT/summary.md (the run-outs, heights, fitted exponents and how close
each run came to rest).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tarfile
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
PLOT = os.path.join(HERE, "..", "..", "..", "utilities", "plot", "axisymmetric.py")
sys.path.insert(0, os.path.dirname(PLOT))
from axisymmetric import lube_height as _lube_height, lube_runout as _lube_runout, read_csv  # noqa: E402
R0 = 0.05
VARIANT = {0.5: "variants/a0.5", 1: "variants/a1", 2: ".", 4: "variants/a4", 8: "variants/a8"}
# family -> (label, cell size [m], reference tarball or None for ../figures/summary.json)
FAMILIES = {
    "h2.5mm": ("2.5 mm, phi_c 19.8 (shipped)", 0.0025, None),
    "h5mm": ("5 mm, phi_c 19.8", 0.005, "h5mm.tar.gz"),
    "h2.5mm_phic30": ("2.5 mm, phi_c 30", 0.0025, "h2.5mm_phic30.tar.gz"),
    "h5mm_phic30": ("5 mm, phi_c 30", 0.005, "h5mm_phic30.tar.gz"),
}


def lube(a):
    return float(_lube_runout(a))


def lube_height(a):
    return float(_lube_height(a))


def fit(pairs):
    if len(pairs) < 2:
        return None
    x, y = np.log([p[0] for p in pairs]), np.log([p[1] for p in pairs])
    alpha, loglam = np.polyfit(x, y, 1)
    return float(alpha), float(math.exp(loglam))


def rest_state(run):
    """The kinetic energy at the end over its peak (runOut.csv)."""
    ke = read_csv(os.path.join(run, "postProcessing", "runOut", "runOut.csv"))["kinetic_energy"]
    return float(ke[-1] / ke.max())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--label", default="", help="the devices and dates of the runs, for the figure")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    data = {}
    tmp = tempfile.mkdtemp(prefix="scree_axisym_series_")
    for fam, (_, _, tarball) in FAMILIES.items():
        if tarball is None:
            with open(os.path.join(HERE, "..", "figures", "summary.json")) as f:
                s = json.load(f)
            data[fam] = {float(a): dict(r, ke_end_over_peak=None) for a, r in s["runs"].items()}
            continue
        root = os.path.join(tmp, fam)
        with tarfile.open(os.path.join(HERE, "reference", tarball)) as t:
            t.extractall(root)
        runs = [(a, os.path.join(root, v)) for a, v in VARIANT.items()
                if os.path.exists(os.path.join(root, v, "postProcessing", "runOut", "runOut.csv"))]
        out = os.path.join(args.out, fam)
        subprocess.run([sys.executable, PLOT] + [f"{a:g}={d}" for a, d in runs] + ["--r0", str(R0), "-o", out],
                       check=True, stdout=subprocess.DEVNULL)
        for name in os.listdir(out):  # keep the summary; the per-family figures are the plot script's
            if name.endswith(".png"):
                os.remove(os.path.join(out, name))
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        data[fam] = {float(a): dict(r, ke_end_over_peak=rest_state(d)) for (a, d), r in
                     zip(runs, (s["runs"][f"{a:g}"] for a, _ in runs))}

    lines = ["| family | a | (r - r0)/r0, 0.99 quantile | furthest point | Lube 2004 | quantile / law | "
             "h_inf/r0 | law | end (s) | kinetic energy, end / peak |", "|" + "---|" * 10]
    fits = {}
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    aa = np.logspace(np.log10(0.4), np.log10(10), 100)
    ax[0].loglog(aa, [lube(a) for a in aa], "k-", lw=1, label="Lube 2004: 1.24 a; 1.6 a^(1/2)")
    ax[1].loglog(aa, [lube_height(a) for a in aa], "k-", lw=1, label="Lube 2004: a; 0.88 a^(1/6)")
    style = {"h2.5mm": ("C0", "o"), "h5mm": ("C0", "s"), "h2.5mm_phic30": ("C2", "o"), "h5mm_phic30": ("C2", "s")}
    for fam, runs in data.items():
        label = FAMILIES[fam][0]
        pts = sorted((a, (r["runout_q99_m"] - R0) / R0) for a, r in runs.items())
        c, m = style[fam]
        ax[0].loglog([p[0] for p in pts], [p[1] for p in pts], m + ("-" if "2.5" in fam else "--"), color=c,
                     mfc=c if "2.5" in fam else "none", label=label)
        hts = sorted((a, r["height_on_axis_m"] / R0) for a, r in runs.items() if r.get("height_on_axis_m"))
        ax[1].loglog([p[0] for p in hts], [p[1] for p in hts], m + ("-" if "2.5" in fam else "--"), color=c,
                     mfc=c if "2.5" in fam else "none", label=label)
        fits[fam] = {"below": fit([p for p in pts if p[0] < 1.7]), "above": fit([p for p in pts if p[0] > 1.7])}
        for a, r in sorted(runs.items()):
            q = (r["runout_q99_m"] - R0) / R0
            e = (r["runout_edge_m"] - R0) / R0 if r.get("runout_edge_m") else None
            h = r.get("height_on_axis_m")
            ke = r.get("ke_end_over_peak")
            lines.append(f"| {label} | {a:g} | {q:.3f} | {'-' if e is None else f'{e:.3f}'} | {lube(a):.2f} | "
                         f"{q / lube(a):.2f} | {'-' if h is None else f'{h / R0:.3f}'} | {lube_height(a):.2f} | "
                         f"{r['end_time_s']:g} | {'-' if ke is None else f'{ke:.1e}'} |")
    lines += ["", "Exponents of (r - r0)/r0 (0.99 quantile) = lambda a^alpha (Lube 2004: 1 below a = 1.7, "
              "1/2 above):", ""]
    for fam, f in fits.items():
        parts = [f"{k}: " + ("-" if v is None else f"{v[1]:.2f} a^{v[0]:.2f}") for k, v in f.items()]
        lines.append(f"- {FAMILIES[fam][0]}: " + "; ".join(parts))
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    ax[0].set_xlabel("a = h0 / r0")
    ax[0].set_ylabel("(r_inf - r0) / r0, 0.99 quantile")
    ax[0].set_title("run-out")
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel("a = h0 / r0")
    ax[1].set_ylabel("h_inf / r0 on the axis")
    ax[1].set_title("final height")
    ax[1].legend(fontsize=8)
    fig.suptitle("Scree axisymmetric collapse (3D, one quarter): cell size and critical friction angle"
                 + (f" - {args.label}" if args.label else ""), fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "series.png"), dpi=110)


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Plot scree-element CSV files (stresses compression positive, Pa).

    plot_element_test.py A.csv [B.csv ...] -o figure.png [--preset NAME] [--labels a b ...]
    plot_element_test.py A.csv -o f.png --x shear_strain --y tau [--y sigma_v] [--logx] [--logy]

Presets (the figures of Feng et al. 2025 and common element tests):
  fig4      undrained simple shear, frictional: (a) tau vs sigma_v (stress path), (b) tau vs shear strain
  fig5      the same for the collisional model, plus (c) stresses vs shear rate
  fig6      tau and sigma_v vs shear rate: (a) log-log over all rates, (b) linear, 0.1-10 1/s
  fig7      one sample: frictional / collisional / total (a) vertical and (b) shear stress vs
            shear rate, (c) K_col = q_col/(q_col + q_f) and T vs shear rate
  history   stresses vs shear rate (log-log) and total/frictional stresses vs time
  steady    one CSV per constant shear rate: last-row (steady) stresses, K_col and T vs rate
  triaxial  q/p and volumetric strain vs axial strain, and the stress path q vs p
Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib).
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    """The CSV as a dict of columns (comment lines '#' before the header are skipped)."""
    with open(path) as f:
        lines = [ln for ln in f if ln.strip() and not ln.startswith("#")]
    names = lines[0].strip().split(",")
    values = np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    return {n: values[:, i] for i, n in enumerate(names)}


def label_of(path, labels, i):
    if labels and i < len(labels):
        return labels[i]
    return os.path.splitext(os.path.basename(path))[0]


def kpa(x):
    return x / 1e3


def positive(x):
    """Mask non-positive values for log axes."""
    y = np.array(x, dtype=float)
    y[y <= 0] = np.nan
    return y


def preset_fig4(sets, title):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    for lab, d in sets:
        ax[0].plot(kpa(d["sigma_v"]), kpa(d["tau"]), label=lab)
        ax[1].plot(d["shear_strain"], kpa(d["tau"]), label=lab)
    ax[0].set_xlabel(r"vertical stress $\sigma_v$ [kPa]")
    ax[0].set_ylabel(r"shear stress $\tau$ [kPa]")
    ax[0].set_title("(a) stress path")
    ax[1].set_xlabel(r"shear strain $\gamma$ [-]")
    ax[1].set_ylabel(r"shear stress $\tau$ [kPa]")
    ax[1].set_title("(b) shear stress vs shear strain")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    return fig


def preset_fig5(sets, title):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    for lab, d in sets:
        ax[0].plot(d["sigma_v"], d["tau"], label=lab)
        ax[1].plot(d["shear_strain"], d["tau"], label=lab)
        ln = ax[2].plot(d["shear_rate"], d["tau"], label=lab + r" $\tau$")
        ax[2].plot(d["shear_rate"], d["sigma_v"], "--", color=ln[0].get_color(), label=lab + r" $\sigma_v$")
    ax[0].set_xlabel(r"vertical stress $\sigma_v$ [Pa]")
    ax[0].set_ylabel(r"shear stress $\tau$ [Pa]")
    ax[0].set_title("(a) stress path")
    ax[1].set_xlabel(r"shear strain $\gamma$ [-]")
    ax[1].set_ylabel(r"shear stress $\tau$ [Pa]")
    ax[1].set_title("(b) shear stress vs shear strain")
    ax[2].set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
    ax[2].set_ylabel("stress [Pa]")
    ax[2].set_title(r"(c) stresses vs shear rate ($\propto \dot\gamma^2$)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].legend()
    ax[2].legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    return fig


def preset_fig6(sets, title):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    for lab, d in sets:
        r = d["shear_rate"]
        ln = ax[0].loglog(positive(r), positive(d["tau"]), label=lab + r" $\tau$")
        ax[0].loglog(positive(r), positive(d["sigma_v"]), "--", color=ln[0].get_color(), label=lab + r" $\sigma_v$")
        m = (r >= 0.1) & (r <= 10)
        ax[1].plot(r[m], d["tau"][m], color=ln[0].get_color(), label=lab + r" $\tau$")
        ax[1].plot(r[m], d["sigma_v"][m], "--", color=ln[0].get_color(), label=lab + r" $\sigma_v$")
    ax[0].set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
    ax[0].set_ylabel("stress [Pa]")
    ax[0].set_title("(a) wide range of shear rates")
    ax[1].set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
    ax[1].set_ylabel("stress [Pa]")
    ax[1].set_title("(b) shear rates 0.1 - 10 1/s")
    for a in ax:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    return fig


def preset_history(sets, title):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    for lab, d in sets:
        r, t = positive(d["shear_rate"]), positive(d["time"])
        ln = ax[0].loglog(r, positive(d["tau"]), label=lab + r" $\tau$")
        c = ln[0].get_color()
        ax[0].loglog(r, positive(d["sigma_v"]), "--", color=c, label=lab + r" $\sigma_v$")
        ax[1].loglog(t, positive(d["sigma_v"]), "--", color=c, label=lab + r" $\sigma_v$")
        ax[1].loglog(t, positive(d["sigma_v_f"]), ":", color=c, label=lab + r" $\sigma_{v,f}$")
        ax[1].loglog(t, positive(d["tau"]), "-", color=c, label=lab + r" $\tau$")
    ax[0].set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
    ax[0].set_ylabel("stress [Pa]")
    ax[0].set_title("(a) stresses vs shear rate")
    ax[1].set_xlabel("time [s]")
    ax[1].set_ylabel("stress [Pa]")
    ax[1].set_title("(b) stresses vs time (total, frictional)")
    for a in ax:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    return fig


def preset_steady(sets, title):
    """One CSV per constant shear rate: the last row of each (steady state)."""
    rows = sorted(((d["shear_rate"][-1], d) for _, d in sets), key=lambda x: x[0])
    r = np.array([x[0] for x in rows])
    last = {k: np.array([d[k][-1] for _, d in rows]) for k in ("tau", "tau_f", "tau_col", "sigma_v", "sigma_v_f",
                                                              "sigma_v_col", "K_col", "granular_temperature")}
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.6))
    ax[0].loglog(r, positive(last["sigma_v"]), "ko-", label=r"total $\sigma_v$")
    ax[0].loglog(r, positive(last["sigma_v_f"]), "bs--", label=r"frictional $\sigma_{v,f}$")
    ax[0].loglog(r, positive(last["sigma_v_col"]), "r^-.", label=r"collisional $\sigma_{v,col}$")
    ax[1].loglog(r, positive(last["tau"]), "ko-", label=r"total $\tau$")
    ax[1].loglog(r, positive(last["tau_f"]), "bs--", label=r"frictional $\tau_f$")
    ax[1].loglog(r, positive(last["tau_col"]), "r^-.", label=r"collisional $\tau_{col}$")
    ax[2].semilogx(r, last["K_col"], "mo-", label=r"$K_{col}$")
    a2 = ax[2].twinx()
    a2.loglog(r, positive(last["granular_temperature"]), "g:", marker=".", label="T")
    a2.set_ylabel(r"granular temperature T [m$^2$/s$^2$]", color="g")
    ax[0].set_ylabel("vertical stress [Pa]")
    ax[0].set_title("(a) steady vertical stress")
    ax[1].set_ylabel("shear stress [Pa]")
    ax[1].set_title("(b) steady shear stress")
    ax[2].set_ylabel(r"$K_{col} = q_{col}/(q_{col}+q_f)$", color="m")
    ax[2].set_ylim(-0.02, 1.02)
    ax[2].set_title("(c) collisional fraction and temperature")
    for a in ax:
        a.set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
        a.grid(alpha=0.3, which="both")
    ax[0].legend(fontsize=8)
    ax[1].legend(fontsize=8)
    fig.suptitle(title)
    return fig


def preset_fig7(sets, title):
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.6))
    for lab, d in sets:
        r = positive(d["shear_rate"])
        ax[0].loglog(r, positive(d["sigma_v"]), "k-", label=r"total $\sigma_v$")
        ax[0].loglog(r, positive(d["sigma_v_f"]), "b--", label=r"frictional $\sigma_{v,f}$")
        ax[0].loglog(r, positive(d["sigma_v_col"]), "r-.", label=r"collisional $\sigma_{v,col}$")
        ax[1].loglog(r, positive(d["tau"]), "k-", label=r"total $\tau$")
        ax[1].loglog(r, positive(d["tau_f"]), "b--", label=r"frictional $\tau_f$")
        ax[1].loglog(r, positive(d["tau_col"]), "r-.", label=r"collisional $\tau_{col}$")
        ax[2].semilogx(r, d["K_col"], "m-", label=r"$K_{col}$")
        a2 = ax[2].twinx()
        a2.loglog(r, positive(d["granular_temperature"]), "g:", label="T")
        a2.set_ylabel(r"granular temperature T [m$^2$/s$^2$]", color="g")
        break  # one sample per figure
    ax[0].set_ylabel("vertical stress [Pa]")
    ax[0].set_title("(a) vertical stress")
    ax[1].set_ylabel("shear stress [Pa]")
    ax[1].set_title("(b) shear stress")
    ax[2].set_ylabel(r"$K_{col} = q_{col}/(q_{col}+q_f)$", color="m")
    ax[2].set_ylim(-0.02, 1.02)
    ax[2].set_title("(c) collisional fraction and temperature")
    for a in ax:
        a.set_xlabel(r"shear rate $\dot\gamma$ [1/s]")
        a.grid(alpha=0.3, which="both")
    ax[0].legend(fontsize=8)
    ax[1].legend(fontsize=8)
    fig.suptitle(title)
    return fig


def preset_triaxial(sets, title):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    for lab, d in sets:
        ax[0].plot(d["axial_strain"], d["q"] / d["p"], label=lab)
        ax[1].plot(d["axial_strain"], d["volumetric_strain"], label=lab)
        ax[2].plot(kpa(d["p"]), kpa(d["q"]), label=lab)
    ax[0].set_xlabel(r"axial strain $\varepsilon_a$ [-]")
    ax[0].set_ylabel(r"stress ratio $q/p$")
    ax[1].set_xlabel(r"axial strain $\varepsilon_a$ [-]")
    ax[1].set_ylabel(r"volumetric strain $\varepsilon_v$ (compression +)")
    ax[2].set_xlabel("p [kPa]")
    ax[2].set_ylabel("q [kPa]")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    return fig


PRESETS = {"fig4": preset_fig4, "fig5": preset_fig5, "fig6": preset_fig6, "fig7": preset_fig7,
           "history": preset_history, "steady": preset_steady, "triaxial": preset_triaxial}


def generic(sets, xs, ys, logx, logy, title):
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for lab, d in sets:
        for y in ys:
            ax.plot(d[xs], d[y], label=f"{lab}: {y}")
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(xs)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    ax.set_title(title)
    return fig


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="scree-element CSV files")
    ap.add_argument("-o", "--output", required=True, help="output image (png, pdf, svg)")
    ap.add_argument("--preset", choices=sorted(PRESETS), help="figure layout")
    ap.add_argument("--labels", nargs="*", help="legend labels, one per CSV (default: file names)")
    ap.add_argument("--title", default="", help="figure title")
    ap.add_argument("--x", default="shear_strain", help="x column (no preset)")
    ap.add_argument("--y", action="append", help="y column(s) (no preset)")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    a = ap.parse_args(argv)
    sets = [(label_of(p, a.labels, i), load(p)) for i, p in enumerate(a.csv)]
    if a.preset:
        fig = PRESETS[a.preset](sets, a.title)
    else:
        fig = generic(sets, a.x, a.y or ["tau"], a.logx, a.logy, a.title)
    fig.tight_layout()
    fig.savefig(a.output, dpi=130)
    print(f"plot_element_test.py: wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

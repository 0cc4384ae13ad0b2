#!/usr/bin/python3
"""Figures of the flume test from a run's own output: section 4.2 of Feng, Liang, Yin & Hu
(2025), "Material point method modeling of granular flow considering phase transition from
solid-like to fluid-like states", Int. J. Numer. Anal. Methods Geomech. 49: 1642-1664
(after the experiment of Moriguchi et al. 2009).

    flume.py CASE [--frictional CASE_F] [-o OUTDIR]

CASE is a run of cases/flume (phaseTransition), CASE_F one of cases/flume/variants/frictional.
Reads VTK/particles.pvd and its .vtp files (those present: measure/gpu-flume.sh keeps the
release and 0.1, 0.4, 0.8, 1, 1.5, 2, 2.5 and 3 s after it), and postProcessing/: deposit
and massFront (runOut.csv), probes/{A,B,C}.csv, energy/energies.csv. Times are shown from
the gate's release (_releaseTime in system/stages). Writes PNGs and summary.json to OUTDIR:

  fig18b_initial_stress.png   vertical stress at t = 0, the geostatic initial state (the
                              paper: near -5 kPa at the deepest point); the release's beside it
  fig19_free_surface.png      the sand at 0.4 and 0.8 s with the fronts against the paper's
                              run-out distances (125 and 215 cm)
  fig20_fields.png            plastic strain, shear viscosity and granular temperature at
                              0.1, 0.8 and 3 s
  fig21_probes.png            the collisional deviatoric stress and the granular temperature
                              of particles A, B and C over time
  fig22_23_frictional.png     (with --frictional) plastic strain and |v| at 0.8 and 3 s for
                              both models
  front_history.png           the fronts over time along the flume's path, both origins (with
                              --frictional, that model's mass front beside them)
  summary.json                the numbers

The distance along the flume: the slope runs from x = X_TOP (the box's back wall) down to
the toe at X_TOE, then the flat floor; a point at x has travelled (x - x0)/cos 45 deg on the
slope and x - X_TOE beyond the toe. The paper does not say where its run-out distance d is
measured from: both the gate (x0 = X_GATE) and the box's back wall (x0 = X_TOP) are given.

Run with Debian's /usr/bin/python3 (python3-vtk9, python3-matplotlib, python3-numpy).
"""

import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from column_collapse import Series, read_csv, read_probes, release_time  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# m: cases/flume (constant/bodies, constant/boundaryConditions): the slope is the line x + y = X_TOE,
# from the box's back wall at x = X_TOP to the floor y = 0 at the toe x = X_TOE
X_TOP, X_GATE, X_TOE = 0.2, 0.553553, 1.826346
COS = math.cos(math.radians(45))
PAPER_FRONT = {0.4: 1.25, 0.8: 2.15}  # m, run-out d at 0.4 and 0.8 s (section 4.2.2)
FIELD_TIMES = [0.1, 0.8, 3.0]  # s after release (Figs. 20, 22, 23)
TOL = 1e-3




def path_from_gate(x, y):
    """Distance along the flume's path from the gate's foot (X_GATE on the slope): the
    projection on the slope's direction while on the slope, then along the floor. Exact for
    points in a thin layer on the bed, unlike along() of x alone, which adds a point's height
    above the slope."""
    s = ((x - X_GATE) - (y - (X_TOE - X_GATE))) * COS
    toe = (X_TOE - X_GATE) / COS
    return np.where(s <= toe, s, toe + (s - toe) / COS)


def along(x, x0):
    """Distance along the flume's path from x0 (on the slope) to the point of the bed below
    x: path_from_gate of the bed point, shifted to the origin x0."""
    x = np.asarray(x, dtype=float)
    return path_from_gate(x, np.maximum(X_TOE - x, 0.0)) + (X_GATE - x0) / COS


def snapshot(series, t):
    if series is None or not series.items:
        return None, None
    tt, f = series.nearest(t)
    if abs(tt - t) > TOL or not os.path.exists(f):
        return None, None
    return tt, f


def axes_flume(ax):
    ax.plot([0.1, X_TOP, X_TOE, 3.0], [X_TOE - 0.3, X_TOE - X_TOP, 0, 0], "k-", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlim(0.1, 3.0)
    ax.set_ylim(-0.05, 1.9)
    ax.tick_params(labelsize=7)


def save(fig, axs, path, legend=7):
    """Legend and grid on each of axs, then the figure to path."""
    for ax in axs:
        ax.legend(fontsize=legend)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=140)
    plt.close(fig)


def plot_field(ax, d, field, title, log=False, comp=None, cmap="viridis", vmin=None, vmax=None):
    v = d.get(field)
    if v is None:
        ax.set_title(title + " (missing)", fontsize=8)
        return None
    if comp == "norm":
        v = np.linalg.norm(v, axis=1)
    elif comp is not None:
        v = v[:, comp]
    if log:
        v = np.log10(np.maximum(v, 1e-12))
    sc = ax.scatter(d["x"][:, 0], d["x"][:, 1], c=v, s=0.6, marker="s", linewidths=0, cmap=cmap, vmin=vmin, vmax=vmax)
    axes_flume(ax)
    ax.set_title(title, fontsize=8)
    return sc


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("case")
    ap.add_argument("--frictional")
    ap.add_argument("-o", "--out", default="flume-figures")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    tr = release_time(a.case)
    if not os.path.exists(os.path.join(a.case, "system", "stages")):
        sys.exit("flume.py: %s has no system/stages: the gate's release time (_releaseTime) is "
                 "needed to give times after the release" % a.case)
    pp = os.path.join(a.case, "postProcessing")
    if not os.path.isdir(pp):
        sys.exit("flume.py: no %s (did the run write its function objects?)" % pp)
    series = Series(a.case)
    fields = ["stress", "velocity", "plasticStrain", "shearViscosity", "granularTemperature", "volume"]
    summary = {"case": os.path.abspath(a.case), "release_time_s": tr}

    # ---- fronts over time ----
    # the purely frictional model's mass front, drawn beside this run's (Figs. 22-23: "runs
    # farther") and read once for the summary
    ro_f, trf = None, release_time(a.frictional) if a.frictional else 0.0
    fr = os.path.join(a.frictional, "postProcessing", "massFront", "runOut.csv") if a.frictional else ""
    if fr and os.path.exists(fr):
        ro_f = read_csv(fr)
    fronts = {}
    for name in ("deposit", "massFront"):
        p = os.path.join(pp, name, "runOut.csv")
        if os.path.exists(p):
            fronts[name] = read_csv(p)
    if fronts:
        fig, ax = plt.subplots(figsize=(6, 3.6))
        labels = {"deposit": "leading point", "massFront": "mass front (99% of the points behind)"}
        for name, ro in fronts.items():
            t = ro["time"] - tr
            ok = t >= 0
            for x0, ls, where in ((X_GATE, "-", "gate"), (X_TOP, "--", "back wall")):
                ax.plot(t[ok], along(ro["runout"][ok], x0), ls, label="%s, from the %s" % (labels[name], where))
        if ro_f is not None:
            t = ro_f["time"] - trf
            ok = t >= 0
            ax.plot(t[ok], along(ro_f["runout"][ok], X_TOP), ":", color="k",
                    label="frictional model: mass front, from the back wall")
            fronts["frictional massFront"] = ro_f  # in summary.json's fronts too
        for ts, d in PAPER_FRONT.items():
            ax.plot(ts, d, "ks", label="paper, Fig. 19" if ts == 0.4 else None)
        ax.set_xlabel("t after release [s]")
        ax.set_ylabel("distance along the flume [m]")
        save(fig, [ax], os.path.join(a.out, "front_history.png"), legend=6)
        summary["fronts"] = {}
        for name, ro in fronts.items():
            rows = {}
            t0 = trf if name == "frictional massFront" else tr
            for ts in (0.4, 0.8, 1.0, 2.0, 3.0):
                j = int(np.argmin(np.abs(ro["time"] - (t0 + ts))))
                if abs(ro["time"][j] - (t0 + ts)) > 0.011:
                    continue
                x = float(ro["runout"][j])
                rows["%gs" % ts] = {"x_m": x, "from_gate_m": float(along(x, X_GATE)),
                                    "from_back_wall_m": float(along(x, X_TOP)),
                                    "kinetic_energy_J_per_m": float(ro["kinetic_energy"][j])}
            summary["fronts"][name] = rows

    # ---- the fronts from the snapshots, along the path (exact; runOut.csv holds x alone) ----
    rows = {}
    for t, f in series.items:
        if t < tr - TOL or not os.path.exists(f):
            continue
        d = Series.read(f, [])
        p = path_from_gate(d["x"][:, 0], d["x"][:, 1])
        rows["%.4g" % (t - tr)] = {"mass_front_from_gate_m": float(np.quantile(p, 0.99)),
                                   "leading_point_from_gate_m": float(p.max()),
                                   "mass_front_from_back_wall_m": float(np.quantile(p, 0.99) + (X_GATE - X_TOP) / COS)}
    summary["fronts_from_snapshots"] = rows

    # ---- Fig. 18b: vertical stress at t = 0 and at the release ----
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
    for ax, (t, label, key) in zip(axs, ((0.0, "t = 0 (geostatic)", "initial"), (tr, "the release", "release"))):
        tt, f = snapshot(series, t)
        if not f:
            ax.set_title("%s: no snapshot" % label, fontsize=8)
            continue
        d = Series.read(f, fields)
        sc = plot_field(ax, d, "stress", "vertical stress [kPa], %s" % label, comp=1, cmap="jet", vmin=-6, vmax=0)
        if sc is not None:
            sc.set_array(d["stress"][:, 1] / 1e3)
            fig.colorbar(sc, ax=ax, shrink=0.8)
            ax.set_xlim(0.15, 0.8)
            ax.set_ylim(1.2, 1.85)
            summary["%s_vertical_stress_min_kPa" % key] = float(d["stress"][:, 1].min() / 1e3)
            summary["%s_vertical_stress_p01_kPa" % key] = float(np.percentile(d["stress"][:, 1], 1) / 1e3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fig18b_initial_stress.png"), dpi=140)
    plt.close(fig)

    # ---- Fig. 19: the sand at 0.4 and 0.8 s ----
    fig, axs = plt.subplots(2, 1, figsize=(7, 6))
    for ax, ts in zip(axs, (0.4, 0.8)):
        tt, f = snapshot(series, tr + ts)
        if not f:
            ax.set_title("t = %g s: no snapshot" % ts, fontsize=8)
            continue
        d = Series.read(f, fields)
        sc = plot_field(ax, d, "velocity", "t = %g s after release: |v| [m/s]" % ts, comp="norm", cmap="jet")
        for x0, c in ((X_GATE, "r"), (X_TOP, "b")):
            dp = PAPER_FRONT[ts]  # the paper's d, placed along the path from x0
            x = x0 + dp * COS if x0 + dp * COS <= X_TOE else X_TOE + (dp - (X_TOE - x0) / COS)
            y = X_TOE - x if x <= X_TOE else 0.0
            ax.plot(x, y, "v", color=c, ms=7, label="paper d = %g m from the %s" % (dp, "gate" if c == "r" else "back wall"))
        ax.legend(fontsize=6, loc="upper right")
        if sc is not None:
            fig.colorbar(sc, ax=ax, shrink=0.7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fig19_free_surface.png"), dpi=140)
    plt.close(fig)

    # ---- Fig. 20: plastic strain, shear viscosity, granular temperature ----
    fig, axs = plt.subplots(3, 3, figsize=(12, 7))
    summary["snapshots"] = {}
    for j, ts in enumerate(FIELD_TIMES):
        tt, f = snapshot(series, tr + ts)
        if not f:
            for i in range(3):
                axs[i][j].set_title("t = %g s: no snapshot" % ts, fontsize=8)
            continue
        d = Series.read(f, fields)
        for i, (field, title, log) in enumerate((("plasticStrain", "plastic strain", False),
                                                 ("shearViscosity", "log10 shear viscosity [Pa s]", True),
                                                 ("granularTemperature", "log10 T [m2/s2]", True))):
            sc = plot_field(axs[i][j], d, field, "%s, t = %g s" % (title, ts), log=log, cmap="jet")
            if sc is not None:
                fig.colorbar(sc, ax=axs[i][j], shrink=0.7)
        sp = np.linalg.norm(d["velocity"], axis=1)
        summary["snapshots"]["%gs" % ts] = {"largest_speed_m_per_s": float(sp.max()),
                                           "points_faster_than_0.05": int((sp > 0.05).sum()),
                                           "max_x_m": float(d["x"][:, 0].max())}
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fig20_fields.png"), dpi=130)
    plt.close(fig)

    # ---- Fig. 21: particles A, B, C ----
    probes = read_probes(a.case)
    if probes:
        fig, axs = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
        for n, d in probes.items():
            t = d["time"] - tr
            axs[0].plot(t, d.get("collisionalDeviatoricStress", np.zeros_like(t)), label="particle " + n)
            axs[1].semilogy(t, np.maximum(d.get("granularTemperature", np.zeros_like(t)), 1e-14), label="particle " + n)
        axs[0].set_ylabel("q$_{col}$ [Pa]")
        axs[1].set_ylabel("T [m$^2$/s$^2$]")
        axs[1].set_xlabel("t after release [s]")
        save(fig, axs, os.path.join(a.out, "fig21_probes.png"))
        summary["probes"] = {}
        for n, d in probes.items():
            T = d.get("granularTemperature", np.zeros(1))
            fluid = np.nonzero(T > 1e-6)[0]  # fluid-like: T above 1e-6 m^2/s^2
            summary["probes"][n] = {
                "peak_q_col_Pa": float(np.nanmax(d.get("collisionalDeviatoricStress", [np.nan]))),
                "peak_T": float(np.nanmax(T)),
                "fluid_like_from_s": float(d["time"][fluid[0]] - tr) if len(fluid) else None,
                "fluid_like_until_s": float(d["time"][fluid[-1]] - tr) if len(fluid) else None}

    # ---- Figs. 22-23: the frictional model ----
    if a.frictional:
        sf = Series(a.frictional)
        fig, axs = plt.subplots(4, 2, figsize=(12, 9))
        for j, ts in enumerate((0.8, 3.0)):
            for k, (s, t0, label) in enumerate(((series, tr, "phase transition"), (sf, trf, "frictional"))):
                tt, f = snapshot(s, t0 + ts)
                if not f:
                    axs[2 * k][j].set_title("%s, t = %g s: no snapshot" % (label, ts), fontsize=8)
                    continue
                d = Series.read(f, fields)
                for i, (field, title, comp) in enumerate((("plasticStrain", "plastic strain", None),
                                                          ("velocity", "|v| [m/s]", "norm"))):
                    sc = plot_field(axs[2 * k + i][j], d, field, "%s: %s, t = %g s" % (label, title, ts), comp=comp,
                                    cmap="jet")
                    if sc is not None:
                        fig.colorbar(sc, ax=axs[2 * k + i][j], shrink=0.7)
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "fig22_23_frictional.png"), dpi=130)
        plt.close(fig)
        if ro_f is not None:
            ro = ro_f
            j = int(np.argmin(np.abs(ro["time"] - (trf + 3.0))))
            if abs(ro["time"][j] - (trf + 3.0)) < 0.01:
                summary["frictional_mass_front_at_3s_from_gate_m"] = float(along(ro["runout"][j], X_GATE))
            else:  # an unfinished run: its last front, and when
                summary["frictional_last_mass_front"] = {
                    "time_after_release_s": float(ro["time"][-1] - trf),
                    "from_gate_m": float(along(ro["runout"][-1], X_GATE)),
                    "from_back_wall_m": float(along(ro["runout"][-1], X_TOP))}

    with open(os.path.join(a.out, "summary.json"), "w") as fo:
        json.dump(summary, fo, indent=1)
    print(json.dumps(summary.get("fronts_from_snapshots", {}), indent=1))


if __name__ == "__main__":
    main()

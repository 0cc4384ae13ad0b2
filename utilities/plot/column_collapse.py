#!/usr/bin/python3
"""Figures of the granular column collapse from a run's own output: section 4.1 of Feng, Liang,
Yin & Hu (2025), "Material point method modeling of granular flow considering phase transition
from solid-like to fluid-like states", Int. J. Numer. Anal. Methods Geomech. 49: 1642-1664.

    column_collapse.py CASE [--frictional CASE_F] [-o OUTDIR]

CASE is a finished run of cases/columnCollapse (phaseTransition); CASE_F the same case
run with the purely frictional material (constant/bodies: material sandFrictional).
Reads VTK/particles.pvd (and its .vtp files), postProcessing/deposit/runOut.csv and
postProcessing/probes/{A,B,C}.csv; times are shown from the gate's release
(_releaseTime in system/stages). CASE needs snapshots at the release and 0.05, 0.25, 0.5
and 1 s after it; CASE_F only its last snapshot (1 s after the release) and, for Fig. 16,
one 0.5 s after it (measure/gpu-column.sh keeps only those two for a frictional run).
Writes PNGs and summary.json to OUTDIR:

  fig09_initial_stress.png      vertical stress at release against rho g (H - y) (Fig. 9b)
  fig10_free_surface.png        final free surface, with the paper's d_inf and h_inf
  fig11_strain_viscosity.png    equivalent plastic strain and shear viscosity at 0.05,
                                0.25, 0.5 and 1 s after release
  fig12_granular_temperature.png  granular temperature at the same times
  fig13_probes_kcol_rate.png    K_col and deviatoric strain rate of particles A, B, C
  fig14_probes_qcol_T.png       q_col and granular temperature of particles A and B
  fig15_surface_comparison.png  final surfaces, phase transition vs frictional
  fig16_velocity_x.png          v_x at 0.5 s after release, both models
  fig17_plastic_strain.png      plastic strain at the end, both models
  runout_history.png            run-out, deposit height and kinetic energy over time (both
                                models with --frictional)
  summary.json                  the numbers, for each run (the frictional one under
                                "frictional"): run-out and height (furthest particle of the
                                continuous deposit plus half a particle spacing; highest
                                particle plus half a spacing), kinetic energy (peak, 0.5 and
                                1 s after release) and the run-out tracker's front and top
                                (particle centres) from runOut.csv, the step number of each
                                snapshot, |v_x| statistics 0.5 s after release

Run with Debian's /usr/bin/python3 (python3-vtk9, python3-matplotlib, python3-numpy).
"""

import argparse
import json
import os
import re
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PAPER_RUNOUT = 0.42   # m, Feng et al. 2025, section 4.1.1 (Bui et al. 2008 experiment)
PAPER_HEIGHT = 0.10   # m
SNAP_TIMES = [0.05, 0.25, 0.5, 1.0]  # s after release (Figs. 11-12)
TOL = 1e-3  # s: a snapshot counts as "at" a time when it is this close


def release_time(case):
    path = os.path.join(case, "system", "stages")
    if not os.path.exists(path):
        return 0.0
    text = open(path).read()
    m = re.search(r"_releaseTime\s+([-+0-9.eE]+)\s*;", text)
    if not m:  # an include-only variant: follow the include
        inc = re.search(r'#include\s+"([^"]+)"', text)
        if inc:
            return release_time(os.path.dirname(os.path.dirname(os.path.normpath(os.path.join(os.path.dirname(path), inc.group(1))))))
        return 0.0
    return float(m.group(1))


def read_csv(path):
    with open(path) as f:
        header = [h.split(" [")[0] for h in f.readline().strip().split(",")]
    data = np.genfromtxt(path, delimiter=",", skip_header=1)
    if data.ndim == 1:
        data = data[None, :]
    return {h: data[:, i] for i, h in enumerate(header)}


class Series:
    """The .pvd series of a case: times and .vtp files; fields read on demand."""

    def __init__(self, case, name="particles"):
        pvd = os.path.join(case, "VTK", name + ".pvd")
        if not os.path.exists(pvd):
            sys.exit("column_collapse.py: no %s (did the run write VTK output?)" % pvd)
        root = ET.parse(pvd).getroot()
        self.items = [(float(d.get("timestep")), os.path.join(os.path.dirname(pvd), d.get("file")))
                      for d in root.iter("DataSet")]
        self.items.sort()

    def nearest(self, t):
        return min(self.items, key=lambda it: abs(it[0] - t))

    @staticmethod
    def read(path, fields):
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
        r = vtkXMLPolyDataReader()
        r.SetFileName(path)
        r.Update()
        poly = r.GetOutput()
        out = {"x": vtk_to_numpy(poly.GetPoints().GetData())}
        pd = poly.GetPointData()
        for f in fields:
            a = pd.GetArray(f)
            if a is not None:
                out[f] = vtk_to_numpy(a)
        return out


def read_probes(case, names=("A", "B", "C")):
    """postProcessing/probes/<name>.csv of each probe present (particleProbes), by name."""
    out = {}
    for n in names:
        p = os.path.join(case, "postProcessing", "probes", n + ".csv")
        if os.path.exists(p):
            out[n] = read_csv(p)
    return out


def snapshot_steps(series, tr):
    """Step number of every snapshot (field data "step" of the .vtp), by time after release."""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    out = []
    for t, f in series.items:
        r = vtkXMLPolyDataReader()
        r.SetFileName(f)
        r.Update()
        a = r.GetOutput().GetFieldData().GetAbstractArray("step")
        out.append({"time_after_release_s": round(t - tr, 9),
                    "step": int(a.GetVariantValue(0).ToDouble()) if a is not None else None})
    return out


def history_numbers(ro, tr):
    """Kinetic energy peak and values 0.5 and 1 s after the release, and the run-out
    tracker's front and top (particle centres) there, from runOut.csv."""
    t, ke = ro["time"], ro["kinetic_energy"]
    i = int(np.nanargmax(np.where(t >= tr, ke, -np.inf)))
    out = {"kinetic_energy_peak_J_per_m": float(ke[i]),
           "kinetic_energy_peak_time_after_release_s": round(float(t[i] - tr), 9)}
    for ts in (0.5, 1.0):
        j = int(np.argmin(np.abs(t - (tr + ts))))
        key = "%gs" % ts
        out["kinetic_energy_at_%s_J_per_m" % key] = float(ke[j])
        out["kinetic_energy_at_%s_over_peak" % key] = float(ke[j] / ke[i])
        out["max_speed_at_%s_m_per_s" % key] = float(ro["max_speed"][j])
        out["tracker_front_at_%s_m" % key] = float(ro["runout"][j])
        out["tracker_height_at_%s_m" % key] = float(ro["height"][j])
    return out


def plateau_edge(x, y, drop=0.001, width=0.001):
    """Right edge of the undisturbed top of the column: the first bin (of `width`) whose
    highest particle centre lies `drop` below the initial top (PAPER_HEIGHT)."""
    sx, sy = surface_profile(x, y, width)
    low = np.nonzero(sy < PAPER_HEIGHT - drop)[0]
    return float(sx[low[0]]) if len(low) else float("nan")


def velocity_numbers(d):
    """|v_x| statistics of one snapshot: 99th percentile over the particles, largest v_x,
    fraction of particles faster than 0.1 m/s, area (particle volume per metre of
    thickness) moving faster than 0.2 and 0.3 m/s in x."""
    vx = d["velocity"][:, 0]
    sp = np.linalg.norm(d["velocity"], axis=1)
    out = {"vx_p99": float(np.percentile(np.abs(vx), 99)), "vx_max": float(vx.max()),
           "fraction_speed_above_0.1": float(np.mean(sp > 0.1))}
    if "volume" in d:
        for v in (0.2, 0.3):
            out["area_vx_above_%g_m2" % v] = float(d["volume"][vx > v].sum())
    return out


def end_state(d):
    """What still moves in the last snapshot: particles faster than 0.05 m/s and their
    median position; the plateau edge (plateau_edge)."""
    x, y = d["x"][:, 0], d["x"][:, 1]
    moving = np.linalg.norm(d["velocity"], axis=1) > 0.05
    return {"largest_speed_m_per_s": float(np.linalg.norm(d["velocity"], axis=1).max()),
            "particles_faster_than_0.05": int(moving.sum()),
            "their_median_x_m": float(np.median(x[moving])) if moving.any() else None,
            "their_median_y_m": float(np.median(y[moving])) if moving.any() else None,
            "plateau_edge_m": plateau_edge(x, y)}


def surface_profile(x, y, width=0.002):
    """Upper envelope of the particles: highest particle per bin of `width`."""
    edges = np.arange(0.0, x.max() + width, width)
    idx = np.digitize(x, edges) - 1
    top = np.full(len(edges), np.nan)
    for i, yy in zip(idx, y):
        if np.isnan(top[i]) or yy > top[i]:
            top[i] = yy
    centres = edges + 0.5 * width
    ok = ~np.isnan(top)
    return centres[ok], top[ok]


def particle_spacing(case, data):
    """Initial particle spacing: sqrt of the particle volume (2D), else from the case's
    cellSize and particlesPerCell (include-only variants are followed)."""
    if "volume" in data:
        return float(np.sqrt(np.median(data["volume"])))
    def find(path, key):
        text = open(path).read()
        m = re.search(r"\b" + key + r"\s+([-+0-9.eE]+)\s*;", text)
        if m:
            return float(m.group(1))
        inc = re.search(r'#include\s+"([^"]+)"', text)
        return find(os.path.normpath(os.path.join(os.path.dirname(path), inc.group(1))), key) if inc else None
    h = find(os.path.join(case, "system", "gridDict"), "cellSize")
    n = find(os.path.join(case, "constant", "bodies"), "particlesPerCell") or 2
    return h / n


def deposit_front(x, y, spacing):
    """Run-out of the continuous deposit: the furthest particle whose neighbourhood (a
    bin of 2 spacings) holds at least 2 particles, which ignores isolated grains."""
    order = np.argsort(x)[::-1]
    for i in order:
        near = np.sum(np.abs(x - x[i]) < 2 * spacing)
        if near >= 2:
            return x[i]
    return x.max()


def scatter(ax, data, field, title, vmin=None, vmax=None, cmap="viridis", comp=None, log=False):
    x = data["x"]
    v = data.get(field)
    if v is None:
        ax.set_title(title + " (missing)")
        return None
    if comp is not None:
        v = v[:, comp]
    if log:
        v = np.log10(np.maximum(v, 1e-12))
    sc = ax.scatter(x[:, 0], x[:, 1], c=v, s=1.5, marker="s", linewidths=0, cmap=cmap, vmin=vmin, vmax=vmax)
    ax.set_aspect("equal")
    ax.set_xlim(0, 0.5)
    ax.set_ylim(0, 0.11)
    ax.set_title(title, fontsize=9)
    ax.tick_params(labelsize=7)
    return sc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--frictional", help="the same case run with the frictional material")
    ap.add_argument("-o", "--outdir", default=None)
    a = ap.parse_args()
    out = a.outdir or os.path.join(a.case, "figures")
    os.makedirs(out, exist_ok=True)
    tr = release_time(a.case)
    series = Series(a.case)
    summary = {"release_time_s": tr}

    # ---- Fig. 9b: the stress field at release against rho g (H - y) ----
    t_rel, f_rel = series.nearest(tr)
    d0 = Series.read(f_rel, ["stress", "mass", "volume", "displacement"])
    y0 = d0["x"][:, 1] - d0["displacement"][:, 1]
    rho0 = float(np.median(d0["mass"] / d0["volume"]))
    H = 0.1
    exact = -rho0 * 9.81 * (H - y0)
    h0 = particle_spacing(a.case, d0) * 2  # cell size (2 particles per cell)
    rows = np.floor(y0 / h0).astype(int)
    dev = max(abs(d0["stress"][rows == r, 1].mean() - exact[rows == r].mean()) for r in np.unique(rows))
    summary["initial_stress_max_row_deviation_over_rho_g_H"] = dev / (rho0 * 9.81 * H)
    fig, ax = plt.subplots(figsize=(4, 4))
    ax.plot(-d0["stress"][:, 1] / 1e3, d0["x"][:, 1], ".", ms=1, label="particles at release")
    yy = np.linspace(0, H, 50)
    ax.plot(rho0 * 9.81 * (H - yy) / 1e3, yy, "r-", label="$\\rho g (H - y)$")
    ax.set_xlabel("vertical stress $-\\sigma_{yy}$ [kPa]")
    ax.set_ylabel("y [m]")
    ax.set_title("t = %.2f s: max row error %.2f%% of $\\rho g H$" % (t_rel, 100 * dev / (rho0 * 9.81 * H)), fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig09_initial_stress.png"), dpi=140)
    plt.close(fig)

    # ---- final state: surface, run-out, height ----
    t_end, f_end = series.items[-1]
    final = Series.read(f_end, ["plasticStrain", "velocity", "volume"])
    x, y = final["x"][:, 0], final["x"][:, 1]
    spacing = particle_spacing(a.case, final)
    half = 0.5 * spacing
    sx, sy = surface_profile(x, y, max(2 * spacing, 0.001))
    runout = deposit_front(x, y, spacing) + half
    height = y.max() + half
    summary.update({"final_time_after_release_s": t_end - tr, "runout_m": runout, "deposit_height_m": height,
                    "paper_runout_m": PAPER_RUNOUT, "paper_height_m": PAPER_HEIGHT,
                    "runout_error": runout / PAPER_RUNOUT - 1, "height_error": height / PAPER_HEIGHT - 1})
    ro = read_csv(os.path.join(a.case, "postProcessing", "deposit", "runOut.csv"))
    ke = ro["kinetic_energy"]
    after = ro["time"] >= tr
    ke_peak = float(np.nanmax(ke[after])) if after.any() else float("nan")
    summary["kinetic_energy_peak_J_per_m"] = ke_peak
    summary["kinetic_energy_final_J_per_m"] = float(ke[-1])
    summary["kinetic_energy_final_over_peak"] = float(ke[-1] / ke_peak) if ke_peak > 0 else float("nan")
    summary.update(history_numbers(ro, tr))
    summary["particles"] = int(len(x))
    summary["snapshot_steps"] = snapshot_steps(series, tr)
    summary["end_state"] = end_state(final)

    fig, ax = plt.subplots(figsize=(7, 2.6))
    ax.fill_between([0, 0.2], [0.1, 0.1], color="0.9", label="initial column")
    ax.plot(sx, sy, "k-", lw=1.5, label="MPM, phase transition")
    ax.axvline(PAPER_RUNOUT, color="r", ls="--", lw=1, label="paper / experiment: d$_\\infty$ = 0.42 m")
    ax.axhline(PAPER_HEIGHT, color="b", ls=":", lw=1, label="h$_\\infty$ = 0.10 m")
    ax.set_xlim(0, 0.5)
    ax.set_ylim(0, 0.12)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Final free surface (t = %.2f s after release): d$_\\infty$ = %.3f m, h$_\\infty$ = %.3f m"
                 % (t_end - tr, runout, height), fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig10_free_surface.png"), dpi=150)
    plt.close(fig)

    # ---- Figs. 11-12: snapshots ----
    fields = ["plasticStrain", "shearViscosity", "granularTemperature"]
    fig11, axes11 = plt.subplots(len(SNAP_TIMES), 2, figsize=(10, 1.6 * len(SNAP_TIMES) + 0.6))
    fig12, axes12 = plt.subplots(len(SNAP_TIMES), 1, figsize=(5.5, 1.6 * len(SNAP_TIMES) + 0.6))
    for i, ts in enumerate(SNAP_TIMES):
        t, f = series.nearest(tr + ts)
        d = Series.read(f, fields)
        lab = "t = %.2f s" % (t - tr)
        s1 = scatter(axes11[i, 0], d, "plasticStrain", "equivalent plastic strain, " + lab, 0, 1.0, "jet")
        s2 = scatter(axes11[i, 1], d, "shearViscosity", "log$_{10}$ shear viscosity [Pa s], " + lab, -6, 0,
                     "jet", log=True)
        s3 = scatter(axes12[i], d, "granularTemperature", "log$_{10}$ T [m$^2$/s$^2$], " + lab, -8, -2, "jet",
                     log=True)
        if i == 0:
            for s, axs in ((s1, axes11[:, 0]), (s2, axes11[:, 1]), (s3, axes12)):
                if s is not None:
                    plt.colorbar(s, ax=list(np.atleast_1d(axs)), shrink=0.6)
    fig11.savefig(os.path.join(out, "fig11_strain_viscosity.png"), dpi=140)
    fig12.savefig(os.path.join(out, "fig12_granular_temperature.png"), dpi=140)
    plt.close(fig11)
    plt.close(fig12)

    # ---- Figs. 13-14: probes ----
    probes = read_probes(a.case)
    if probes:
        fig, axs = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
        for n, d in probes.items():
            t = d["time"] - tr
            axs[0].plot(t, d.get("collisionalFraction", np.zeros_like(t)), label="particle " + n)
            axs[1].semilogy(t, np.maximum(d.get("deviatoricStrainRate", np.zeros_like(t)), 1e-6), label=n)
        axs[0].set_ylabel("K$_{col}$ = q$_{col}$/(q$_{col}$+q$_f$)")
        axs[1].set_ylabel("deviatoric strain rate [1/s]")
        axs[1].set_xlabel("time after release [s]")
        axs[0].legend(fontsize=8)
        for ax in axs:
            ax.set_xlim(0, 1.0)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig13_probes_kcol_rate.png"), dpi=140)
        plt.close(fig)
        fig, axs = plt.subplots(1, 2, figsize=(10, 3.5))
        for ax, n in zip(axs, ("A", "B")):
            if n not in probes:
                continue
            d = probes[n]
            t = d["time"] - tr
            ax.plot(t, d.get("collisionalDeviatoricStress", np.zeros_like(t)), "b-", label="q$_{col}$ [Pa]")
            ax.set_ylabel("q$_{col}$ [Pa]", color="b")
            ax2 = ax.twinx()
            ax2.plot(t, d.get("granularTemperature", np.zeros_like(t)), "r-", label="T")
            ax2.set_ylabel("T [m$^2$/s$^2$]", color="r")
            ax.set_xlim(0, 1.0)
            ax.set_xlabel("time after release [s]")
            ax.set_title("particle " + n)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig14_probes_qcol_T.png"), dpi=140)
        plt.close(fig)
        summary["probes"] = {n: {"peak_Kcol": float(np.nanmax(d.get("collisionalFraction", [np.nan]))),
                                 "peak_T": float(np.nanmax(d.get("granularTemperature", [np.nan])))}
                             for n, d in probes.items()}

    # ---- history ----
    fig, axs = plt.subplots(3, 1, figsize=(6, 6.5), sharex=True)
    runs = [("phase transition", a.case, ro)]
    if a.frictional:
        runs.append(("frictional", a.frictional,
                     read_csv(os.path.join(a.frictional, "postProcessing", "deposit", "runOut.csv"))))
    for label, case, d in runs:
        t = d["time"] - release_time(case)
        axs[0].plot(t, d["runout"], label=label)
        axs[1].plot(t, d["height"], label=label)
        axs[2].semilogy(t, np.maximum(d["kinetic_energy"], 1e-12), label=label)
    axs[0].axhline(PAPER_RUNOUT, color="r", ls="--", lw=0.8)
    axs[1].axhline(PAPER_HEIGHT, color="r", ls="--", lw=0.8)
    axs[0].set_ylabel("front [m]")
    axs[1].set_ylabel("top [m]")
    axs[2].set_ylabel("kinetic energy [J/m]")
    axs[2].set_xlabel("time after release [s]")
    axs[0].legend(fontsize=8)
    axs[2].set_xlim(-0.02, 1.0)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "runout_history.png"), dpi=140)
    plt.close(fig)

    # ---- Figs. 15-17: comparison with the frictional model ----
    if a.frictional:
        fs = Series(a.frictional)
        trf = release_time(a.frictional)
        tf_end, ff_end = fs.items[-1]
        ffinal = Series.read(ff_end, ["plasticStrain", "velocity", "volume"])
        fx, fy = ffinal["x"][:, 0], ffinal["x"][:, 1]
        fspacing = particle_spacing(a.frictional, ffinal)  # its own (the same cells: the same)
        fhalf = 0.5 * fspacing
        fsx, fsy = surface_profile(fx, fy, max(2 * fspacing, 0.001))
        f_runout = deposit_front(fx, fy, fspacing) + fhalf
        f_height = fy.max() + fhalf
        fro = runs[1][2]
        summary["frictional"] = {"final_time_after_release_s": tf_end - trf, "runout_m": f_runout,
                                 "deposit_height_m": f_height, "runout_error": f_runout / PAPER_RUNOUT - 1,
                                 "height_error": f_height / PAPER_HEIGHT - 1, "particles": int(len(fx))}
        summary["frictional"].update(history_numbers(fro, trf))
        summary["frictional"]["snapshot_steps"] = snapshot_steps(fs, trf)
        fig, ax = plt.subplots(figsize=(7, 2.6))
        ax.fill_between([0, 0.2], [0.1, 0.1], color="0.9", label="initial column")
        ax.plot(sx, sy, "k-", label="phase transition: d$_\\infty$ = %.3f m" % runout)
        ax.plot(fsx, fsy, "r--", label="frictional only: d$_\\infty$ = %.3f m" % f_runout)
        ax.axvline(PAPER_RUNOUT, color="b", ls=":", lw=1, label="paper / experiment: d$_\\infty$ = 0.42 m")
        ax.set_title("Final free surfaces, %.2f s after release (Fig. 15)" % (t_end - tr), fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlim(0, 0.5)
        ax.set_ylim(0, 0.12)
        ax.legend(fontsize=7)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig15_surface_comparison.png"), dpi=150)
        plt.close(fig)
        fig, axs = plt.subplots(2, 1, figsize=(7, 4))
        speeds, vnum = {}, {}
        for ax, (label, ser, r) in zip(axs, (("phase transition", series, tr), ("frictional", fs, trf))):
            t, f = ser.nearest(r + 0.5)
            if abs(t - (r + 0.5)) > TOL:  # e.g. a frictional run written without it
                ax.set_title("%s: no snapshot 0.5 s after release (nearest %.2f s)" % (label, t - r), fontsize=9)
                ax.set_axis_off()
                print("column_collapse.py: %s run has no snapshot 0.5 s after the release" % label, file=sys.stderr)
                continue
            d = Series.read(f, ["velocity", "volume"])
            s = scatter(ax, d, "velocity", "%s: v$_x$ [m/s] at t = %.2f s after release" % (label, t - r),
                        0, 0.4, "jet", comp=0)
            plt.colorbar(s, ax=ax, shrink=0.8)
            x5, y5 = d["x"][:, 0], d["x"][:, 1]
            vnum[label] = velocity_numbers(d)
            vnum[label]["plateau_edge_m"] = plateau_edge(x5, y5)
            speeds[label] = vnum[label]["vx_p99"]
        summary["vx_p99_at_0.5s"] = speeds
        summary["velocity_at_0.5s"] = vnum
        summary["frictional"]["end_state"] = end_state(ffinal)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig16_velocity_x.png"), dpi=140)
        plt.close(fig)
        fig, axs = plt.subplots(2, 1, figsize=(7, 4))
        ends = (("phase transition", final, t_end - tr), ("frictional", ffinal, tf_end - trf))
        for ax, (label, d, te) in zip(axs, ends):
            s = scatter(ax, d, "plasticStrain", "%s: equivalent plastic strain, %.2f s after release"
                        % (label, te), 0, 1.0, "jet")
            plt.colorbar(s, ax=ax, shrink=0.8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig17_plastic_strain.png"), dpi=140)
        plt.close(fig)

    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()

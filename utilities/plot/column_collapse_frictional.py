#!/usr/bin/python3
"""Figures of the purely frictional column collapse (cases/columnCollapse/variants/frictional*)
on its own, from the run's own output, with column_collapse.py's definitions.

    column_collapse_frictional.py CASE [-o OUTDIR] [--pt-summary SUMMARY_JSON]

column_collapse.py expects a phaseTransition run as its main case (stress snapshot at the
release, granular temperature, shear viscosity, K_col probes); a frictional run written
with fewer snapshots (e.g. scripts/gpu-column.sh: 0.5 and 1 s after the release only) gives
meaningless figures there. This script draws only what a frictional run has, with the
same functions (Series, deposit_front, surface_profile, particle_spacing, scatter) and the
same run-out and height definitions (furthest particle of the continuous deposit plus half
a particle spacing; highest particle plus half a spacing). Writes to OUTDIR:

  fig10_free_surface.png      final free surface, with the paper's d_inf and h_inf (and the
                              phase-transition run-out from --pt-summary, if given)
  runout_history.png          front, top and kinetic energy over time (postProcessing/deposit)
  fig16_velocity_x_0.5s.png   v_x 0.5 s after the release
  fig17_plastic_strain.png    equivalent plastic strain at the snapshots 0.05, 0.25, 0.5, 1 s
                              after the release that the run wrote
  summary.json                run-out, height, kinetic energy peak and at 0.5 s and 1 s after
                              the release, 99th percentile of |v_x| at 0.5 s (as
                              column_collapse.py's vx_p99_at_0.5s)

Run with Debian's /usr/bin/python3 (python3-vtk9, python3-matplotlib, python3-numpy).
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import column_collapse as cc  # noqa: E402

plt = cc.plt
np = cc.np

TOL = 1e-3  # s: a snapshot counts as "at" a time when it is this close


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", help="a finished run of a frictional variant")
    ap.add_argument("-o", "--outdir", default=None)
    ap.add_argument("--pt-summary", help="summary.json of column_collapse.py for the phase-transition run "
                    "at the same resolution: its run-out is drawn on the surface figure")
    a = ap.parse_args()
    out = a.outdir or os.path.join(a.case, "figures")
    os.makedirs(out, exist_ok=True)
    tr = cc.release_time(a.case)
    series = cc.Series(a.case)
    summary = {"release_time_s": tr, "snapshot_times_after_release_s": [t - tr for t, _ in series.items]}

    # ---- final state: run-out and height as in column_collapse.py ----
    t_end, f_end = series.items[-1]
    final = cc.Series.read(f_end, ["plasticStrain", "velocity", "volume"])
    x, y = final["x"][:, 0], final["x"][:, 1]
    spacing = cc.particle_spacing(a.case, final)
    half = 0.5 * spacing
    sx, sy = cc.surface_profile(x, y, max(2 * spacing, 0.001))
    runout = cc.deposit_front(x, y, spacing) + half
    height = y.max() + half
    summary.update({"final_time_after_release_s": t_end - tr, "particles": int(len(x)),
                    "particle_spacing_m": spacing, "runout_m": runout, "deposit_height_m": height,
                    "paper_runout_m": cc.PAPER_RUNOUT, "paper_height_m": cc.PAPER_HEIGHT,
                    "runout_error": runout / cc.PAPER_RUNOUT - 1, "height_error": height / cc.PAPER_HEIGHT - 1})

    # ---- the run-out tracker's history (postProcessing/deposit/runOut.csv) ----
    ro = cc.read_csv(os.path.join(a.case, "postProcessing", "deposit", "runOut.csv"))
    t_ro = ro["time"]
    ke = ro["kinetic_energy"]
    after = t_ro >= tr
    i_peak = int(np.nanargmax(np.where(after, ke, -np.inf)))
    ke_peak = float(ke[i_peak])
    summary["kinetic_energy_peak_J_per_m"] = ke_peak
    summary["kinetic_energy_peak_time_after_release_s"] = float(t_ro[i_peak] - tr)
    for ts in (0.5, 1.0):
        j = int(np.argmin(np.abs(t_ro - (tr + ts))))
        key = "%gs" % ts
        summary["kinetic_energy_at_%s_J_per_m" % key] = float(ke[j])
        summary["kinetic_energy_at_%s_over_peak" % key] = float(ke[j] / ke_peak)
        summary["max_speed_at_%s_m_per_s" % key] = float(ro["max_speed"][j])
        summary["tracker_front_at_%s_m" % key] = float(ro["runout"][j])  # furthest particle centre
        summary["tracker_height_at_%s_m" % key] = float(ro["height"][j])  # highest particle centre

    pt = None
    if a.pt_summary:
        with open(a.pt_summary) as f:
            pt = json.load(f)

    fig, ax = plt.subplots(figsize=(7, 2.6))
    ax.fill_between([0, 0.2], [0.1, 0.1], color="0.9", label="initial column")
    ax.plot(sx, sy, "r-", lw=1.5, label="MPM, frictional (SIMSAND alone)")
    ax.axvline(cc.PAPER_RUNOUT, color="r", ls="--", lw=1, label="paper / experiment: d$_\\infty$ = 0.42 m")
    if pt is not None:
        ax.axvline(pt["runout_m"], color="k", ls="-.", lw=1,
                   label="phase transition, same cells: d$_\\infty$ = %.3f m" % pt["runout_m"])
    ax.axhline(cc.PAPER_HEIGHT, color="b", ls=":", lw=1, label="h$_\\infty$ = 0.10 m")
    ax.set_xlim(0, 0.5)
    ax.set_ylim(0, 0.12)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Frictional, final free surface (t = %.2f s after release): d$_\\infty$ = %.3f m, "
                 "h$_\\infty$ = %.3f m" % (t_end - tr, runout, height), fontsize=9)
    ax.legend(fontsize=6.5, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig10_free_surface.png"), dpi=150)
    plt.close(fig)

    fig, axs = plt.subplots(3, 1, figsize=(6, 6.5), sharex=True)
    t = t_ro - tr
    axs[0].plot(t, ro["runout"], "r-", label="frictional (furthest particle)")
    axs[1].plot(t, ro["height"], "r-")
    axs[2].semilogy(t, np.maximum(ke, 1e-12), "r-")
    axs[0].axhline(cc.PAPER_RUNOUT, color="k", ls="--", lw=0.8, label="paper / experiment")
    axs[1].axhline(cc.PAPER_HEIGHT, color="k", ls="--", lw=0.8)
    axs[0].set_ylabel("front [m]")
    axs[1].set_ylabel("top [m]")
    axs[2].set_ylabel("kinetic energy [J/m]")
    axs[2].set_xlabel("time after release [s]")
    axs[0].legend(fontsize=8)
    axs[2].set_xlim(-0.02, 1.0)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "runout_history.png"), dpi=140)
    plt.close(fig)

    # ---- v_x 0.5 s after the release (the statistic of column_collapse.py's Fig. 16) ----
    t5, f5 = series.nearest(tr + 0.5)
    if abs(t5 - (tr + 0.5)) <= TOL:
        d = cc.Series.read(f5, ["velocity"])
        vx = d["velocity"][:, 0]
        summary["vx_p99_at_0.5s"] = float(np.percentile(np.abs(vx), 99))
        summary["vx_max_at_0.5s"] = float(vx.max())
        summary["fraction_of_particles_speed_above_0.1_at_0.5s"] = float(
            np.mean(np.linalg.norm(d["velocity"], axis=1) > 0.1))
        fig, ax = plt.subplots(figsize=(7, 2.2))
        s = cc.scatter(ax, d, "velocity", "frictional: v$_x$ [m/s] at t = %.2f s" % (t5 - tr), 0, 0.4, "jet", comp=0)
        plt.colorbar(s, ax=ax, shrink=0.8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig16_velocity_x_0.5s.png"), dpi=140)
        plt.close(fig)
    else:
        print("column_collapse_frictional.py: no snapshot 0.5 s after the release (nearest %.3f s): "
              "no v_x figure" % (t5 - tr), file=sys.stderr)

    # ---- plastic strain at the snapshots the run wrote ----
    shown = []
    for ts in cc.SNAP_TIMES:
        t, f = series.nearest(tr + ts)
        if abs(t - (tr + ts)) <= TOL and f not in [g for _, g in shown]:
            shown.append((t, f))
    if shown:
        fig, axs = plt.subplots(len(shown), 1, figsize=(7, 2.0 * len(shown)), squeeze=False)
        for ax, (t, f) in zip(axs[:, 0], shown):
            d = cc.Series.read(f, ["plasticStrain"])
            s = cc.scatter(ax, d, "plasticStrain", "frictional: equivalent plastic strain, t = %.2f s" % (t - tr),
                           0, 1.0, "jet")
            plt.colorbar(s, ax=ax, shrink=0.8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "fig17_plastic_strain.png"), dpi=140)
        plt.close(fig)

    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()

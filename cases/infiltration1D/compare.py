#!/usr/bin/python3
"""Pore-pressure profiles of the two-phase MPM (scree) against the 1D Richards reference
(scree-richards) for the four readings of the seed's 1D infiltration.

    compare.py WORK_DIR [FIGURE.png]

WORK_DIR/<variant>/mpm/VTK/particles.pvd and WORK_DIR/<variant>/<reference>/profiles.csv, as
run-comparison.sh leaves them, for three references: `richards` (rigid skeleton),
`richards_skeleton` (the MPM's skeleton, E_oed, with the water's weight) and
`richards_skeleton_noload` (without it). Writes WORK_DIR/comparison.csv: per variant, time
and reference the largest |p_w(MPM) - p_w(Richards)| over the points, in kPa and in % of the
suction range rho_w g H = 10.3 kPa (the tolerance we state: 5%), and WORK_DIR/storage.csv:
the stored water gained since t = 0 [mm] (MPM: sum of n S V (1 + p_w/K_l) over the points per
unit width, the water at the reference density as the references count it;
references: surface.csv's storage) and the rise of the surface [mm] (MPM: the top point's
displacement; references: the integral of the swelling -eps up to that point's initial
elevation). The rigid reference is read at
the MPM point's elevation y, the deformable ones at its initial elevation y - u_y (they
solve in the solid's reference coordinate). Needs python3-vtk9, numpy, matplotlib.
"""

import csv
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

READINGS = ["kappa_ponding", "kappa_rain", "Ksat2e-4_ponding", "Ksat2e-4_rain"]
SKELETONS = ["rigid", "seed"]  # E = 500 MPa (the Richards reference's rigid skeleton), Table A's 5 MPa
VARIANTS = ["%s_%s" % (r, k) for k in SKELETONS for r in READINGS]
RANGE = 1000 * 9.81 * 1.05  # [Pa] the suction range of the column


REFS = [("richards", "rigid"), ("richards_skeleton", "skeleton"), ("richards_skeleton_noload", "skel_noload")]
WIDTH = 0.025  # [m] the MPM column's width (constant/bodies)


def liquid_bulk_modulus(d):
    # constant/bodies: "liquidBulkModulus <K_l>;"
    for line in open(os.path.join(d, "constant", "bodies")):
        w = line.split("//")[0].split()
        if len(w) >= 2 and w[0] == "liquidBulkModulus":
            return float(w[1].rstrip(";"))
    raise SystemExit("no liquidBulkModulus in %s/constant/bodies" % d)


def mpm_series(d):
    K_l = liquid_bulk_modulus(d)
    pvd = os.path.join(d, "VTK", "particles.pvd")
    out = []
    for ds in ET.parse(pvd).getroot().iter("DataSet"):
        r = vtk.vtkXMLPolyDataReader()
        r.SetFileName(os.path.join(d, "VTK", ds.get("file")))
        r.Update()
        o = r.GetOutput()
        pd = o.GetPointData()
        y = vtk_to_numpy(o.GetPoints().GetData())[:, 1]
        p = vtk_to_numpy(pd.GetArray("porePressure"))
        S = vtk_to_numpy(pd.GetArray("saturation"))
        n = vtk_to_numpy(pd.GetArray("porosity"))
        V = vtk_to_numpy(pd.GetArray("volume"))
        uy = vtk_to_numpy(pd.GetArray("displacement"))[:, 1]
        # [m] per unit area, at the reference density rho_l (1 + p/K_l) as the references' storage
        water = float(np.sum(n * S * V * (1 + p / K_l))) / WIDTH
        top = np.argmax(y)
        rise = float(uy[top])
        out.append((float(ds.get("timestep")), y, p, S, water, rise, y - uy, float(y[top] - uy[top])))
    return out


def richards(path):
    prof = {}
    with open(os.path.join(path, "profiles.csv")) as f:
        rows = [l for l in f if not l.startswith("#")]
    for row in csv.DictReader(rows):
        prof.setdefault(float(row["time"]), []).append(
            (float(row["z"]), float(row["p_w"]), float(row["S"]), float(row.get("eps", 0.0))))
    prof = {t: np.array(sorted(v)) for t, v in prof.items()}
    with open(os.path.join(path, "surface.csv")) as f:
        rows = [l for l in f if not l.startswith("#")]
    hist = np.array([(float(r["time"]), float(r["storage"])) for r in csv.DictReader(rows)])
    return prof, hist


def main():
    work = sys.argv[1]
    fig_path = sys.argv[2] if len(sys.argv) > 2 else None
    table = []
    storage = []
    panels = []
    for v in VARIANTS:
        d = os.path.join(work, v)
        if not os.path.isdir(d):
            continue
        series = mpm_series(os.path.join(d, "mpm"))
        refs = {k: richards(os.path.join(d, sub)) for sub, k in REFS if os.path.isdir(os.path.join(d, sub))}
        water0 = series[0][4]
        shown = []
        for t, y, p, S, water, rise, Y, Ytop in series:
            if t == 0:
                continue
            row_s = [v, t, 1e3 * (water - water0), 1e3 * rise]
            errs = {}
            for _, k in REFS:
                if k not in refs:
                    row_s += [float("nan"), float("nan")]
                    continue
                prof, hist = refs[k]
                tr = min(prof, key=lambda x: abs(x - t))
                if abs(tr - t) > 1e-6:
                    row_s += [float("nan"), float("nan")]
                    continue
                z, pr, eps = prof[tr][:, 0], prof[tr][:, 1], prof[tr][:, 3]
                # The rigid reference at the point's elevation y (the rigid column does not move);
                # the deformable ones at its initial elevation Y = y - u_y: they solve in the
                # solid's reference coordinate (utilities/richards1d/README.md, skeleton).
                err = np.abs(p - np.interp(y if k == "rigid" else Y, z, pr))
                errs[k] = (err.max() / 1e3, 100 * err.max() / RANGE, 100 * np.mean(err) / RANGE)
                table.append((v, t, k) + errs[k])
                # the rise of the top point (initial elevation Ytop), as the MPM's is measured
                zz = np.append(z[z < Ytop], Ytop)
                ee = np.interp(zz, z, eps)
                swell = -np.sum(0.5 * (ee[1:] + ee[:-1]) * np.diff(zz))
                row_s += [1e3 * (np.interp(t, hist[:, 0], hist[:, 1]) - hist[0, 1]), 1e3 * swell]
            storage.append(row_s)
            shown.append((t, y, p, {k: (refs[k][0][t][:, 0], refs[k][0][t][:, 1]) for k in errs}))
        panels.append((v, shown))
    out = os.path.join(work, "comparison.csv")
    with open(out, "w") as f:
        f.write("variant,time_s,reference,max_abs_err_kPa,max_err_pct_of_range,mean_err_pct_of_range\n")
        for r in table:
            f.write("%s,%g,%s,%.4f,%.3f,%.3f\n" % r)
    with open(os.path.join(work, "storage.csv"), "w") as f:
        f.write("variant,time_s,mpm_water_gained_mm,mpm_rise_mm," +
                ",".join("%s_water_gained_mm,%s_rise_mm" % (k, k) for _, k in REFS) + "\n")
        for r in storage:
            f.write("%s,%g," % tuple(r[:2]) + ",".join("%.5f" % x for x in r[2:]) + "\n")
    print("largest |p_w(MPM) - p_w(Richards)| in % of rho g H (mean in brackets), per reference:")
    print("%-24s %6s  %16s  %16s  %16s" % ("variant", "t [s]", "rigid", "skeleton", "skeleton, no load"))
    by = {}
    for v, t, k, _, mx, mn in table:
        by.setdefault((v, t), {})[k] = "%6.2f%% (%5.2f%%)" % (mx, mn)
    for (v, t), e in by.items():
        print("%-24s %6g  %16s  %16s  %16s" % (v, t, e.get("rigid", "-"), e.get("skeleton", "-"),
                                             e.get("skel_noload", "-")))
    print("water gained [mm] and surface rise [mm]: MPM | rigid | skeleton | skeleton, no load")
    for r in storage:
        print("%-24s %6g  %7.3f %6.3f | %7.3f %6.3f | %7.3f %6.3f | %7.3f %6.3f" % tuple(r))
    if fig_path:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rows = max(1, (len(panels) + 3) // 4)
        fig, axes = plt.subplots(rows, min(4, len(panels)), figsize=(16, 5 * rows), sharey=True, squeeze=False)
        axes = axes.ravel()
        for ax, (v, shown) in zip(axes, panels):
            for k, (t, y, p, ref) in enumerate(shown[:: max(1, len(shown) // 5)]):
                c = "C%d" % k
                if "skeleton" in ref:
                    z, pr = ref["skeleton"]
                    ax.plot(pr / 1e3, z, "-", color=c, label="%g s" % t)
                if "rigid" in ref:
                    z, pr = ref["rigid"]
                    ax.plot(pr / 1e3, z, ":", color=c, lw=1, label=None if "skeleton" in ref else "%g s" % t)
                o = np.argsort(y)
                ax.plot(p[o][::2] / 1e3, y[o][::2], "o", mfc="none", color=c, ms=4)
            ax.set_title(v)
            ax.set_xlabel("p_w [kPa]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        for ax in axes[::4]:
            ax.set_ylabel("z [m]")
        fig.suptitle("infiltration1D: MPM (circles) against the Richards reference with the MPM's skeleton "
                     "(E_oed, solid lines) and with a rigid skeleton (dotted)")
        fig.tight_layout()
        fig.savefig(fig_path, dpi=110)
        print("wrote", fig_path)


if __name__ == "__main__":
    main()

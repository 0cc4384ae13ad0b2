#!/usr/bin/python3
"""Pore-pressure profiles of the two-phase MPM (scree) against the 1D Richards reference
(scree-richards) for the four readings of the seed's 1D infiltration.

    compare.py WORK_DIR [FIGURE.png]

WORK_DIR/<variant>/mpm/VTK/particles.pvd and WORK_DIR/<variant>/richards/profiles.csv, as
run-comparison.sh leaves them. Writes WORK_DIR/comparison.csv: per variant and time the
largest |p_w(MPM) - p_w(Richards)| over the points, in kPa and in % of the suction range
rho_w g H = 10.3 kPa (the tolerance we state: 5%). Needs python3-vtk9, numpy, matplotlib.
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


def mpm_series(d):
    pvd = os.path.join(d, "VTK", "particles.pvd")
    out = []
    for ds in ET.parse(pvd).getroot().iter("DataSet"):
        r = vtk.vtkXMLPolyDataReader()
        r.SetFileName(os.path.join(d, "VTK", ds.get("file")))
        r.Update()
        o = r.GetOutput()
        y = vtk_to_numpy(o.GetPoints().GetData())[:, 1]
        p = vtk_to_numpy(o.GetPointData().GetArray("porePressure"))
        S = vtk_to_numpy(o.GetPointData().GetArray("saturation"))
        out.append((float(ds.get("timestep")), y, p, S))
    return out


def richards(path):
    prof = {}
    with open(path) as f:
        rows = [l for l in f if not l.startswith("#")]
    for row in csv.DictReader(rows):
        prof.setdefault(float(row["time"]), []).append((float(row["z"]), float(row["p_w"]), float(row["S"])))
    return {t: np.array(sorted(v)) for t, v in prof.items()}


def main():
    work = sys.argv[1]
    fig_path = sys.argv[2] if len(sys.argv) > 2 else None
    table = []
    panels = []
    for v in VARIANTS:
        d = os.path.join(work, v)
        if not os.path.isdir(d):
            continue
        series = mpm_series(os.path.join(d, "mpm"))
        ref = richards(os.path.join(d, "richards", "profiles.csv"))
        shown = []
        for t, y, p, S in series:
            tr = min(ref, key=lambda x: abs(x - t)) if ref else None
            if tr is None or abs(tr - t) > 1e-6 or t == 0:
                continue
            z, pr, Sr = ref[tr][:, 0], ref[tr][:, 1], ref[tr][:, 2]
            err = np.abs(p - np.interp(y, z, pr))
            table.append((v, t, err.max() / 1e3, 100 * err.max() / RANGE, 100 * np.mean(err) / RANGE))
            shown.append((t, y, p, z, pr))
        panels.append((v, shown))
    out = os.path.join(work, "comparison.csv")
    with open(out, "w") as f:
        f.write("variant,time_s,max_abs_err_kPa,max_err_pct_of_range,mean_err_pct_of_range\n")
        for r in table:
            f.write("%s,%g,%.4f,%.3f,%.3f\n" % r)
    for r in table:
        print("%-24s t = %5g s   max |dp| = %7.3f kPa = %6.2f%%  (mean %5.2f%%) of rho g H" % r)
    if fig_path:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rows = max(1, (len(panels) + 3) // 4)
        fig, axes = plt.subplots(rows, min(4, len(panels)), figsize=(16, 5 * rows), sharey=True, squeeze=False)
        axes = axes.ravel()
        for ax, (v, shown) in zip(axes, panels):
            for k, (t, y, p, z, pr) in enumerate(shown[:: max(1, len(shown) // 5)]):
                c = "C%d" % k
                ax.plot(pr / 1e3, z, "-", color=c, label="%g s" % t)
                o = np.argsort(y)
                ax.plot(p[o][::2] / 1e3, y[o][::2], "o", mfc="none", color=c, ms=4)
            ax.set_title(v)
            ax.set_xlabel("p_w [kPa]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        for ax in axes[::4]:
            ax.set_ylabel("z [m]")
        fig.suptitle("infiltration1D: MPM (circles) against the Richards reference (lines)")
        fig.tight_layout()
        fig.savefig(fig_path, dpi=110)
        print("wrote", fig_path)


if __name__ == "__main__":
    main()

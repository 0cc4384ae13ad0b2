#!/usr/bin/python3
"""Numbers read back from the column-collapse figures of a run whose raw output is gone
(the phase-transition 1 mm run of cases/columnCollapse/figures), each reading checked
on the frictional 1 mm run, whose raw output exists and gives the true value.

    column_collapse_read_pictures.py [--pt cases/columnCollapse/figures]
        [--frictional cases/columnCollapse/figures/frictional-1mm]
        [--frictional-case cases/columnCollapse/variants/frictional]

1. Kinetic energy 0.5 s after the release, read off runout_history.png (bottom panel, log
   axis): the axis is calibrated on the curve itself, at its peak and at its last point,
   whose values are in the folder's summary.json (kinetic_energy_peak_J_per_m,
   kinetic_energy_final_J_per_m); time from the x axis (-0.02 .. 1.0 s, the last point is
   1.0 s).
2. v_x 0.5 s after the release, read off paraview_vx_0.5s.png (utilities/render/
   paraview_snapshot.py, Jet colours, range 0-0.4 m/s, colour bar at the bottom right):
   every drawn pixel is given the value of the nearest colour of the picture's own colour
   bar; prints the 99th percentile over the drawn area and the area above 0.1, 0.2, 0.3 m/s.
   A percentile over drawn pixels is not one over particles (discs overlap, the thin fast
   layer shows gaps): compare the two models' readings with each other, and look at the
   frictional check line for how far a reading is from the particles' value.

Needs /usr/bin/python3 with matplotlib and numpy (and vtk for the frictional check).
"""

import argparse
import json
import os
import sys

import matplotlib.image as mpimg
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import column_collapse as cc  # noqa: E402

# runout_history.png of column_collapse.py / column_collapse_frictional.py (figsize 6 x 6.5,
# dpi 140): the lower panel starts below this fraction of the height.
LOWER_PANEL = 0.62


def curve_pixels(png, colour):
    """Columns and centre rows of a line of `colour` (RGB 0-1) in the lower panel."""
    im = mpimg.imread(png)[:, :, :3]
    rows = np.arange(im.shape[0])
    low = rows > int(LOWER_PANEL * im.shape[0])
    near = np.all(np.abs(im - np.asarray(colour)) < 0.12, axis=2) & low[:, None]
    cols = np.where(near.any(0))[0]
    mid = np.array([rows[near[:, c]].mean() for c in cols])
    return cols, mid


def ke_at(png, colour, ke_peak, ke_end, t_query):
    cols, mid = curve_pixels(png, colour)
    t = -0.02 + (cols - cols.min()) / (cols.max() - cols.min()) * 1.02  # xlim (-0.02, 1.0)
    flowing = t > 0.02
    i_peak = np.argmin(np.where(flowing, mid, np.inf))  # highest point = peak
    r_peak, r_end = mid[i_peak], mid[-1]
    lp, le = np.log10(ke_peak), np.log10(ke_end)
    j = np.argmin(np.abs(t - t_query))
    return 10 ** (lp + (mid[j] - r_peak) / (r_end - r_peak) * (le - lp)), t[i_peak]


def vx_reading(png, vmax=0.4):
    im = mpimg.imread(png)[:, :, :3]
    bg = im[5, 5]
    drawn = np.any(np.abs(im - bg) > 0.08, axis=2)
    # the colour bar: the bottom-right block of columns fully drawn over > 100 rows
    h, w = drawn.shape
    box = drawn[int(0.55 * h):, int(0.9 * w):]
    bar_cols = np.where(box.sum(0) > 100)[0]
    c = int(0.9 * w) + bar_cols[len(bar_cols) // 2]
    bar_rows = np.where(box[:, bar_cols].all(1))[0] + int(0.55 * h)
    bar = im[bar_rows.min():bar_rows.max() + 1, c]
    vals = np.linspace(vmax, 0.0, len(bar))  # top of the bar = vmax
    dep = drawn.copy()
    dep[:, int(0.9 * w):] = False  # the deposit is left of the colour bar
    px = im[dep]
    idx = np.argmin(((px[:, None, :] - bar[None, :, :]) ** 2).sum(2), axis=1)
    v = vals[idx]
    # metres per pixel: the deposit's height is 0.1 m (the column's top at the wall)
    r = np.where(dep.any(1))[0]
    m_per_px = 0.1 / (r.max() - r.min())
    out = {"p99": float(np.percentile(v, 99)), "m_per_px": m_per_px}
    for th in (0.1, 0.2, 0.3):
        out["area_above_%.1f_m2" % th] = float((v > th).sum() * m_per_px ** 2)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pt", default="cases/columnCollapse/figures")
    ap.add_argument("--frictional", default="cases/columnCollapse/figures/frictional-1mm")
    ap.add_argument("--frictional-case", default="cases/columnCollapse/variants/frictional")
    a = ap.parse_args()
    res = {}
    blue, red = (31 / 255, 119 / 255, 180 / 255), (1.0, 0.0, 0.0)
    for name, folder, colour in (("phase transition", a.pt, blue), ("frictional", a.frictional, red)):
        s = json.load(open(os.path.join(folder, "summary.json")))
        end = s.get("kinetic_energy_final_J_per_m", s.get("kinetic_energy_at_1s_J_per_m"))
        ke5, t_peak = ke_at(os.path.join(folder, "runout_history.png"), colour,
                            s["kinetic_energy_peak_J_per_m"], end, 0.5)
        res[name] = {"ke_0.5s_read_J_per_m": ke5, "ke_0.5s_read_over_peak": ke5 / s["kinetic_energy_peak_J_per_m"],
                     "vx_0.5s_picture": vx_reading(os.path.join(folder, "paraview_vx_0.5s.png"))}
        if "kinetic_energy_at_0.5s_J_per_m" in s:
            res[name]["ke_0.5s_true_J_per_m"] = s["kinetic_energy_at_0.5s_J_per_m"]
    if os.path.isdir(os.path.join(a.frictional_case, "VTK")):
        series = cc.Series(a.frictional_case)
        tr = cc.release_time(a.frictional_case)
        t, f = series.nearest(tr + 0.5)
        d = cc.Series.read(f, ["velocity", "volume"])
        vx, area = d["velocity"][:, 0], float(np.median(d["volume"]))
        true = {"p99": float(np.percentile(np.abs(vx), 99))}
        for th in (0.1, 0.2, 0.3):
            true["area_above_%.1f_m2" % th] = float((vx > th).sum() * area)
        res["frictional"]["vx_0.5s_particles"] = true
    print(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()

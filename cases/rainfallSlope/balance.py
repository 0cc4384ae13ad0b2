#!/usr/bin/python3
"""The whole slope's water balance, from the VTK series and the waterBalance function object.

The case is 20 two-phase bodies (the strips of makeBodies.py), and the waterBalance function
object cannot sum them: the solver hands the case's liquid inflow totals
(liquidInflowSurface, liquidInflowPrescribed) only to the first two-phase body's snapshot, and
waterBalance stops when any selected body lacks them. So `water` in system/controlDict is
restricted to strip00: its inflow columns are the whole case's, its stored-mass column is
strip00's alone (and so is its balanceError: ignore it). This script takes the stored liquid
mass of every point from the VTK files, with the function object's formula
W = sum rho_l (1 + p_w / K_l) n S_l V, and the inflows from the function object's rows at the
same times, and prints the balance of the whole slope.

    /usr/bin/python3 cases/rainfallSlope/balance.py [CASE]   (default: this directory)
"""
import csv
import glob
import os
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

RHO_L = 1000.0   # constant/soilProperties: liquidDensity
K_L = 2e7        # liquidBulkModulus


def series(case):
    files = glob.glob(os.path.join(case, "VTK", "particles_*.vtp"))
    return sorted(files, key=lambda f: int(f.rsplit("_", 1)[1][:-4]))


def stored(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    o = r.GetOutput()
    a = lambda n: vtk_to_numpy(o.GetPointData().GetArray(n))
    t = float(vtk_to_numpy(o.GetFieldData().GetArray("TimeValue"))[0])
    w = np.sum(RHO_L * (1 + a("porePressure") / K_L) * a("porosity") * a("saturation") * a("volume"))
    return t, w


def main():
    case = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(case, "postProcessing", "water", "waterBalance.csv")) as f:
        rows = [[float(c) for c in r] for r in list(csv.reader(f))[1:]]
    fo = np.array(rows)
    print("time [s],stored [kg/m],storedChange [kg/m],inflowSurface [kg/m],inflowPrescribed [kg/m],"
          "balanceError [kg/m],relativeError [-]")
    w0 = None
    for path in series(case):
        t, w = stored(path)
        i = int(np.argmin(np.abs(fo[:, 0] - t)))
        if abs(fo[i, 0] - t) > 1e-6 * max(1.0, t):
            continue  # no function-object row at this write time
        if w0 is None:
            w0, s0, p0 = w, fo[i, 3], fo[i, 4]
        dw, si, pi = w - w0, fo[i, 3] - s0, fo[i, 4] - p0
        err = dw - si - pi
        rel = err / max(abs(dw), abs(si + pi), 1e-12 * abs(w))
        print(f"{t:.6g},{w:.6f},{dw:.6f},{si:.6f},{pi:.6f},{err:.6f},{rel:.4f}")


if __name__ == "__main__":
    main()

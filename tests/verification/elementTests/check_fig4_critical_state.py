#!/usr/bin/env python3
"""Fig. 4 of Feng et al. (2025) as the case runs it: SIMSAND (Table 1) in undrained simple
shear from sigma_v = 400 kPa, K0 = 0.5. At constant volume the void ratio stays e0, so the
critical state the case claims the samples reach is the pressure at which e0 is the critical
void ratio of eq. (16), e_c = e_ref exp(-lambda (p/p_at)^xi):

    p_cs(e0) = p_at (ln(e_ref / e0) / lambda)^(1/xi)

with Table 1's e_ref = 0.937, lambda = 0.022, xi = 0.71, p_at = 101.3 kPa, written here
from the paper, not read from the code: 1.629 MPa (e0 = 0.80), 824 kPa (0.85), 237 kPa
(0.90). e0 = 0.95 > e_ref has no critical state with p > 0: the sample liquefies.

Checked on the last row of each run, at the case's own final strain:
  - e0 = 0.80, 0.85, 0.90: |p / p_cs - 1| < 1%. The samples approach the line
    asymptotically, the gap closing about as 1/gamma (measured: -1.79, -2.90, -7.09% at the
    shear strain of 0.5 the case was run to before; -0.17, -0.28, -0.68% at 5): the case
    runs to gamma = 5, where the slowest is within 1% with a margin of 1.5;
  - e0 = 0.95: p and tau below 1e-3 of p0 (267 kPa).
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile

E_REF, LAMBDA, XI, P_AT = 0.937, 0.022, 0.71, 101.3e3
P0 = (400e3 + 2 * 0.5 * 400e3) / 3


def last_row(path):
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    head = rows[0]
    return {k: float(v) for k, v in zip(head, rows[-1])}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--element", required=True)
    ap.add_argument("--case", required=True)
    a = ap.parse_args()
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        case = os.path.join(tmp, "fig4")
        shutil.copytree(a.case, case, ignore=shutil.ignore_patterns("output", "*.png"))
        for e0 in ("0.80", "0.85", "0.90", "0.95"):
            out = os.path.join(tmp, f"{e0}.csv")
            subprocess.run([a.element, f"e0_{e0}", "-o", out], cwd=case, check=True, stdout=subprocess.DEVNULL)
            r = last_row(out)
            e = float(e0)
            if e < E_REF:
                p_cs = P_AT * (math.log(E_REF / e) / LAMBDA) ** (1 / XI)
                gap = r["p"] / p_cs - 1
                ok = abs(gap) < 0.01
                print(f"e0 = {e0}: at shear strain {r['shear_strain']:g}, p = {r['p']:.0f} Pa against "
                      f"p_cs = {p_cs:.0f} Pa ({100 * gap:+.2f}%), tau/sigma_v = {r['tau'] / r['sigma_v']:.4f}")
            else:
                ok = r["p"] < 1e-3 * P0 and abs(r["tau"]) < 1e-3 * P0
                print(f"e0 = {e0} > e_ref: at shear strain {r['shear_strain']:g}, p = {r['p']:.3g} Pa, "
                      f"tau = {r['tau']:.3g} Pa (liquefied: below {1e-3 * P0:.0f} Pa)")
            if not ok:
                failures.append(e0)
    if failures:
        print("FAILED: " + ", ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Which particles set the adaptive time step of a column-collapse run, from its snapshots.

    column_collapse_time_step.py CASE [-o SUMMARY_JSON]

CASE is a finished phaseTransition run of cases/columnCollapse (adjustTimeStep, maxCo in
system/controlDict). For every snapshot the script recomputes, per particle, the speed the
solver's step control uses (framework: dt = maxCo h / max(c + |v|)), with the material's
wave_speed (materials/phaseTransition/PhaseTransition.hpp):

  c = SIMSAND p-wave speed sqrt(K (1 + 4/3 G/K) / rho)   (K of eq. 13 at the frictional pressure)
    + sound speed of the granular gas (kt::sound_speed)
    + viscous speed 2 (4/3 eta + gamma) / (rho h)        (kt::viscous_speed)

rho = mass/volume of the particle, solid fraction V = rho / rho_p, e = 1/V - 1 (a point below
the material's minSolidFraction is dispersed: no wave, only |v| counts); eta is
the snapshot's shearViscosity, gamma = eta gamma*/eta* (the kinetic-theory coefficients of
materials/common/include/scree/materials/kinetic_theory.hpp at V, clamped as there), T the snapshot's
granularTemperature, p the snapshot's pressure less the collisional one. Parameters are
read from the case's phaseTransition material (constant/materialProperties). The snapshots
are single precision and a step sees the state of that step only, so the result is an
estimate of the step at the snapshot's instant; the mean step between snapshots comes from
their step numbers (field data "step").

Prints, and writes as JSON with -o: per snapshot the estimated step and what sets it
(viscous, elastic), the step the rest of the particles would allow, and the loose particles
(V < 0.1, i.e. more than 5 times their initial volume): how many, where they are, where
they started (position less displacement), their volume ratio and granular temperature.

Run with Debian's /usr/bin/python3 (python3-vtk9, python3-numpy).
"""

import argparse
import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import column_collapse as cc  # noqa: E402

LOOSE_V = 0.1  # solid fraction below which a particle counts as loose


def material(case):
    """Parameters of the case's phaseTransition material (first one found)."""
    text = open(os.path.join(case, "constant", "materialProperties")).read()
    text = re.sub(r"//[^\n]*", "", text)
    for m in re.finditer(r"(\w+)\s*\{([^{}]*)\}", text):
        body = m.group(2)
        if re.search(r"\btype\s+phaseTransition\s*;", body):
            return {k: float(v) for k, v in re.findall(r"(\w+)\s+([-+0-9.eE]+)\s*;", body)}
    sys.exit("column_collapse_time_step.py: no phaseTransition material in %s" % case)


def control(case, key, default, name="controlDict"):
    text = open(os.path.join(case, "system", name)).read()
    m = re.search(r"\b" + key + r"\s+([-+0-9.eE]+)\s*;", text)
    return float(m.group(1)) if m else default


class KineticTheory:
    """The coefficients of kinetic_theory.hpp that the speeds need (vectorised)."""

    def __init__(self, p):
        self.rho_p = p["particleDensity"]
        self.d = p["diameter"]
        self.Vsd = 1 / (1 + p["voidRatioSd"]) if "voidRatioSd" in p else p["solidFractionSd"]
        self.Vm = p.get("solidFractionM", 0.4)
        e = p["restitutionCoefficient"] - 1.5 * p.get("particleFriction", 0.0) * np.exp(-3 * p.get("particleFriction", 0.0))
        self.eps = min(max(e, 0.0), 1 - 1e-9)  # eq. (24)
        g0max = p.get("maxRadialDistribution", 1000.0)
        v = self.Vsd - 2 / g0max
        self.Vcap = v if v > self.Vm else 0.5 * (self.Vm + self.Vsd)
        # minSolidFraction, default 1e-3 (materials/common/include/scree/materials/dispersed.hpp):
        # the solid fraction the coefficients are clamped at, below which a point is dispersed
        self.Vmin = p.get("minSolidFraction", 1e-3)

    def g0(self, V):  # eqs. (25)-(26)
        cs = (2 - V) / (2 * (1 - V) ** 3)
        f = (V * V - 2 * self.Vm * V + self.Vsd * (2 * self.Vm - self.Vsd)) / \
            (2 * self.Vsd * self.Vm - self.Vm ** 2 - self.Vsd ** 2)
        return np.where(V < self.Vm, cs, f * cs + (1 - f) * 2 / (self.Vsd - V))

    def stars(self, V):
        """eta*, gamma* (A4, A5) and p* (eq. 20) at the clamped solid fraction V."""
        e = self.eps
        e2 = e * e
        g0 = self.g0(V)
        G = V * g0
        cstar = 32 * (1 - e) * (1 - 2 * e2) / (81 - 17 * e + 30 * e2 * (1 - e))
        zeta0 = 5 / 12 * g0 * (1 - e2) * (1 + 3 * cstar / 32)
        nu_eta = g0 * (1 - 0.25 * (1 - e) ** 2) * (1 - cstar / 64)
        eta_k = (1 - 0.4 * (1 + e) * (1 - 3 * e) * G) / (nu_eta - 0.5 * zeta0)
        gam = 128 / (5 * np.pi) * V * G * (1 + e) * (1 - cstar / 32)
        eta = eta_k * (1 + 0.8 * G * (1 + e)) + 0.6 * gam
        return eta, gam, 1 + 2 * (1 + e) * G

    def sound_speed(self, V, T):
        dV = 1e-6
        Va, Vb = np.maximum(V - dV, self.Vmin), np.minimum(V + dV, self.Vcap)
        pa = 2 * (1 + self.eps) * Va * self.g0(Va)
        pb = 2 * (1 + self.eps) * Vb * self.g0(Vb)
        dpdV = np.where(Vb > Va, (pb - pa) / np.maximum(Vb - Va, 1e-30), 0.0)
        ps = self.stars(V)[2]
        return np.sqrt(np.maximum(T, 0) * (ps + V * np.maximum(dpdV, 0) + 2 / 3 * ps * ps))


def speeds(d, p, kt, h):
    """Per-particle speeds (elastic, sound, viscous, |v|) and the solid fraction."""
    rho = d["mass"].astype(float) / d["volume"].astype(float)
    Vraw = rho / kt.rho_p
    V = np.clip(Vraw, kt.Vmin, kt.Vcap)
    T = np.maximum(d["granularTemperature"].astype(float), 0)
    eta = d["shearViscosity"].astype(float)
    eta_s, gam_s, p_s = kt.stars(V)
    c_visc = 2 * (4 / 3 * eta + eta * gam_s / eta_s) / (rho * h)
    c_sound = kt.sound_speed(V, T)
    pf = np.maximum(d["pressure"].astype(float) - kt.rho_p * V * p_s * T, 0)  # frictional pressure
    n = p.get("elasticExponent", 0.5)
    pat = p.get("atmosphericPressure", 101300.0)
    e = np.clip(1 / Vraw - 1, 0, 2)
    K = p["referenceBulkModulus"] * pat ** (1 - n) * (2.97 - e) ** 2 / (1 + e) * (pf + p.get("minPressure", 1.0)) ** n
    nu = p["poissonRatio"]
    c_el = np.sqrt(K * (1 + 4 / 3 * 3 * (1 - 2 * nu) / (2 * (1 + nu))) / rho)
    v = np.linalg.norm(d["velocity"], axis=1)
    # dispersed points (below minSolidFraction: materials/common/include/scree/materials/
    # dispersed.hpp) carry no stress and no wave: only their own speed counts
    gas = Vraw < kt.Vmin
    c_el, c_sound, c_visc = (np.where(gas, 0.0, c) for c in (c_el, c_sound, c_visc))
    return {"elastic": c_el, "sound": c_sound, "viscous": c_visc, "v": v}, Vraw


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("-o", "--output", help="write the numbers as JSON here")
    a = ap.parse_args()
    p = material(a.case)
    kt = KineticTheory(p)
    tr = cc.release_time(a.case)
    series = cc.Series(a.case)
    co = control(a.case, "maxCo", 0.5)
    h = control(a.case, "cellSize", None, "gridDict")
    V0 = 1 / (1 + p["initialVoidRatio"])
    steps = cc.snapshot_steps(series, tr)
    out = {"maxCo": co, "cell_size_m": h, "snapshots": []}
    prev = None
    for (t, f), st in zip(series.items, steps):
        d = cc.Series.read(f, ["mass", "volume", "velocity", "displacement", "pressure", "shearViscosity",
                               "granularTemperature"])
        c, V = speeds(d, p, kt, h)
        total = c["elastic"] + c["sound"] + c["viscous"] + c["v"]
        dt = co * h / total
        i = int(np.argmax(total))
        loose = V < LOOSE_V
        x, x0 = d["x"], d["x"] - d["displacement"]
        row = {"time_after_release_s": round(t - tr, 9), "step": st["step"],
               "dt_estimate_s": float(dt[i]),
               "limiting_particle": {"x_m": float(x[i, 0]), "y_m": float(x[i, 1]), "solid_fraction": float(V[i]),
                                     "viscous_m_per_s": float(c["viscous"][i]),
                                     "sound_m_per_s": float(c["sound"][i]),
                                     "elastic_m_per_s": float(c["elastic"][i]),
                                     "velocity_m_per_s": float(c["v"][i])},
               "particles_setting_within_10_percent": int(np.sum(dt < 1.1 * dt[i])),
               "particles_with_dt_below_1e-6": int(np.sum(dt < 1e-6)),
               "particles_with_dt_below_2e-6": int(np.sum(dt < 2e-6)),
               "dt_of_the_others_s": float(dt[~loose].min()) if (~loose).any() else None,
               "loose_particles": int(loose.sum())}
        if loose.any():
            row["loose"] = {
                "x_m": [float(x[loose, 0].min()), float(x[loose, 0].max())],
                "y_max_m": float(x[loose, 1].max()),
                "initial_x_m": [float(x0[loose, 0].min()), float(x0[loose, 0].max())],
                "initial_y_m": [float(x0[loose, 1].min()), float(x0[loose, 1].max())],
                "solid_fraction": [float(V[loose].min()), float(V[loose].max())],
                "volume_over_initial": [float(V0 / V[loose].max()), float(V0 / V[loose].min())],
                "granular_temperature_m2_per_s2": [float(d["granularTemperature"][loose].min()),
                                                   float(d["granularTemperature"][loose].max())],
                "largest_speed_m_per_s": float(c["v"][loose].max())}
        if prev is not None and st["step"] is not None and prev[1] is not None and st["step"] > prev[1]:
            row["mean_dt_since_previous_snapshot_s"] = (t - prev[0]) / (st["step"] - prev[1])
        prev = (t, st["step"])
        out["snapshots"].append(row)
    text = json.dumps(out, indent=2)
    print(text)
    if a.output:
        with open(a.output, "w") as fh:
            fh.write(text + "\n")


if __name__ == "__main__":
    main()

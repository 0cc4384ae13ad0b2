// muI: the mu(I) rheology of dense granular flows as an elastic-viscoplastic continuum
// for explicit MPM. An out-of-tree example plugin: docs/writing-a-material.md builds it
// step by step.
//
// Rheology (Jop, Forterre & Pouliquen 2006, Nature 441, 727-730; GDR MiDi 2004, Eur.
// Phys. J. E 14, 341-365): in steady shear the shear stress is a friction coefficient
// times the pressure, and the coefficient grows with the inertial number I,
//
//   tau = mu(I) p,   mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1),
//   I = gammadot d / sqrt(p / rho_s),
//
// with tau = sqrt(s:s / 2) (s the stress deviator; tau = |sigma_xy| in simple shear) and
// gammadot = sqrt(2 D:D) (= dv_x/dy in simple shear).
//
// Elastic-viscoplastic form (Dunatunga & Kamrin 2015, J. Fluid Mech. 779, 483-513): the
// grains deform elastically below the yield stress mu_s p and flow plastically above it.
// One step, from the framework's co-rotated stress sigma_n:
//
//   1. elastic trial (hypoelastic, bulk modulus K, shear modulus G):
//        sigma_tr = sigma_n + K tr(deps) I + 2 G dev(deps)
//        p_tr = -tr(sigma_tr)/3,  s_tr = dev(sigma_tr),  tau_tr = sqrt(s_tr:s_tr / 2)
//   2. p_tr <= 0: the grains have lost contact; the point is stress free and its stress
//      is rebuilt from zero on compaction (Dunatunga & Kamrin's "disconnected" material,
//      here decided by the sign of the trial pressure instead of by the density).
//   3. tau_tr <= mu_s p_tr: elastic, sigma = sigma_tr.
//   4. otherwise the plastic shear rate gp >= 0 solves
//        tau = tau_tr - G dt gp = mu(I(gp)) p_tr,  I(gp) = gp d sqrt(rho_s / p_tr),
//      a quadratic in gp with exactly one positive root (below); the flow is isochoric
//      and along the deviator (radial return): sigma = -p_tr I + (tau / tau_tr) s_tr.
//
// With A = d sqrt(rho_s / p), S = G dt, the condition times (I0 + A gp) is
//   S A gp^2 + (S I0 + mu_2 p A - tau_tr A) gp - (tau_tr - mu_s p) I0 = 0,
// whose constant term is negative when the point yields, so one root is positive.
//
// Time step: the update is implicit in gp, so its stress never responds to a strain
// increment more stiffly than the elastic trial does (d tau / d tau_tr lies in (0, 1]);
// the elastic P-wave speed bounds the explicit step, as in Dunatunga & Kamrin. A viscous
// model whose stress is 2 eta D evaluated from the current strain rate (explicit) would add
// c_visc = 2 eta / (rho h) to wave_speed.
//
// Units SI, stress tension positive (the framework's convention); p is compression
// positive.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "scree/material/material.hpp"

namespace mui_example {

using scree::Real;
using scree::StrainIncrement;
using scree::Sym3;

struct MuIRheology {
  static constexpr const char* type_name = "muI";

  struct Params {
    Real mu_s;   ///< static friction coefficient mu_s [-]
    Real mu_2;   ///< limiting friction coefficient at large I, mu_2 > mu_s [-]
    Real I0;     ///< inertial number scale I0 [-]
    Real d;      ///< grain diameter [m]
    Real rho_s;  ///< grain (solid) density [kg/m^3]
    Real phi;    ///< solid fraction phi [-] (bulk density phi rho_s)
    Real K;      ///< bulk modulus [Pa]
    Real G;      ///< shear modulus [Pa]
  };

  // Internal variables: only Real (or Sym3) members, stored one array per Real.
  struct State {
    Real gp;      ///< plastic shear rate of the last step [1/s]
    Real I;       ///< inertial number of the last step [-]
    Real gamma;   ///< accumulated plastic shear strain, integral of gp dt [-]
  };

  static scree::ParamSpec spec() {
    scree::ParamSpec s(type_name,
                       "mu(I) rheology of dense granular flow (Jop, Forterre & Pouliquen 2006), "
                       "elastic-viscoplastic (Dunatunga & Kamrin 2015); tension: stress free");
    s.scalar("muS", "-", "static friction coefficient mu_s = tan(theta_1), e.g. 0.382 for glass beads")
        .range(0.0, 2.0)
        .open_min();
    s.scalar("mu2", "-", "limiting friction coefficient mu_2 = tan(theta_2) > mu_s, e.g. 0.643")
        .range(0.0, 2.0)
        .open_min();
    s.scalar("I0", "-", "inertial number scale I0, e.g. 0.279").positive();
    s.scalar("grainDiameter", "m", "grain diameter d").positive();
    s.scalar("grainDensity", "kg/m^3", "grain (solid) density rho_s").positive();
    s.scalar("solidFraction", "-", "solid fraction phi; the bulk density is phi rho_s")
        .range(0.0, 1.0)
        .open_min();
    s.scalar("bulkModulus", "Pa", "bulk modulus K (give K and G, or E and nu)").positive().optional();
    s.scalar("shearModulus", "Pa", "shear modulus G (give K and G, or E and nu)").positive().optional();
    s.scalar("E", "Pa", "Young's modulus (give K and G, or E and nu)").positive().optional();
    s.scalar("nu", "-", "Poisson's ratio (give K and G, or E and nu)").range(-1.0, 0.5).open_min().open_max().optional();
    // Checks across parameters run after the per-key checks; every error is reported.
    s.check([](const scree::Dictionary& d, std::vector<scree::InputError>& errors) {
      const bool kg = d.has("bulkModulus") && d.has("shearModulus");
      const bool enu = d.has("E") && d.has("nu");
      const bool any_kg = d.has("bulkModulus") || d.has("shearModulus");
      const bool any_enu = d.has("E") || d.has("nu");
      if (!((kg && !any_enu) || (enu && !any_kg)))
        errors.emplace_back(d.where(), "'" + d.name() + "': give either bulkModulus and shearModulus, or E and nu");
      if (d.has("muS") && d.has("mu2") && !(d.get_scalar("mu2") > d.get_scalar("muS")))
        errors.emplace_back(d.where(), "'" + d.name() + "': mu2 must exceed muS");
    });
    return s;
  }

  static Params read(const scree::ParamReader& r) {
    Params p{};
    p.mu_s = r.scalar("muS");
    p.mu_2 = r.scalar("mu2");
    p.I0 = r.scalar("I0");
    p.d = r.scalar("grainDiameter");
    p.rho_s = r.scalar("grainDensity");
    p.phi = r.scalar("solidFraction");
    if (r.has("bulkModulus")) {
      p.K = r.scalar("bulkModulus");
      p.G = r.scalar("shearModulus");
    } else {
      const Real E = r.scalar("E"), nu = r.scalar("nu");
      p.K = E / (3 * (1 - 2 * nu));
      p.G = E / (2 * (1 + nu));
    }
    return p;
  }

  static Real density(const Params& p) { return p.phi * p.rho_s; }

  /// mu(I) of Jop et al. (2006), eq. (2) (host and device).
  SCREE_HD static Real friction(const Params& p, Real I) {
    return p.mu_s + (p.mu_2 - p.mu_s) * I / (p.I0 + I);
  }

  static State initial_state(const Params& p, Sym3& sigma) {
    // A tensile initial stress cannot be carried by loose grains: start stress free.
    if (scree::pressure(sigma) <= 0) sigma = Sym3::zero();
    // An initial stress beyond the yield surface is brought back onto it (rate 0).
    const Real pr = scree::pressure(sigma);
    const Sym3 s = scree::deviator(sigma);
    const Real tau = sqrt(Real(0.5) * scree::ddot(s, s));
    if (tau > p.mu_s * pr && tau > 0) sigma = Real(-1) * pr * Sym3::identity() + (p.mu_s * pr / tau) * s;
    return State{0, 0, 0};
  }

  /// The elastic trial of step 1 (see the top of this file).
  SCREE_HD static Sym3 trial(const Params& p, const Sym3& sigma, const StrainIncrement& inc) {
    const Real ev = inc.deps.trace();
    Sym3 t = sigma;
    for (int i = 0; i < 3; ++i) t[i] += p.K * ev + 2 * p.G * (inc.deps[i] - ev / 3);
    for (int i = 3; i < 6; ++i) t[i] += 2 * p.G * inc.deps[i];
    return t;
  }

  /// Whether the trial stress (pressure pr, shear stress tau_tr) stays elastic: in contact
  /// and not above the static yield stress mu_s p (steps 2 and 3).
  SCREE_HD static bool elastic(const Params& p, Real pr, Real tau_tr, const StrainIncrement& inc) {
    return pr > 0 && (!(tau_tr > p.mu_s * pr) || !(inc.dt > 0));
  }
  SCREE_HD static Real shear_stress(const Sym3& dev) { return sqrt(Real(0.5) * scree::ddot(dev, dev)); }

  // Optional: the cheap common case alone (an elastic step), the same result as update()
  // when it returns true. The GPU runs it in a lean kernel over all points and update()
  // only where it returns false (then s and sigma must be untouched).
  SCREE_HD static bool update_elastic(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    const Sym3 t = trial(p, sigma, inc);
    if (!elastic(p, scree::pressure(t), shear_stress(scree::deviator(t)), inc)) return false;
    sigma = t;
    s.gp = 0;
    s.I = 0;
    return true;
  }

  SCREE_HD static void update(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    const Sym3 t = trial(p, sigma, inc);
    const Real pr = scree::pressure(t);
    s.gp = 0;
    s.I = 0;
    if (!(pr > 0)) {  // 2. disconnected: no contact, no stress
      sigma = Sym3::zero();
      return;
    }
    const Sym3 dev = scree::deviator(t);
    const Real tau_tr = shear_stress(dev);
    if (elastic(p, pr, tau_tr, inc)) {  // 3. below the static yield stress
      sigma = t;
      return;
    }
    // 4. plastic shear rate: the positive root of a gp^2 + b gp - C = 0, written so that
    //    it loses no digits whatever the sign of b.
    const Real A = p.d * sqrt(p.rho_s / pr);
    const Real C = (tau_tr - p.mu_s * pr) * p.I0;
    const Real S = p.G * inc.dt;
    const Real a = S * A;
    const Real b = S * p.I0 + (p.mu_2 * pr - tau_tr) * A;
    const Real q = sqrt(b * b + 4 * a * C);
    const Real gp = b >= 0 ? 2 * C / (b + q) : (q - b) / (2 * a);
    const Real tau = fmax(tau_tr - S * gp, p.mu_s * pr);
    const Real scale = tau / tau_tr;
    for (int i = 0; i < 3; ++i) sigma[i] = -pr + scale * dev[i];
    for (int i = 3; i < 6; ++i) sigma[i] = scale * dev[i];
    s.gp = gp;
    s.I = gp * A;
    s.gamma += gp * inc.dt;
  }

  // Signal speed for the CFL step: the elastic P-wave speed at the current density (no
  // viscous limit is needed, see the top of this file).
  SCREE_HD static Real wave_speed(const Params& p, const State&, const Sym3&, Real rho, Real) {
    return sqrt((p.K + Real(4) / 3 * p.G) / rho);
  }

  static void describe(scree::OutputFields<MuIRheology>& out) {
    out.state("plasticShearRate", &State::gp, "1/s", "plastic shear rate gammadot_p of the last step (0: elastic)");
    out.state("inertialNumber", &State::I, "-", "inertial number I = gammadot_p d / sqrt(p / rho_s) of the last step");
    out.state("plasticStrain", &State::gamma, "-", "accumulated plastic shear strain, integral of gammadot_p dt");
    out.derived("frictionCoefficient", "-", "tau / p = sqrt(s:s/2) / p (0 where p <= 0)",
                [](const Params&, const State&, const Sym3& sig) {
                  const Real pr = scree::pressure(sig);
                  const Sym3 s = scree::deviator(sig);
                  return pr > 0 ? sqrt(Real(0.5) * scree::ddot(s, s)) / pr : Real(0);
                });
    out.derived("shearViscosity", "Pa s", "effective viscosity tau / gammadot_p where flowing, else 0",
                [](const Params&, const State& st, const Sym3& sig) {
                  const Sym3 s = scree::deviator(sig);
                  return st.gp > 0 ? sqrt(Real(0.5) * scree::ddot(s, s)) / st.gp : Real(0);
                });
  }
};

}  // namespace mui_example

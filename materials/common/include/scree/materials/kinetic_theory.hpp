// Kinetic theory of dense granular flows: collisional stress and granular temperature.
//
// One formula in one place: the kineticTheory and phaseTransition materials both call these
// free functions (materials/common, shared by the plugins and installed with the SDK). Every
// line cites the equation it implements: "eq. N" is the phase-transition paper (Feng, Liang,
// Yin & Hu 2025, IJNAMG), "(A.n)"/"(B.n)" its appendices, "GD99" Garzó & Dufty (1999) Phys.
// Rev. E 59:5895, "CS13" Chialvo & Sundaresan (2013) Phys. Fluids 25:070603. Where the paper
// departs from GD99 by a slip, the comment says which form is used and why;
// materials/kineticTheory/README.md lists every decision.
//
// Units: SI. Granular temperature T in m^2/s^2 (the fluctuation kinetic energy per unit mass
// is 3/2 T). Solid fraction V = 1/(1+e). Stress tension positive; p_col is a pressure
// (compression positive). D is the strain-rate tensor (tension positive), D = deps/dt.
//
// Device code: only <cmath> functions, no exceptions, no allocation, no recursion.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/core/tensor.hpp"
#include "scree/materials/dispersed.hpp"

namespace scree::materials::kt {

inline constexpr Real kSqrtPi = 1.77245385090551602730;

/// The constants of the collisional part, by name; make_params() derives Params from them:
///   kt::make_params(kt::Constants{.rho_p = 2650, .d = 1.25e-3, .Vsd = ..., ...})
struct Constants {
  Real rho_p;    ///< particle (grain) density rho_p [kg/m^3]
  Real d;        ///< particle diameter d [m]
  Real Vsd;      ///< solid fraction of the densest disordered packing V_sd = 1/(1+e_sd) [-]
  Real Vm;       ///< solid fraction where the dense branch of g0 starts, V_m [-] (eq. 26)
  Real eps;      ///< effective restitution coefficient eps_r (eq. 24, CS13), in [0, 1)
  Real Vcap;     ///< largest solid fraction used in the theory (g0 cap, see cap_solid_fraction)
  Real Vmin;     ///< smallest solid fraction of a continuum; below it a point is dispersed (dispersed())
  Real zeta1;    ///< 1: include the first-order cooling rate zeta1* (B11-B14), 0: omit it
  /// The paper-literal readings (0, the default: Garzo & Dufty 1999; README, KT-3 and KT-2):
  Real a5_printed = 0;  ///< 1: gamma* of (A5) as printed, with G = V g0 where GD99 has V G
  Real b8_printed = 0;  ///< 1: Gamma of (B8)/eq. (28) as printed, one factor V fewer than GD99
  /// 1: the time step's signal speeds take the larger of T and the steady temperature of the
  /// last step's strain rate (step_temperature); 0: T itself (timeStepTemperature)
  Real steady_step = 0;
};

/// The factors of the coefficients that depend on the constants only, computed once by
/// make_params(): with them coefficients() needs three divisions instead of nine (a GPU
/// waits about ten dependent instructions on each). The functions of Appendices A-B
/// regrouped: every g0 in (B12)'s numerator and denominator cancels, so Gamma1 needs no
/// division at all.
struct Prepared {
  Real cstar;   ///< c* (A9)
  Real z0;      ///< zeta0*/g0 (A7)
  Real nueta;   ///< nu_eta/g0 (A8)
  Real ek;      ///< 0.4 (1+e)(1-3e) of (A6)
  Real ek_den;  ///< (nu_eta - zeta0/2)/g0 of (A6)
  Real gam;     ///< gamma*/(V G) (A5)
  Real eta_g;   ///< 0.8 (1+e) of (A4)
  Real eta0;    ///< 5 sqrt(pi)/96 rho_p d
  Real diss;    ///< 144/(5 sqrt(pi)) rho_p/d
  Real n_lam;   ///< 4/15 lambda of (B12)
  Real n_p;     ///< (2/3 - e) c* of (B12)
  Real b_p;     ///< (1 - e) of (B11)
  Real b_n;     ///< 5/32 (1-e^2)(1+3c*/64) / (Dn/g0) of (B11)-(B13)
  Real rf;      ///< 1/(2 V_sd V_m - V_m^2 - V_sd^2) of eq. (26)
};

/// Parameters of the collisional part: the constants and their prepared factors (trivially
/// copyable, copied to the GPU once). Made by make_params() below, or from a dictionary by
/// read_collisional() (kinetic_theory_spec.hpp).
struct Params : Constants {
  Prepared k;  ///< parameter-only factors of the coefficients
};

/// eq. (24) (CS13): effective restitution coefficient accounting for tangential friction,
/// eps_r = eps_n - 3/2 mu_p exp(-3 mu_p); clamped to [0, 1 - 1e-9] (a negative value has no
/// meaning as a restitution coefficient; eps_r = 1 would remove all dissipation).
SCREE_HD inline Real effective_restitution(Real eps_n, Real mu_p) {
  const Real e = eps_n - Real(1.5) * mu_p * exp(-3 * mu_p);  // eq. (24)
  return fmin(fmax(e, Real(0)), Real(1) - Real(1e-9));
}

/// The solid fraction at which g0 (eq. 25) reaches g0max: V_cap = V_sd - 2/g0max, from the
/// dense branch g0 ~ 2/(V_sd - V) near V_sd (where f(e) -> 0, eq. 26). Kept >= V_m.
inline Real cap_solid_fraction(Real Vsd, Real Vm, Real g0max) {
  const Real v = Vsd - 2 / g0max;
  return v > Vm ? v : Real(0.5) * (Vm + Vsd);
}

/// Solid fraction used by the theory: V = 1/(1+e) clamped to [Vmin, Vcap] (regularises
/// g0 -> infinity as V -> V_sd and V > V_sd, where eqs. 25-26 have no meaning).
SCREE_HD inline Real solid_fraction(const Params& P, Real e) {
  const Real V = 1 / (1 + fmax(e, Real(0)));
  return fmin(fmax(V, P.Vmin), P.Vcap);
}

/// Whether a point of void ratio e is dispersed: its solid fraction 1/(1+e) below V_min
/// (minSolidFraction). The kinetic theory is a continuum theory: its Chapman-Enskog
/// expansion holds while the mean free path lambda = d/(6 sqrt(2) V g0) is short against the
/// flow's length scale. At V = 1e-3 (the default) lambda is about 118 d, 0.12-0.15 m for the
/// sands of the paper's cases: as long as the flowing layers themselves. Such a point is a
/// spray of grains in free flight, not a continuum: it carries no stress (no contact network,
/// and a collisional stress whose viscosity eta0 ~ rho_p d sqrt(T) does not vanish with V
/// would be transmitted across a gap wider than the flow), so its stress does no work and its
/// granular temperature has no production. Left to eqs. (19)-(27), such points are heated
/// by their own stretching to T ~ (d D/V)^2 and set the time step through their viscous and
/// sound speeds (materials/kineticTheory/README.md, "Dispersed points").
SCREE_HD inline bool dispersed(const Params& P, Real e) { return dispersed_below(P.Vmin, e); }

/// 1/(2 V_sd V_m - V_m^2 - V_sd^2), the denominator of eq. (26) as a reciprocal (a
/// parameter-only factor: Prepared::rf).
inline Real blend_reciprocal(const Constants& P) { return 1 / (2 * P.Vsd * P.Vm - P.Vm * P.Vm - P.Vsd * P.Vsd); }

/// The blend f of eq. (26) above V_m, f = 1 - ((V - V_m)/(V_sd - V_m))^2, by the prepared
/// reciprocal of its denominator.
SCREE_HD inline Real dense_blend(const Params& P, Real V) {
  return (V * V - 2 * P.Vm * V + P.Vsd * (2 * P.Vm - P.Vsd)) * P.k.rf;
}

/// Radial distribution function at contact g0(V), eqs. (25)-(26) (CS13 form):
/// Carnahan-Starling below V_m, blended with the dense 2/(V_sd - V) branch above.
SCREE_HD inline Real radial_distribution(const Params& P, Real V) {
  const Real cs = (2 - V) / (2 * (1 - V) * (1 - V) * (1 - V));  // eq. (25), first term
  // eq. (26): f = 1 below V_m (g0 = cs exactly: 1 cs + 0), the blend above. Without a branch,
  // so that the compiler can share the whole of coefficients() between a stress update and
  // the wave speed right after it (V < V_sd always: V_cap < V_sd).
  const Real f = V < P.Vm ? Real(1) : dense_blend(P, V);
  return f * cs + (1 - f) * 2 / (P.Vsd - V);  // eq. (25)
}

/// dg0/dV of radial_distribution(), from the derivatives of eqs. (25)-(26):
///   d/dV (2 - V)/(2 (1 - V)^3) = (5 - 2V)/(2 (1 - V)^4),   d/dV 2/(V_sd - V) = 2/(V_sd - V)^2,
///   df/dV = 2 (V - V_m)/(2 V_sd V_m - V_m^2 - V_sd^2).
SCREE_HD inline Real radial_distribution_slope(const Params& P, Real V) {
  const Real r = 1 / (1 - V), r3 = r * r * r;
  const Real cs = Real(0.5) * (2 - V) * r3, dcs = Real(0.5) * (5 - 2 * V) * r3 * r;  // eq. (25)
  if (V < P.Vm) return dcs;                                                          // eq. (26), f = 1
  const Real f = dense_blend(P, V), df = 2 * (V - P.Vm) * P.k.rf;
  const Real q = 1 / (P.Vsd - V);
  return df * cs + f * dcs - df * 2 * q + (1 - f) * 2 * q * q;
}

/// Coefficients of the constitutive functions at one solid fraction, such that
///   p_col = p_hat T,  eta = eta_hat sqrt(T),  gamma = gam_hat sqrt(T),
///   Gamma = diss_hat T^{3/2} + div_hat T tr(D)          (dissipation rate per volume)
struct Coefficients {
  Real V;         ///< solid fraction used [-]
  Real g0;        ///< radial distribution at contact [-]
  Real G;         ///< G = V g0 (eq. 23 with GD99: the paper's "= rho_p/(1+e) g0" is a slip) [-]
  Real p_star;    ///< p* = 1 + 2 (1 + eps) G = 4 G F (eq. 20 with A1) [-]
  Real cstar;     ///< c* (A9) [-]
  Real zeta0;     ///< zeta0* (A7 = B10) [-]
  Real eta_star;  ///< eta* (A4) [-]
  Real gam_star;  ///< gamma* (A5, GD99 form) [-]
  Real p_hat;     ///< [kg/m^3]
  Real eta_hat;   ///< [kg/m^2]
  Real gam_hat;   ///< [kg/m^2]
  Real diss_hat;  ///< [kg/m^4]
  Real div_hat;   ///< [kg/m^3]
  Real energy;    ///< 3/2 rho_p V: fluctuation energy per volume per unit T [kg/m^3] (eq. 27)
};

/// The parameter-only factors (Prepared) of the constants.
inline Prepared prepare(const Constants& P) {
  Prepared C{};
  const Real e = P.eps, e2 = e * e, e3 = e2 * e;
  C.cstar = 32 * (1 - e) * (1 - 2 * e2) / (81 - 17 * e + 30 * e2 * (1 - e));  // (A9), e = eps_r (not the void ratio)
  C.z0 = Real(5) / 12 * (1 - e2) * (1 + 3 * C.cstar / 32);                     // (A7) = (B10), over g0
  C.nueta = (1 - Real(0.25) * (1 - e) * (1 - e)) * (1 - C.cstar / 64);         // (A8), over g0
  C.ek = Real(0.4) * (1 + e) * (1 - 3 * e);                                    // (A6) numerator
  C.ek_den = C.nueta - Real(0.5) * C.z0;                                       // (A6) denominator, over g0
  // (A5): GD99 has phi^2 chi = V G; the paper's "G" drops one factor V (README, item KT-3).
  C.gam = Real(128) / (5 * kPi) * (1 + e) * (1 - C.cstar / 32);
  C.eta_g = Real(0.8) * (1 + e);  // (A4)
  // eqs. (21)-(22) with (A2)-(A3) and rho = rho_p V: the G, (1+e) and V factors cancel to
  // eta = eta0 eta*, eta0 = 5 sqrt(pi)/96 rho_p d sqrt(T) (GD99's dilute viscosity).
  C.eta0 = 5 * kSqrtPi / 96 * P.rho_p * P.d;
  // eq. (28) with rho = rho_p V (GD99; the paper's (B8) lacks a factor V):
  // Gamma0 = 144/(5 sqrt(pi)) rho_p V^2 zeta0* T^{3/2} / d.
  C.diss = 144 / (5 * kSqrtPi) * P.rho_p / P.d;
  // (B11)-(B14): zeta1* = (5/96) d (1+e_void) sqrt(pi/T) [-(1-eps)(p*-1)
  //   + 5/32 (1-eps^2)(1+3c*/64) g0 N/Dn] tr(D). Inserted into eq. (28):
  // Gamma1 = 3/2 rho_p V T [ ... ] tr(D) (the d, sqrt(T) and (1+e_void) V cancel), and g0
  // cancels between g0 and Dn (B12)-(B13).
  const Real lam = Real(0.375) * ((1 - e) * (5 * e2 + 4 * e - 1) +
                                  C.cstar / 12 * (159 * e + 3 * e2 - 19 - 15 * e3));  // (B14), GD99's "- 19"
  const Real nugam = (1 + e) / 48 *
                     (128 - 96 * e + 15 * e2 - 15 * e3 + C.cstar / 64 * (15 * e3 - 15 * e2 + 498 * e - 434));  // (B13)/g0
  const Real dn = Real(0.5) * C.z0 + nugam + Real(5) / 64 * C.cstar * (1 + 3 * C.cstar / 64) * (1 - e2);  // (B12) den./g0
  C.n_lam = Real(4) / 15 * lam;          // (B12) numerator
  C.n_p = (Real(2) / 3 - e) * C.cstar;   // (B12) numerator
  C.b_p = 1 - e;                         // (B11)
  C.b_n = Real(5) / 32 * (1 - e2) * (1 + 3 * C.cstar / 64) / dn;  // (B11)
  C.rf = blend_reciprocal(P);            // eq. (26)
  return C;
}

/// Params from the named constants: the constants and their prepared factors.
inline Params make_params(const Constants& c) {
  Params P{};
  static_cast<Constants&>(P) = c;
  P.k = prepare(c);
  return P;
}

/// The coefficients at the solid fraction V (eqs. 20-28 with Appendices A-B), from the
/// prepared factors P.k.
SCREE_HD inline Coefficients coefficients(const Params& P, Real V) {
  const Prepared& C = P.k;
  Coefficients c;
  const Real e = P.eps;
  c.V = V;
  c.g0 = radial_distribution(P, V);                // eqs. (25)-(26)
  c.G = V * c.g0;                                  // eq. (23), G = V g0 (GD99)
  c.p_star = 1 + 2 * (1 + e) * c.G;                // 4GF, eq. (20)+(A1)
  c.cstar = C.cstar;                               // (A9)
  c.zeta0 = C.z0 * c.g0;                           // (A7)
  const Real eta_k = (1 - C.ek * c.G) / (C.ek_den * c.g0);  // (A6)
  c.gam_star = C.gam * (P.a5_printed > 0 ? Real(1) : V) * c.G;  // (A5); as printed: no V
  c.eta_star = eta_k * (1 + C.eta_g * c.G) + Real(0.6) * c.gam_star;  // (A4)
  c.eta_hat = fmax(C.eta0 * c.eta_star, Real(0));  // eq. (21)
  c.gam_hat = fmax(C.eta0 * c.gam_star, Real(0));  // eq. (22)
  c.p_hat = P.rho_p * V * c.p_star;                // eq. (20)
  c.diss_hat = C.diss * (P.b8_printed > 0 ? Real(1) : V) * V * c.zeta0;  // eq. (28); as printed: V, not V^2
  c.div_hat = 0;
  if (P.zeta1 > 0) {  // (B11)-(B14): br = -(1-e)(p*-1) + 5/32 (1-e^2)(1+3c*/64) g0 N/Dn
    const Real N = C.n_lam * c.G + (c.p_star - 1) * C.n_p;
    c.div_hat = Real(1.5) * P.rho_p * V * (-C.b_p * (c.p_star - 1) + C.b_n * N);
  }
  c.energy = Real(1.5) * P.rho_p * V;  // eq. (27): 3/2 rho_p/(1+e) dT/dt
  return c;
}

/// Strain-rate invariants used by the energy balance: |dev D|^2 = dev D : dev D, tr D.
struct RateInvariants {
  Real dev2;
  Real tr;
};
SCREE_HD inline RateInvariants rate_invariants(const Sym3& D) {
  const Sym3 dd = deviator(D);
  return RateInvariants{ddot(dd, dd), D.trace()};
}

/// Exact solution over dt of the Riccati equation dx/dt = (a + b x - k x^2)/2 with constant
/// coefficients, a >= 0, k >= 0, x0 >= 0. It is eq. (27) without flux written for x = sqrt(T):
/// dT/dt = a sqrt(T) + b T - k T^{3/2} (production by viscous work is linear in sqrt(T), the
/// pressure work and Gamma1 linear in T, the dissipation Gamma0 ~ T^{3/2}). Unconditionally
/// stable, non-negative for any dt, and exact in the steady state (x -> x_plus).
SCREE_HD inline Real riccati_sqrt_temperature(Real x0, Real a, Real b, Real k, Real dt) {
  x0 = fmax(x0, Real(0));
  if (!(dt > 0)) return x0;
  if (a <= 0 && x0 <= 0) return 0;  // x = 0 is a fixed point without production
  const Real h = Real(0.5) * dt;
  if (!(k > 0)) {  // no dissipation: linear equation x' = (a + b x)/2
    const Real bh = b * h;
    const Real phi = fabs(bh) > Real(1e-12) ? expm1(bh) / b : h;  // (e^{bh} - 1)/b
    return fmax(x0 + (a + b * x0) * phi, Real(0));
  }
  const Real s = sqrt(b * b + 4 * k * a);                 // discriminant, >= |b|
  const Real xp = b >= 0 ? (b + s) / (2 * k) : 2 * a / (s - b);  // positive root (stable form)
  const Real E = exp(-s * h);
  const Real y0 = x0 - xp;
  // y(t) = y0 E / (1 + k y0 (1-E)/s); the denominator written as a sum of non-negative
  // terms: [(s - b) + E (b + s)]/(2 s) + (1 - E) k x0 / s, with s - b = 4 k a/(s + b).
  if (s * h < Real(1e-12)) {  // s ~ 0 (a = b = 0): x' = -k x^2/2
    return x0 / (1 + k * x0 * h);
  }
  const Real smb = b >= 0 ? 4 * k * a / (s + b) : s - b;
  const Real rs = 1 / s;
  const Real den = (smb + E * (b + s)) * (Real(0.5) * rs) + (1 - E) * k * x0 * rs;
  const Real x = xp + y0 * E / den;
  return fmax(x, Real(0));
}

/// Granular temperature after one step of eq. (27) (no flux) with the rate D held constant
/// over dt and the solid fraction frozen at c.V.
SCREE_HD inline Real update_temperature(const Coefficients& c, Real T0, const RateInvariants& r, Real dt) {
  // energy * dT/dt = 2 eta dev2 + gamma tr^2 - p tr - Gamma0 - Gamma1   (eq. 27, sigma_col:D
  // with sigma_col = -p I + 2 eta dev D + gamma tr(D) I, tension positive; the paper is compression positive)
  const Real re = 1 / c.energy;
  const Real a = (2 * c.eta_hat * r.dev2 + c.gam_hat * r.tr * r.tr) * re;  // ~ sqrt(T)
  const Real b = -(c.p_hat + c.div_hat) * r.tr * re;                        // ~ T
  const Real k = c.diss_hat * re;                                           // ~ T^{3/2}
  // dT/dt = a x + b x^2 - k x^3 with x = sqrt(T)  <=>  dx/dt = (a + b x - k x^2)/2
  const Real x = riccati_sqrt_temperature(sqrt(fmax(T0, Real(0))), a, b, k, dt);
  return x * x;
}

/// The collisional dissipation rate per volume, eq. (28) with (B8)-(B14):
/// Gamma = Gamma0 + Gamma1 = diss_hat T^{3/2} + div_hat T tr D [W/m^3] (the sink of eq. 27).
SCREE_HD inline Real dissipation_rate(const Coefficients& c, Real T, Real trD) {
  const Real Tp = fmax(T, Real(0));
  return c.diss_hat * Tp * sqrt(Tp) + c.div_hat * Tp * trD;
}

/// The granular temperature the time step's signal speeds assume (timeStepTemperature). With
/// `current` (steady_step 0) T itself. With `steady`, the larger of T and the steady
/// temperature of the last step's strain rates, where eq. (27)'s production balances its
/// dissipation: x+ of update_temperature's Riccati equation, from the rate invariants the state
/// keeps (rate = sqrt(2/3 |dev D|^2), tr D). Why: compression heats a dense point within one
/// step by up to e^{2/3 p* |tr deps|}, and T then answers the strain rate: at V = 0.62 (g0 =
/// 383) a cold point (T = 1e-4) compressed at tr D = -4000 1/s reaches T = 2 m^2/s^2 in one
/// step of 1e-6 s, and d sigma/d tr D is 3.5 times the viscosity 4/3 eta + gamma at its new T,
/// 500 times the one at the T the step was chosen for. The update moves T monotonically
/// towards the steady state, so while the rates hold, the next step's T is at most this one.
SCREE_HD inline Real step_temperature(const Params& P, const Coefficients& c, Real T, Real rate, Real trD) {
  if (!(P.steady_step > 0)) return T;
  const Real re = 1 / c.energy;
  const Real dev2 = Real(1.5) * rate * rate;                     // |dev D|^2 from sqrt(2/3 |dev D|^2)
  const Real a = (2 * c.eta_hat * dev2 + c.gam_hat * trD * trD) * re;  // as update_temperature
  const Real b = -(c.p_hat + c.div_hat) * trD * re;
  const Real k = c.diss_hat * re;
  if (!(k > 0)) return T;
  const Real s = sqrt(b * b + 4 * k * a);
  const Real xp = b >= 0 ? (b + s) / (2 * k) : (s - b > 0 ? 2 * a / (s - b) : Real(0));
  return fmax(T, xp * xp);
}

/// eq. (19) in Scree's sign convention (tension positive):
/// sigma_col = -p_col I + 2 eta dev(D) + gamma tr(D) I. Its work sigma_col : D =
/// -p tr D + 2 eta |dev D|^2 + gamma tr(D)^2 is non-negative in isochoric shear (a production term, GD99).
SCREE_HD inline Sym3 collisional_stress(const Coefficients& c, Real T, const Sym3& D) {
  const Real x = sqrt(fmax(T, Real(0)));
  const Real p = c.p_hat * T;          // eq. (20)
  const Real eta = c.eta_hat * x;      // eq. (21)
  const Real gam = c.gam_hat * x;      // eq. (22)
  const Real tr = D.trace();
  Sym3 s = deviator(D) * (2 * eta);
  const Real iso = -p + gam * tr;
  s[0] += iso;
  s[1] += iso;
  s[2] += iso;
  return s;
}

/// Adiabatic sound speed of the granular gas at (V, T): c^2 = T [p* + V dp*/dV + 2/3 p*^2]
/// ((dp/drho)_T + T (dp/dT)_rho^2 / (rho^2 c_v), c_v = 3/2), with p* = 1 + 2 (1 + eps) V g0
/// (eq. 20): dp*/dV = 2 (1 + eps) (g0 + V dg0/dV), g0 = c.g0 at c.V.
SCREE_HD inline Real sound_speed(const Params& P, const Coefficients& c, Real T) {
  const Real dpdV = 2 * (1 + P.eps) * (c.g0 + c.V * radial_distribution_slope(P, c.V));
  const Real c2 = fmax(T, Real(0)) * (c.p_star + c.V * fmax(dpdV, Real(0)) + Real(2) / 3 * c.p_star * c.p_star);
  return sqrt(c2);
}

/// Explicit-diffusion limit written as a speed (material.hpp): c_visc = 2 mu_eff/(rho h)
/// with mu_eff = 4/3 eta + gamma (the longitudinal viscosity).
SCREE_HD inline Real viscous_speed(const Coefficients& c, Real T, Real rho, Real h) {
  if (!(rho > 0) || !(h > 0)) return 0;
  const Real x = sqrt(fmax(T, Real(0)));
  return 2 * (Real(4) / 3 * c.eta_hat * x + c.gam_hat * x) / (rho * h);
}

}  // namespace scree::materials::kt

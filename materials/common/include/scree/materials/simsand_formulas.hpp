// SIMSAND-type critical-state frictional model: the formulas, one per function.
//
// One formula in one place: the simsand material and the frictional half of phaseTransition
// both call these free functions (materials/common, shared by the plugins and installed with
// the SDK). "eq. N" is the phase-transition paper (Feng, Liang, Yin & Hu 2025, IJNAMG);
// materials/simsand/README.md lists the parameters and every decision. The constants:
// simsand_params.hpp; the stress integration that uses these formulas: simsand_integrator.hpp.
//
// Conventions: sigma is the Cauchy stress [Pa], tension positive (Scree). p = -tr(sigma)/3
// and q = sqrt(3/2 s:s) [Pa] are compression positive; the volumetric strain eps_v = tr(eps)
// is tension positive (so compression is -tr(deps)). Angles in radians.
//
// Model (per unit increment, in p-q-theta form):
//   K = K0 p_at (2.97 - e)^2/(1 + e) ((p + p_min)/p_at)^n,  G = 3(1-2nu)/(2(1+nu)) K   eq. (13)
//   f = q/(p g(theta)) - M_p eps_d^p/(k_p + eps_d^p)                                  eq. (14)
//   dg/dp = A_d (M_pt - q/(p g(theta))),  dg/dq = 1 (flow radial in the deviatoric plane) eq. (15)
//   e_c = e_ref exp(-lambda (p/p_at)^xi)                                             eq. (16)
//   tan phi_p = (e_c/e)^n_p tan phi_c,  tan phi_pt = (e/e_c)^n_d tan phi_c           eqs. (17)-(18)
//   M = 6 sin phi/(3 - sin phi) for M_c, M_p, M_pt (triaxial compression)
//   g(theta) = [2c^4/(1 + c^4 - (1 - c^4) sin 3theta)]^{1/4}, c = (3 - sin phi_c)/(3 + sin phi_c)
//              (Sheng, Sloan & Yu 2000; g = 1 in compression, c in extension = Mohr-Coulomb
//               vertices), or g = 1 (lodeDependence none)
//   1 + e follows the volume: 1 + e <- (1 + e) exp(tr deps)   (paper: de = -(1+e) d eps_v,
//              compression-positive eps_v; here tension positive)
//
// Device code: only <cmath> functions; no exceptions, allocation, recursion or lambdas
// (elastic_energy() and initial_vars(), host only, excepted).
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/materials/simsand_params.hpp"

namespace scree::materials::simsand {

// ------------------------------------------------------------------ small tensor helpers

/// (a a)_ij for a symmetric a (Voigt xx yy zz xy yz zx).
SCREE_HD inline Sym3 sym_square(const Sym3& a) {
  return Sym3{{a[0] * a[0] + a[3] * a[3] + a[5] * a[5], a[3] * a[3] + a[1] * a[1] + a[4] * a[4],
               a[5] * a[5] + a[4] * a[4] + a[2] * a[2], a[0] * a[3] + a[3] * a[1] + a[5] * a[4],
               a[3] * a[5] + a[1] * a[4] + a[4] * a[2], a[0] * a[5] + a[3] * a[4] + a[5] * a[2]}};
}
/// det(a) for a symmetric a.
SCREE_HD inline Real sym_det(const Sym3& a) {
  return a[0] * (a[1] * a[2] - a[4] * a[4]) - a[3] * (a[3] * a[2] - a[4] * a[5]) +
         a[5] * (a[3] * a[4] - a[1] * a[5]);
}
SCREE_HD inline bool finite_real(Real x) { return (x - x) == 0; }
SCREE_HD inline bool finite_sym(const Sym3& a) {
  Real s = 0;
  for (int i = 0; i < 6; ++i) s += a[i];
  return finite_real(s);
}
/// sigma = s - p I.
SCREE_HD inline Sym3 from_p_s(Real p, const Sym3& s) {
  return Sym3{{s[0] - p, s[1] - p, s[2] - p, s[3], s[4], s[5]}};
}

// Divisions are what the stress update waits on (on a GPU a double division is a chain of
// about ten dependent instructions): the functions below multiply by reciprocals where a
// quotient is a constant or is used more than once, and fold pairs of quotients into one.
// The algebra is the same; the results differ from the plain quotients by round-off.
inline constexpr Real kThird = Real(1) / 3;
/// -tr(a)/3 (tensor.hpp's pressure()) by a product.
SCREE_HD inline Real mean_pressure(const Sym3& a) { return -a.trace() * kThird; }
/// a - tr(a)/3 I (tensor.hpp's deviator()) by a product.
SCREE_HD inline Sym3 dev_part(const Sym3& a) {
  const Real m = a.trace() * kThird;
  return Sym3{{a[0] - m, a[1] - m, a[2] - m, a[3], a[4], a[5]}};
}

/// x^y for the exponents of the model: pow() on the reference path (Pol::exact_powers); on
/// the fast path the exponents the paper's parameters give, 1/2 (n = 0.5), 2 (1/(1 - n)) and
/// 1/4 (Lode function), by sqrt and a product: a few cycles instead of a pow() (which is a
/// logarithm and an exponential in extended precision), and within an ulp of it.
template <class Pol = Production>
SCREE_HD inline Real power(const Params& /*P*/, Real x, Real y) {
  if (!Pol::exact_powers) {
    if (y == Real(0.5)) return sqrt(x);
    if (y == Real(2)) return x * x;
    if (y == Real(0.25)) return sqrt(sqrt(x));
  }
  return pow(x, y);
}

// ------------------------------------------------------------------ constitutive functions

/// (2.97 - e)^2/(1 + e) of eq. (13); e limited to [0, 2] (the expression has a spurious
/// minimum at e = 2.97).
SCREE_HD inline Real void_function(Real e) {
  e = fmin(fmax(e, Real(0)), Real(2));
  const Real a = Real(2.97) - e;
  return a * a / (1 + e);
}

/// Tangent bulk modulus, eq. (13) with p regularised by p_min: K(0) > 0 so that a
/// stress-free point regains stiffness in compression.
template <class Pol = Production>
SCREE_HD inline Real bulk_modulus(const Params& P, Real e, Real p) {
  return P.Cfac * void_function(e) * power<Pol>(P, fmax(p, Real(0)) + P.pmin, P.n);  // eq. (13)
}

/// Elastic energy stored per volume at the stress sigma and void ratio e [J/m^3], for the
/// energy budget (plugins/functionObjects/Energies.hpp). Eq. (13)'s law is hypoelastic and
/// has no exact potential (K depends on e and p, G = rG K on p); this is the complementary
/// energy of an isotropic loading to p at the current e followed by a shear to q at p:
///   w = int_0^p p' dp'/K(p') + q^2/(6 G(p)),   K = Cfac F(e) (p + p_min)^n,
/// with u = p' + p_min: int p'/K dp' = [u^(2-n)/(2-n) - p_min u^(1-n)/(1-n)] from p_min to
/// p + p_min, over Cfac F(e). A stress-free point (p <= 0, the apex) stores nothing.
inline Real elastic_energy(const Params& P, Real e, const Sym3& sigma) {
  const Real p = fmax(mean_pressure(sigma), Real(0));
  const Real c = P.Cfac * void_function(e);
  const Real n = P.n, u1 = p + P.pmin, u0 = P.pmin;
  auto prim = [&](Real u) { return pow(u, 2 - n) / (2 - n) - P.pmin * pow(u, 1 - n) / (1 - n); };
  const Real wp = (prim(u1) - prim(u0)) / c;
  const Sym3 sd = dev_part(sigma);
  const Real q2 = Real(1.5) * (sd[0] * sd[0] + sd[1] * sd[1] + sd[2] * sd[2] +
                               2 * (sd[3] * sd[3] + sd[4] * sd[4] + sd[5] * sd[5]));
  const Real G = P.rG * c * pow(u1, n);
  return wp + q2 / (6 * G);
}

/// (p/p_at)^xi of eq. (16), p clipped at 0: pow() on the reference path (Pol::exact_powers),
/// exp(xi ln(p/p_at)) on the fast one (a pow() is a logarithm and an exponential in extended
/// precision, about twice the work; the two differ by an ulp or two).
template <class Pol = Production>
SCREE_HD inline Real pressure_power(const Params& P, Real p) {
  const Real x = fmax(p, Real(0)) * P.inv_pat;
  return Pol::exact_powers ? pow(x, P.xi) : exp(P.xi * log(x));
}

/// Critical void ratio, eq. (16): e_c = e_ref exp(-lambda (p/p_at)^xi).
template <class Pol = Production>
SCREE_HD inline Real critical_void_ratio(const Params& P, Real p) {
  return P.eref * exp(-P.lambda * pressure_power<Pol>(P, p));  // eq. (16)
}

/// ln(e_c/e) = ln e_ref - lambda (p/p_at)^xi - ln e (eq. 16), from pxi = (p/p_at)^xi: what
/// the void-ratio powers of eqs. (17)-(18) need, without the exponential of e_c and the
/// quotient e_c/e.
SCREE_HD inline Real log_critical_ratio(const Params& P, Real pxi, Real e) {
  return P.ln_eref - P.lambda * pxi - log(e);
}

/// Stress ratio in triaxial compression for a friction angle given by its tangent:
/// M = 6 sin phi/(3 - sin phi).
SCREE_HD inline Real ratio_from_tan(Real t) {
  return 6 * t / (3 * sqrt(1 + t * t) - t);  // sin phi = t/sqrt(1 + t^2), one quotient
}

/// Peak and phase-transformation stress ratios (eqs. 17-18) and the derivatives of M_p
/// needed by the consistency condition.
struct Ratios {
  Real ec;      ///< critical void ratio e_c(p), eq. (16)
  Real Mp;      ///< peak stress ratio, eq. (17)
  Real Mpt;     ///< phase-transformation stress ratio, eq. (18)
  Real dMp_de;  ///< dM_p/de at fixed p
  Real dMp_dp;  ///< dM_p/dp at fixed e (through e_c(p)) [1/Pa]
};
/// tan phi_p / tan phi_c = (e_c/e)^n_p of eq. (17) from pxi = (p/p_at)^xi, as ratios()
/// evaluates it: pow() on the reference path, exp(n_p ln(e_c/e)) on the fast one (whose
/// logarithm ratios() shares with eq. 18), so that the yield function and the plastic rate
/// see the same M_p.
template <class Pol = Production>
SCREE_HD inline Real peak_factor(const Params& P, Real pxi, Real e) {
  return Pol::exact_powers ? pow(P.eref * exp(-P.lambda * pxi) / e, P.np) : exp(P.np * log_critical_ratio(P, pxi, e));
}

/// M_p (eq. 17) and the values ratios_at() completes the other ratios from: a yield
/// evaluation needs M_p alone, a plastic rate all the ratios; a rate at a state a yield
/// evaluation has just checked starts from its PeakRatio (PointRatios below).
struct PeakRatio {
  Real e;      ///< void ratio, floored at 1e-6
  Real p;      ///< mean stress [Pa]
  Real pxi;    ///< (p/p_at)^xi (eq. 16)
  Real L;      ///< ln(e_c/e) (the fast path's; 0 on the reference path)
  Real tp;     ///< tan phi_p (eq. 17)
  Real w, d3;  ///< sqrt(1 + tan^2 phi_p) and 3 w - tan phi_p: sin phi_p = tp/w, 3 - sin phi_p = d3/w
  Real Mp;     ///< M_p = 6 sin phi_p/(3 - sin phi_p)
};
template <class Pol = Production>
SCREE_HD inline PeakRatio peak(const Params& P, Real e, Real p) {
  PeakRatio k;
  k.e = fmax(e, Real(1e-6));
  k.p = p;
  k.pxi = pressure_power<Pol>(P, p);
  Real fp;  // (e_c/e)^n_p, as peak_factor(); on the fast path from the logarithm eq. (18) shares
  if (Pol::exact_powers) {
    k.L = 0;
    fp = peak_factor<Pol>(P, k.pxi, k.e);
  } else {
    k.L = log_critical_ratio(P, k.pxi, k.e);
    fp = exp(P.np * k.L);
  }
  k.tp = fp * P.tanphic;  // eq. (17)
  k.w = sqrt(1 + k.tp * k.tp);
  k.d3 = 3 * k.w - k.tp;
  k.Mp = 6 * k.tp / k.d3;  // ratio_from_tan(tp)
  return k;
}

/// The peak stress ratio M_p (eq. 17) alone: what the yield function needs. Equal to
/// ratios(P, e, p).Mp.
template <class Pol = Production>
SCREE_HD inline Real peak_ratio(const Params& P, Real e, Real p) { return peak<Pol>(P, e, p).Mp; }

/// All the ratios from peak()'s part of them.
template <class Pol = Production>
SCREE_HD inline Ratios ratios_at(const Params& P, const PeakRatio& k) {
  Ratios r;
  const Real e = k.e, p = k.p, pe = fmax(p, P.pmin), tp = k.tp;
  r.ec = P.eref * exp(-P.lambda * k.pxi);  // eq. (16), as critical_void_ratio()
  // (e/e_c)^n_d of eq. (18) and (p_e/p_at)^(xi-1) of dM_p/dp: on the fast path from peak()'s
  // logarithm and (p/p_at)^xi, instead of two more pow()s.
  Real fd, pxi1;
  if (Pol::exact_powers) {
    fd = pow(e / r.ec, P.nd);
    pxi1 = pow(pe * P.inv_pat, P.xi - 1);
  } else {
    fd = exp(-P.nd * k.L);
    pxi1 = p >= P.pmin ? k.pxi * (P.pat / p) : pow(pe * P.inv_pat, P.xi - 1);
  }
  r.Mp = k.Mp;
  const Real td = fd * P.tanphic;  // eq. (18)
  r.Mpt = ratio_from_tan(td);
  // dM/dtan = 18/(3 - sin)^2 * cos^3 = 18/(d3^2 w);  dtan_p/de = -n_p tan_p/e;
  // dtan_p/dp = n_p tan_p/e_c de_c/dp = -n_p tan_p lambda xi (p/p_at)^(xi-1)/p_at
  const Real dMdt = 18 / (k.d3 * k.d3 * k.w);
  r.dMp_de = dMdt * (-P.np * tp / e);
  r.dMp_dp = dMdt * (-P.np * tp * P.lambda * P.xi * pxi1 * P.inv_pat);
  return r;
}
template <class Pol = Production>
SCREE_HD inline Ratios ratios(const Params& P, Real e, Real p) { return ratios_at<Pol>(P, peak<Pol>(P, e, p)); }

/// Lode-angle function g(theta) of M (Sheng et al. 2000) from sin(3 theta) in the
/// compression-positive convention (+1 triaxial compression, -1 triaxial extension).
template <class Pol = Production>
SCREE_HD inline Real lode_g(const Params& P, Real S) {
  if (P.lode == 0) return 1;
  S = fmin(fmax(S, Real(-1)), Real(1));
  return power<Pol>(P, 2 * P.c4 / (1 + P.c4 - (1 - P.c4) * S), Real(0.25));
}

/// What a yield evaluation and a plastic rate at the same (sigma, e) share: g(theta) and M_p
/// with its logarithms and exponentials (PeakRatio). integrate() hands them from its start
/// check and from the drift correction of an accepted substep to the rate that follows at
/// that state, which then skips evaluating them again. A projection onto the
/// surface scales the deviator at constant p and Lode angle, so they hold for its result.
struct PointRatios {
  Real g;       ///< lode_g(P, S)
  PeakRatio k;  ///< peak(P, e, p)
  bool valid = false;  ///< set by the yield evaluation that filled it (p > p_apex there)
};

/// Stress invariants: p, q, the deviator s and sin(3 theta) (compression-positive convention:
/// sin 3theta = (3 sqrt3/2) J3(-s)/J2^{3/2}, so +1 in triaxial compression).
struct Invariants {
  Real p, q, J2, J3, S;
  Real rJ2;  ///< sqrt(J2)
  Sym3 s;
};
SCREE_HD inline Invariants invariants(const Sym3& sig) {
  Invariants v;
  v.p = mean_pressure(sig);
  v.s = dev_part(sig);
  v.J2 = Real(0.5) * ddot(v.s, v.s);
  v.rJ2 = sqrt(v.J2);
  v.q = Real(1.7320508075688772) * v.rJ2;  // sqrt(3 J2)
  v.J3 = sym_det(v.s);
  v.S = v.J2 > 0 ? -Real(2.598076211353316) * v.J3 / (v.J2 * v.rJ2) : Real(0);
  v.S = fmin(fmax(v.S, Real(-1)), Real(1));
  return v;
}

/// Hardening function of eq. (14): H = M_p kappa/(k_p + kappa).
SCREE_HD inline Real hardening(const Params& P, Real Mp, Real kappa) {
  kappa = fmax(kappa, Real(0));
  return Mp * kappa / (P.kp + kappa);
}

/// Yield function eq. (14): f = q/(p g) - M_p kappa/(k_p + kappa). At the apex (p ~ 0) 0.
/// f from its parts, q/(p g) - M_p k/(k_p + k) as one quotient (k = max(kappa, 0)).
SCREE_HD inline Real yield_value(const Params& P, Real q, Real p, Real g, Real Mp, Real kappa) {
  const Real k = fmax(kappa, Real(0)), kk = P.kp + k, pg = p * g;
  return (q * kk - Mp * k * pg) / (pg * kk);
}

template <class Pol = Production>
SCREE_HD inline Real yield(const Params& P, const Sym3& sig, Real e, Real kappa) {
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex)) return 0;
  const Real g = lode_g<Pol>(P, v.S);
  return yield_value(P, v.q, v.p, g, peak_ratio<Pol>(P, e, v.p), kappa);
}

/// Elastic response to deps from sig0, integrated exactly for the power law of eq. (13) with
/// e frozen: d(p + p_min)^(1-n) = (1-n) C F(e) d(-eps_v), and the deviator with the secant
/// shear modulus G = rG (p1 - p0)/(-eps_v) (exact along a straight strain path since G/K is
/// constant). Returns false when the extension would take p below zero (separation).
template <class Pol = Production>
SCREE_HD inline bool elastic_predictor(const Params& P, const Sym3& sig0, Real e, const Sym3& deps, Sym3& sig1) {
  const Real p0 = fmax(mean_pressure(sig0), Real(0));
  const Real evc = -deps.trace();          // volumetric strain, compression positive
  const Real C = P.Cfac * void_function(e);  // K = C (p + p_min)^n
  const Real A0 = power<Pol>(P, p0 + P.pmin, P.m);
  const Real dA = P.m * C * evc;
  const Real B = A0 + dA;
  if (!(B > P.Amin)) return false;  // p1 <= 0: tension cut-off
  Real Ksec;
  Real p1;
  if (fabs(dA) > Real(1e-9) * A0) {
    p1 = power<Pol>(P, B, P.inv_m) - P.pmin;
    Ksec = (p1 - p0) / evc;
  } else {  // tiny volumetric increment: tangent modulus at the mid-point
    const Real Kt = C * power<Pol>(P, p0 + P.pmin, P.n);
    Ksec = C * power<Pol>(P, fmax(p0 + Real(0.5) * Kt * evc, Real(0)) + P.pmin, P.n);
    p1 = p0 + Ksec * evc;
  }
  p1 = fmax(p1, Real(0));
  const Sym3 s1 = dev_part(sig0) + dev_part(deps) * (2 * P.rG * Ksec);
  sig1 = from_p_s(p1, s1);
  return true;
}

/// Elastoplastic rate (one explicit evaluation) for the strain increment deps at (sig, kappa, e),
/// with de the void-ratio change over deps. Consistency (eq. 14):
///   n_f : dsig + df/de de + df/dkappa dkappa = 0,   dsig = D:(deps - dlambda m),
///   n_f = d(q/(p g))/dsig + (H/M_p) dM_p/dp dp/dsig,   m = -d/3 I + 3/2 s/q,  d = A_d (M_pt - eta)
///   dlambda = [n_f : D : deps - (H/M_p) dM_p/de de] / [n_f : D : m + M_p k_p/(k_p+kappa)^2]
/// dlambda = d eps_d^p (the flow is radial in the deviatoric plane, eq. 15).
struct Rate {
  Sym3 dsig;
  Real dkappa;
  Real deq;
  Real num;  ///< loading indicator n_f : D : deps (before clipping)
};
/// `at`: g(theta) and M_p's parts at (sig, e) already evaluated (PointRatios), or null.
template <class Pol = Production>
SCREE_HD inline bool plastic_rate(const Params& P, const Sym3& sig, Real kappa, Real e, const Sym3& deps, Real de,
                                  Rate& r, const PointRatios* at = nullptr) {
  if (at && !at->valid) at = nullptr;
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex) || !finite_real(v.p)) return false;
  const Real p = v.p, q = v.q;
  const Real K = bulk_modulus<Pol>(P, e, p);  // eq. (13)
  const Real G = P.rG * K;
  const Sym3 dev = dev_part(deps);
  const Real tr = deps.trace();
  // unit deviatoric direction of the flow (radial); along the strain deviator at q = 0
  Sym3 nh = Sym3::zero();
  const Real sn = sqrt(ddot(v.s, v.s));
  if (q > Real(1e-10) * p) {
    nh = v.s * (1 / sn);
  } else {
    const Real dn = sqrt(ddot(dev, dev));
    if (dn > 0) nh = dev * (1 / dn);
  }
  // Lode dependence of the yield surface: g(theta) and the part of df/dsigma normal to s
  Real g = 1;
  Sym3 L = Sym3::zero();
  if (P.lode != 0 && q > Real(1e-8) * p) {
    g = at ? at->g : lode_g<Pol>(P, v.S);
    const Real den_g = 1 + P.c4 - (1 - P.c4) * v.S;
    const Real dg = Real(0.25) * g * (1 - P.c4) / den_g;  // dg/dS
    // 1/J2^{3/2}, and 1/J2^{5/2} = (1/J2^{3/2})^2 sqrt(J2)
    const Real r15 = 1 / (v.J2 * v.rJ2);
    // dS/dsigma = -(3 sqrt3/2) [dev(s s)/J2^{3/2} - 3/2 J3 s/J2^{5/2}]  (deviatoric, normal to s)
    const Sym3 dJ3 = dev_part(sym_square(v.s));
    const Sym3 dS = (dJ3 * r15 - v.s * (Real(1.5) * v.J3 * r15 * r15 * v.rJ2)) * Real(-2.598076211353316);
    // d(q/(p g))/dS dS/dsigma, with q/(p g^2) = q p (1/(p g))^2
    if (fabs(v.S) < Real(1) - Real(1e-9)) {
      const Real rpg = 1 / (p * g);
      L = dS * (-q * p * rpg * rpg * dg);
    }
  }
  const Real rpg = 1 / (p * g);  // 1/(p g), used four times below
  const Real eta = q * rpg;
  const Ratios R = at ? ratios_at<Pol>(P, at->k) : ratios<Pol>(P, e, p);  // eqs. (16)-(18)
  const Real kk = fmax(kappa, Real(0)), rk = 1 / (P.kp + kk);
  const Real h = kk * rk;
  const Real dh = P.kp * rk * rk;
  const Real d = P.Ad * (R.Mpt - eta);  // eq. (15): dilatancy, > 0 contractive
  const Real a = eta * g * rpg + h * R.dMp_dp;  // eta/p + h dM_p/dp
  const Real c1 = Real(1.224744871391589) * 2 * G * rpg;  // sqrt(3/2) 2G/(p g)
  const Real num = c1 * ddot(nh, dev) + a * K * tr + 2 * G * ddot(L, dev) - h * R.dMp_de * de;
  const Real den0 = 3 * G * rpg;
  Real den = den0 - a * K * d + R.Mp * dh;
  den = fmax(den, Real(1e-3) * den0);  // guard against a non-positive plastic modulus (README)
  const Real dl = fmax(num / den, Real(0));
  // dsig = K tr I + 2G dev - dl (-K d I + 2G sqrt(3/2) nh)
  const Real iso = K * tr + dl * K * d;
  Sym3 ds = dev * (2 * G) - nh * (dl * 2 * G * Real(1.224744871391589));
  ds[0] += iso;
  ds[1] += iso;
  ds[2] += iso;
  r.dsig = ds;
  r.dkappa = dl;
  r.deq = dl * sqrt(d * d * (Real(2) / 9) + 1);  // sqrt(2/3 m:m) dlambda
  r.num = num;
  return finite_sym(ds) && finite_real(dl);
}

SCREE_HD inline Real void_ratio_at(Real one_plus_e0, Real tr, Real frac) {
  return fmax(one_plus_e0 * exp(frac * tr) - 1, Real(1e-6));
}
/// void_ratio_at() at the middle and at the end of the increment from one exponential:
/// (1 + e0) E - 1 and (1 + e0) E^2 - 1 with E = exp(tr/2) (within an ulp of the two calls).
SCREE_HD inline void void_ratios_mid_end(Real one_plus_e0, Real tr, Real& e_mid, Real& e_end) {
  const Real E = exp(Real(0.5) * tr);
  e_mid = fmax(one_plus_e0 * E - 1, Real(1e-6));
  e_end = fmax(one_plus_e0 * E * E - 1, Real(1e-6));
}

/// State for an initial stress (tension positive): tension is cut to zero; kappa is chosen
/// so that the stress lies on the yield surface (eq. 14); a stress ratio beyond 0.99 M_p is
/// reduced to 0.99 M_p (deviator scaled at constant p and Lode angle).
template <class Pol = Production>
inline Vars initial_vars(const Params& P, Sym3& sig, Real e0) {
  Vars v{e0, 0, 0};
  const Invariants iv = invariants(sig);
  if (!(iv.p > P.papex) || !finite_sym(sig)) {
    sig = Sym3::zero();
    return v;
  }
  const Real g = lode_g<Pol>(P, iv.S);
  const Real eta = iv.q / (iv.p * g);
  const Real Mp = ratios<Pol>(P, e0, iv.p).Mp;
  if (eta <= 0) return v;
  if (eta < Real(0.99) * Mp) {
    v.kappa = P.kp * eta / (Mp - eta);  // H(kappa) = eta
  } else {
    v.kappa = 99 * P.kp;
    sig = from_p_s(iv.p, iv.s * (Real(0.99) * Mp / eta));
  }
  return v;
}

/// Elastic P-wave speed sqrt((K + 4/3 G)/rho) at the current state.
template <class Pol = Production>
SCREE_HD inline Real pwave_speed(const Params& P, Real e, Real p, Real rho) {
  if (!(rho > 0)) return 0;
  const Real K = bulk_modulus<Pol>(P, e, p);
  return sqrt(K * (1 + Real(4) / 3 * P.rG) / rho);
}

}  // namespace scree::materials::simsand

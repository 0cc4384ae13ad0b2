// SIMSAND-type critical-state frictional model: formulas and stress integration.
//
// One formula in one place: the simsand material and the frictional half of phaseTransition
// both call these free functions (materials/common, shared by the plugins and installed with
// the SDK). "eq. N" is the phase-transition paper (Feng, Liang, Yin & Hu 2025, IJNAMG);
// materials/simsand/README.md lists the parameters and every decision.
//
// Conventions: sigma is the Cauchy stress, tension positive (Scree). p = -tr(sigma)/3 and
// q = sqrt(3/2 s:s) are compression positive; the volumetric strain eps_v = tr(eps) is
// tension positive (so compression is -tr(deps)). Angles in radians.
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
// Integration: elastic predictor integrated exactly (secant moduli of the power law, e frozen
// at mid-increment), Pegasus search of the yield crossing, then Sloan et al.'s (2001)
// modified-Euler substepping with local error control and drift correction. See README.md.
//
// Device code: only <cmath> functions; no exceptions, allocation, recursion or lambdas.
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"

// Diagnostics (off unless defined): with SCREE_SIMSAND_REPORT_SUBSTEPS = N, e.g. from the
// CMake option of that name in a diagnostic build, every update of integrate() that takes
// more than N substeps prints one line (printf, on the GPU too) with its count, its input
// stress, void ratio, kappa and strain increment at full precision: enough to replay it on
// the CPU and see where the substeps go (docs/performance.md, entry 15). In GPU builds with
// SCREE_REPORT_CYCLES, every update notes its substeps and paths for the particle pass's
// report of slow warps (scree/core/report_cycles.hpp; entry 16).
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
#include <cstdio>
#endif
#include "scree/core/report_cycles.hpp"

namespace scree::materials::simsand {

/// Host-prepared constants (trivially copyable).
struct Params {
  Real K0;       ///< dimensionless reference bulk modulus K_0 (eq. 13)
  Real nu;       ///< Poisson's ratio
  Real n;        ///< elastic exponent n (eq. 13), in [0, 1)
  Real pat;      ///< atmospheric pressure p_at [Pa]
  Real tanphic;  ///< tan(phi_c)
  Real Mc;       ///< 6 sin phi_c/(3 - sin phi_c)
  Real eref;     ///< e_ref (eq. 16)
  Real lambda;   ///< lambda (eq. 16)
  Real xi;       ///< xi (eq. 16)
  Real Ad;       ///< A_d (eq. 15)
  Real kp;       ///< k_p (eq. 14)
  Real np;       ///< n_p (eq. 17)
  Real nd;       ///< n_d (eq. 18)
  Real pmin;     ///< stiffness regularisation pressure p_min [Pa]: K uses p + p_min
  Real papex;    ///< below this mean stress the state is the stress-free apex [Pa]
  Real serr;     ///< stress scale below which the substepping error is absolute: 1e-3 p_at [Pa]
  Real stol;     ///< relative local error tolerance of the substepping
  Real rG;       ///< G/K = 3 (1 - 2 nu)/(2 (1 + nu))
  Real c4;       ///< c^4 of the Lode function (1 when lode == 0)
  Real lode;     ///< 1: Lode-angle dependent M (Sheng), 0: M independent of theta
  // derived constants of the elastic power law
  Real m;        ///< 1 - n
  Real inv_m;    ///< 1/(1 - n)
  Real Amin;     ///< p_min^(1-n)
  Real Cfac;     ///< K0 p_at^(1-n): K = Cfac F(e) (p + p_min)^n
  Real inv_pat;  ///< 1/p_at
  Real ln_eref;  ///< ln e_ref: ln(e_c/e) of eqs. (16)-(18) without forming e_c (log_critical_ratio)
};

/// Internal variables integrated together with the stress.
struct Vars {
  Real e;      ///< void ratio
  Real kappa;  ///< deviatoric plastic strain eps_d^p (hardening variable, eq. 14)
  Real epsEq;  ///< equivalent plastic strain integral of sqrt(2/3 deps^p : deps^p)
};

/// How the model is evaluated, fixed at compile time: the plugins' kernels carry neither a
/// field nor a branch for it. Every function below that depends on it is a template on this
/// policy, defaulting to Production; the tests instantiate the references.
///   exact_powers: false, production: the exponents 1/2, 2 and 1/4 by sqrt and products, and
///     the two void-ratio powers of eqs. (17)-(18) from one logarithm (power() and ratios();
///     within a few ulps of pow()); true: pow() for every power, the straightforward
///     evaluation the fast one is tested against (tests/unit/performance).
///   stiff_returns: true, production: stiff remainders of an update by implicit returns
///     (integrate(), README step 5); false: modified-Euler substeps throughout (Sloan et al.
///     2001), the reference the returns are tested against (tests/unit/materials).
template <bool ExactPowersV, bool StiffReturnsV>
struct Evaluation {
  static constexpr bool exact_powers = ExactPowersV;
  static constexpr bool stiff_returns = StiffReturnsV;
};
using Production = Evaluation<false, true>;       ///< what the plugins run
using ExactPowers = Evaluation<true, true>;       ///< reference for the fast powers (tests)
using EulerThroughout = Evaluation<false, false>;  ///< reference for the stiff returns (tests)

inline constexpr Real kFtol = 1e-9;        ///< yield-function tolerance (f is a stress ratio)
inline constexpr int kMaxSubsteps = 1000;  ///< substeps with error control per update (then relaxed)
inline constexpr Real kMinSubstep = 1e-4;  ///< smallest substep, as a fraction of the increment
inline constexpr int kApexIter = 8;        ///< rate evaluations to locate where a substep reaches the apex
/// Stiff updates (integrate(), README step 5): after kStiffAfter substep attempts, a remainder
/// that would need more than kStiffRemaining substeps of the current size is done in
/// kReturnSubsteps implicit returns, if the state is looser than critical and p does not grow
/// along them.
inline constexpr int kStiffAfter = 64;
inline constexpr Real kStiffRemaining = 32;
inline constexpr int kReturnSubsteps = 8;

/// The constants of the model by name, as the dictionary gives them (phi_c in degrees);
/// make_params() derives Params from them. With C++20 designated initializers:
///   simsand::make_params({.K0 = 120, .nu = 0.2, .n = 0.5, .phic_deg = 19.8, .eref = 0.977, ...})
/// Members left out take the dictionary's defaults where it has one.
struct Constants {
  Real K0;               ///< dimensionless reference bulk modulus K_0 (eq. 13)
  Real nu;               ///< Poisson's ratio
  Real n;                ///< elastic exponent n (eq. 13), in [0, 1)
  Real pat = 101300;     ///< atmospheric pressure p_at [Pa] (eqs. 13, 16)
  Real phic_deg;         ///< critical-state friction angle phi_c [deg]
  Real eref;             ///< e_ref (eq. 16)
  Real lambda;           ///< lambda (eq. 16)
  Real xi;               ///< xi (eq. 16)
  Real Ad;               ///< A_d (eq. 15)
  Real kp;               ///< k_p (eq. 14)
  Real np;               ///< n_p (eq. 17)
  Real nd;               ///< n_d (eq. 18)
  Real pmin = 1;         ///< stiffness regularisation pressure p_min [Pa]
  Real stol = 1e-4;      ///< relative local error tolerance of the substepping
  bool lode = true;      ///< Lode-angle dependent M (Sheng et al. 2000), or M_c everywhere
};

/// Host: Params, with the derived constants, from the named constants.
inline Params make_params(const Constants& k) {
  Params P{};
  P.K0 = k.K0;
  P.nu = k.nu;
  P.n = k.n;
  P.pat = k.pat;
  const Real phi = k.phic_deg * Real(3.14159265358979323846) / 180;
  const Real s = std::sin(phi);
  P.tanphic = std::tan(phi);
  P.Mc = 6 * s / (3 - s);
  P.eref = k.eref;
  P.lambda = k.lambda;
  P.xi = k.xi;
  P.Ad = k.Ad;
  P.kp = k.kp;
  P.np = k.np;
  P.nd = k.nd;
  P.pmin = k.pmin;
  P.papex = 1e-6 * k.pmin;
  P.serr = std::fmax(1e-3 * k.pat, k.pmin);
  P.stol = k.stol;
  P.rG = 3 * (1 - 2 * k.nu) / (2 * (1 + k.nu));
  const Real c = (3 - s) / (3 + s);
  P.lode = k.lode ? 1 : 0;
  P.c4 = k.lode ? c * c * c * c : 1;
  P.m = 1 - k.n;
  P.inv_m = 1 / (1 - k.n);
  P.Amin = std::pow(k.pmin, 1 - k.n);
  P.Cfac = k.K0 * std::pow(k.pat, 1 - k.n);
  P.inv_pat = 1 / k.pat;
  P.ln_eref = std::log(k.eref);
  return P;
}

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
/// that state, which then skips them (performance log, entry 21). A projection onto the
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

/// Put a stress on the yield surface by scaling its deviator at constant p and Lode angle
/// (drift correction; also used for initial stresses outside the surface).
template <class Pol = Production>
SCREE_HD inline void project_to_surface(const Params& P, Sym3& sig, Real e, Real kappa) {
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex) || !(v.q > 0)) return;
  const Real qt = hardening(P, peak_ratio<Pol>(P, e, v.p), kappa) * lode_g<Pol>(P, v.S) * v.p;
  sig = from_p_s(v.p, v.s * (qt / v.q));
}

/// f = yield() followed, when f > kFtol (or |f| > kFtol with `both_sides`), by
/// project_to_surface(), with the invariants, M_p and g(theta) evaluated once for both: the
/// same numbers as the two calls. Returns f before the projection; `projected` says whether
/// sig changed. `at`, if not null, receives g(theta) and M_p's parts for a plastic rate at
/// (sig, e) (valid only where p > p_apex).
template <class Pol = Production>
SCREE_HD inline Real yield_and_project(const Params& P, Sym3& sig, Real e, Real kappa, bool both_sides,
                                       bool& projected, PointRatios* at = nullptr) {
  projected = false;
  if (at) at->valid = false;
  const Invariants v = invariants(sig);
  if (!(v.p > P.papex)) return 0;
  const Real g = lode_g<Pol>(P, v.S);
  const PeakRatio k = peak<Pol>(P, e, v.p);
  if (at) *at = PointRatios{g, k, true};
  const Real f = yield_value(P, v.q, v.p, g, k.Mp, kappa);
  if ((both_sides ? fabs(f) : f) > kFtol && v.q > 0) {
    sig = from_p_s(v.p, v.s * (hardening(P, k.Mp, kappa) * g * v.p / v.q));
    projected = true;
  }
  return f;
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

/// Material point separated (tension): stress-free; the deviatoric strain of the remaining
/// fraction counts as plastic (free flow at zero stress).
SCREE_HD inline void separate(Sym3& sig, Vars& v, const Sym3& deps, Real frac) {
  sig = Sym3::zero();
  const Real ed = equivalent_deviatoric_strain(deps) * frac;
  v.kappa += ed;
  v.epsEq += ed;
}

/// f along the elastic path at fraction a of deps from sig0.
template <class Pol = Production>
SCREE_HD inline Real elastic_path_yield(const Params& P, const Sym3& sig0, Real kappa, Real ope0, const Sym3& deps,
                                        Real a, Sym3& sig_a) {
  const Real tr = deps.trace();
  if (!elastic_predictor<Pol>(P, sig0, void_ratio_at(ope0, tr, Real(0.5) * a), deps * a, sig_a)) return 1;
  return yield<Pol>(P, sig_a, void_ratio_at(ope0, tr, a), kappa);
}

/// The Pegasus method (Dowell & Jarratt 1972), a secant search that keeps a root bracketed,
/// used by every scalar search below: the next point from the bracket (xa, fa), (xb, fb), with
/// (xb, fb) the latest evaluation, ...
SCREE_HD inline Real pegasus_point(Real xa, Real fa, Real xb, Real fb) { return xb - fb * (xb - xa) / (fb - fa); }
/// ... and the bracket after f(x) = fx: x replaces xb; where the sign did not change, fa is
/// scaled by fb/(fb + fx) (Pegasus' rule; plain regula falsi would keep fa and stall).
SCREE_HD inline void pegasus_bracket(Real x, Real fx, Real& xa, Real& fa, Real& xb, Real& fb) {
  if (fx * fb < 0) {
    xa = xb;
    fa = fb;
  } else {
    fa = fa * fb / (fb + fx);
  }
  xb = x;
  fb = fx;
}

/// Pegasus search of the elastic fraction a in (a0, a1) where the elastic path crosses f = 0
/// (f0 < 0 < f1).
template <class Pol = Production>
SCREE_HD inline Real yield_crossing(const Params& P, const Sym3& sig0, Real kappa, Real ope0, const Sym3& deps,
                                    Real a0, Real f0, Real a1, Real f1) {
  Sym3 tmp;
  for (int it = 0; it < 60; ++it) {
    const Real a = pegasus_point(a0, f0, a1, f1);
    const Real fa = elastic_path_yield<Pol>(P, sig0, kappa, ope0, deps, a, tmp);
    if (fabs(fa) <= kFtol) return a;
    pegasus_bracket(a, fa, a0, f0, a1, f1);
    if (fabs(a1 - a0) < Real(1e-14)) break;
  }
  return fmin(a0, a1) > 0 ? fmin(a0, a1) : Real(0);
}

/// Apex branch: the increment deps from the stress-free apex (sigma = 0), e_mid the void ratio
/// of the elastic predictor (mid-increment), e1 at the end. An extension separates (sigma = 0,
/// the deviatoric strain is plastic); a compression rebuilds stress by the elastic trial from
/// zero, returned radially in the deviatoric plane (constant p) onto the cone. Isochoric shear
/// keeps the point stress-free. Does not update v.e.
template <class Pol = Production>
SCREE_HD inline void apex_update(const Params& P, Sym3& sig, Vars& v, const Sym3& deps, Real e_mid, Real e1) {
  Sym3 st;
  if (!elastic_predictor<Pol>(P, Sym3::zero(), e_mid, deps, st)) {
    separate(sig, v, deps, 1);
    return;
  }
  const Invariants iv = invariants(st);
  const Real H = hardening(P, peak_ratio<Pol>(P, e1, iv.p), v.kappa);
  const Real qt = H * lode_g<Pol>(P, iv.S) * iv.p;
  if (iv.q > qt && iv.q > 0) {  // return radially in the deviatoric plane at constant p
    const Real dq = iv.q - qt;
    const Real G = P.rG * bulk_modulus<Pol>(P, e1, iv.p);
    st = from_p_s(iv.p, iv.s * (qt / iv.q));
    v.kappa += dq / (3 * G);
    v.epsEq += dq / (3 * G);
  }
  sig = st;
}

/// One modified-Euler (Heun) substep of size x (fraction of the plastic part drem) from
/// (sig, kappa) at void ratio ea: the first rate is r1u (for the whole of drem) scaled by x,
/// the second is evaluated at the Euler end state. Returns false when the second rate cannot be
/// evaluated (the Euler end state has p <= p_apex); sn, kn are then the Euler end state.
template <class Pol = Production>
SCREE_HD inline bool heun_substep(const Params& P, const Sym3& sig, Real kappa, const Rate& r1u, const Sym3& drem,
                                  Real x, Real eb, Real de, Rate& r1, Rate& r2, Sym3& sn, Real& kn) {
  r1.dsig = r1u.dsig * x;
  r1.dkappa = r1u.dkappa * x;
  r1.deq = r1u.deq * x;
  r1.num = r1u.num * x;
  sn = sig + r1.dsig;
  kn = kappa + r1.dkappa;
  if (!plastic_rate<Pol>(P, sn, kn, eb, drem * x, de, r2)) return false;
  sn = sig + (r1.dsig + r2.dsig) * Real(0.5);
  kn = kappa + Real(0.5) * (r1.dkappa + r2.dkappa);
  return true;
}

/// Sloan et al. (2001)'s factor for the next substep size after one with local error R,
/// 0.9 sqrt(STOL/R); the callers bound it: at least 0.1 after a rejection, at most 1.1 after
/// an acceptance.
SCREE_HD inline Real substep_factor(const Params& P, Real R) { return Real(0.9) * sqrt(P.stol / R); }

/// Local error estimate of a Heun substep (Sloan et al. 2001): relative to max(|sigma|, s_e).
SCREE_HD inline Real heun_error(const Params& P, const Rate& r1, const Rate& r2, const Sym3& sn, Real kn) {
  // Relative error with a floor of 1e-3 p_at (~100 Pa): near a free surface the
  // stress is a few Pa and each MPM increment changes it by as much again, so a
  // purely relative error asked for hundreds of substeps per update there while
  // the absolute error (stol x 100 Pa = 0.01 Pa at 1e-4) is far below anything
  // the flow can feel. Measured on the C-1 column collapse: 5x fewer substeps.
  const Real es = norm(r2.dsig - r1.dsig) / fmax(norm(sn), P.serr);
  const Real ek = fabs(r2.dkappa - r1.dkappa) / (kn + P.kp);
  return Real(0.5) * fmax(es, ek);
}

/// The implicit return of a stiff substep in the p-q plane: the plastic multiplier x = d eps_d^p
/// (= d kappa) that brings the elastic trial (p_t, q_t) back onto the yield surface, with the
/// moduli K, G = rG K, the ratios M_p, M_pt and g(theta) frozen at the trial (backward Euler,
/// the flow evaluated at the end state, where q/(p g) = H):
///   q(x) = q_t - 3G x,   p(x) = p_t - K d x,   d = A_d (M_pt - H(x))          eqs. (13), (15)
///   H(x) = M_p (kappa + x)/(k_p + kappa + x)                                     eq. (14)
///   phi(x) = q(x) - H(x) g p(x) = 0                                             eq. (14)
/// (the flow is radial in the deviatoric plane, so the Lode angle stays the trial's).
struct StiffReturn {
  Real pt, qt, G3, KAd, Mp, Mpt, g, kappa, kp;  ///< KAd = K A_d
  SCREE_HD Real H(Real x) const { return Mp * (kappa + x) / (kp + kappa + x); }
  SCREE_HD Real p(Real x) const { return p(x, H(x)); }
  SCREE_HD Real phi(Real x) const {
    const Real h = H(x);
    return qt - G3 * x - h * g * p(x, h);
  }

 private:
  SCREE_HD Real p(Real x, Real h) const { return pt - KAd * (Mpt - h) * x; }
};

/// Whether the stiff remainder drem of an update from sig (void ratio e) may be done by the
/// implicit returns (integrate(), README step 5), as the margin by which the plastic contraction
/// outweighs the volumetric compression of drem; below 0: not at all.
/// - the state must be looser than critical, e >= e_c(p) (eq. 16): then M_pt >= M_c >= M_p
///   (eqs. 17-18) and the flow contracts (d >= 0, eq. 15) at every stress ratio the yield surface
///   allows, whatever the hardening (denser, dilatancy can build p by orders of magnitude along
///   the path, which returns with moduli frozen at the trial do not follow);
/// - margin = A_d (M_pt - M_p) eps_d(drem) / max(-tr drem, 0): the contraction at its slowest
///   over the elastic compression. The caller asks for 1 (p stays bounded: the balance of the
///   two near the apex, or a fall to it), and before it lets a return separate the point either
///   p <= p_min, where K ~ (p + p_min)^n hardly varies along the path and the frozen moduli are
///   all but exact, or 1.25 (where the two nearly balance at a larger p, whether the path falls
///   to the apex depends on how K varies along it).
template <class Pol = Production>
SCREE_HD inline Real stiff_return_margin(const Params& P, const Sym3& sig, Real e, const Sym3& drem) {
  const Real p = mean_pressure(sig);
  if (!(p > P.papex)) return -1;
  const Ratios R = ratios<Pol>(P, e, p);
  if (!(R.Mpt >= R.Mp)) return -1;  // denser than critical
  const Real contraction = P.Ad * (R.Mpt - R.Mp) * equivalent_deviatoric_strain(drem);
  const Real compression = fmax(-drem.trace(), Real(0));
  return contraction >= Real(1e300) * compression ? Real(1e300) : contraction / compression;
}
inline constexpr Real kStiffMargin = 1;        ///< stiff_return_margin() needed for the returns
inline constexpr Real kStiffApexMargin = 1.25;  ///< ... and for a return to separate a point at p > p_min

/// One stiff substep (integrate(), README step 5): the elastic predictor over d from sig at the
/// void ratio e_mid, then the implicit return above, solved for x in (0, q_t/3G) by the Pegasus
/// method (phi(0) > 0 outside the surface, phi(q_t/3G) = -H g p < 0 while p > 0), then the drift
/// correction of the substepping. Returns false (nothing changed) when the substep reaches the
/// apex: the trial separates, or p(x) would reach p_apex before q/(p g) comes down to H.
template <class Pol = Production>
SCREE_HD inline bool stiff_substep(const Params& P, Sym3& sig, Vars& v, Real e_mid, Real eb, const Sym3& d) {
  Sym3 st;
  if (!elastic_predictor<Pol>(P, sig, e_mid, d, st)) return false;
  const Invariants iv = invariants(st);
  if (!(iv.p > P.papex)) return false;
  const Ratios R = ratios<Pol>(P, eb, iv.p);
  const Real K = bulk_modulus<Pol>(P, eb, iv.p);
  const StiffReturn ret{iv.p, iv.q, 3 * P.rG * K, K * P.Ad, R.Mp, R.Mpt, lode_g<Pol>(P, iv.S), fmax(v.kappa, Real(0)),
                        P.kp};
  Real xa = 0, fa = ret.phi(0);
  Real x = 0;
  if (fa > 0) {  // plastic: locate the root of phi in (0, q_t/3G)
    Real xb = iv.q / ret.G3, fb = ret.phi(xb);
    if (!(fb < 0) || !(ret.p(xb) > P.papex)) return false;
    const Real tol = Real(1e-12) * (iv.q + ret.g * ret.Mp * iv.p);
    for (int it = 0; it < 100; ++it) {
      x = pegasus_point(xa, fa, xb, fb);
      const Real fx = ret.phi(x);
      if (fabs(fx) <= tol || fabs(xb - xa) <= Real(1e-15) * xb) break;
      pegasus_bracket(x, fx, xa, fa, xb, fb);
    }
    const Real pe = ret.p(x);
    if (!(pe > P.papex)) return false;
    const Real qe = iv.q - ret.G3 * x;
    st = from_p_s(pe, iv.s * (fmax(qe, Real(0)) / iv.q));
    const Real dil = P.Ad * (R.Mpt - ret.H(x));
    v.kappa += x;
    v.epsEq += x * sqrt(dil * dil * (Real(2) / 9) + 1);  // sqrt(2/3 m:m) dlambda, as plastic_rate()
  }
  sig = st;
  bool projected;
  yield_and_project<Pol>(P, sig, eb, v.kappa, true, projected);  // drift correction
  return true;
}

/// What stiff_remainder() did.
enum StiffOutcome { kStiffDone, kStiffApex, kStiffDeclined };

/// The remainder (T, 1] of the plastic part drem of an update in kReturnSubsteps stiff substeps
/// (integrate(), README step 5). kStiffDone: sig, v and T = 1 updated. kStiffApex: a return
/// reached the apex (allowed when may_separate); sig, v and T are those after the returns before
/// it (the caller separates the rest). kStiffDeclined: p grew along the returns beyond twice its
/// start (+ STOL s_e), where frozen moduli are not accurate, or a return reached the apex where
/// that is not certain; nothing changed (the caller goes on with Heun substeps).
template <class Pol = Production>
SCREE_HD inline StiffOutcome stiff_remainder(const Params& P, Sym3& sig, Vars& v, Real ope0, Real tr, Real alpha,
                                             Real& T, const Sym3& drem, bool may_separate) {
  Sym3 s = sig;
  Vars w = v;
  Real Ts = T;
  const Real pcap = 2 * mean_pressure(sig) + P.stol * P.serr;
  for (int j = 1; j <= kReturnSubsteps; ++j) {
    const Real Tn = j == kReturnSubsteps ? Real(1) : T + (1 - T) * j / kReturnSubsteps;
    const Real em = void_ratio_at(ope0, tr, alpha + (1 - alpha) * Real(0.5) * (Ts + Tn));
    const Real eb = void_ratio_at(ope0, tr, alpha + (1 - alpha) * Tn);
    if (!stiff_substep<Pol>(P, s, w, em, eb, drem * (Tn - Ts))) {
      if (!may_separate) return kStiffDeclined;
      sig = s;
      v = w;
      T = Ts;
      return kStiffApex;
    }
    if (mean_pressure(s) > pcap) return kStiffDeclined;
    Ts = Tn;
  }
  sig = s;
  v = w;
  T = 1;
  return kStiffDone;
}

/// The opening of every stress update (integrate() and integrate_elastic() below): the void
/// ratios of the increment and the exact elastic trial from the start stress t.sig0.
/// Needs a finite t.sig0 and deps with p > p_apex (the caller handles the rest).
struct ElasticTrial {
  Real tr;         ///< tr deps (tension positive)
  Real ope0;       ///< 1 + e at the start
  Real e1;         ///< e at the end of the increment
  Real f0;         ///< yield function at the (projected) start stress (integrate() only)
  Sym3 sig0;       ///< start stress (integrate(): after the projection)
  Sym3 sig_tr;     ///< elastic trial stress at the end
  Real ftr;        ///< yield function at sig_tr (0 when it separates)
  bool separates;  ///< the trial ends in tension or at the apex: the point separates
  bool elastic;    ///< the whole increment is elastic: sig_tr is the answer
  PointRatios at0;  ///< g(theta) and M_p's parts at (sig0, e) (integrate() only)
};
template <class Pol = Production>
SCREE_HD inline void elastic_trial_from_start(const Params& P, const Vars& v, const Sym3& deps, ElasticTrial& t) {
  t.tr = deps.trace();
  t.ope0 = 1 + v.e;
  Real e_mid;
  void_ratios_mid_end(t.ope0, t.tr, e_mid, t.e1);
  // An extension whose elastic trial ends at the apex (p <= p_apex, where yield() no longer
  // bounds q) separates like one that would end in tension: otherwise a small stress rebuilt at
  // the apex could be pulled back to p ~ 0 with its deviator kept (q >> p; found by the fuzz test).
  t.separates = !elastic_predictor<Pol>(P, t.sig0, e_mid, deps, t.sig_tr) ||
                !(mean_pressure(t.sig_tr) > P.papex);
  t.ftr = t.separates ? Real(0) : yield<Pol>(P, t.sig_tr, t.e1, v.kappa);
  t.elastic = !t.separates && t.ftr <= kFtol;
}
/// integrate()'s opening: the start stress first brought back onto the yield surface when it
/// lies outside (f0 > kFtol), e.g. an initial or prescribed stress from elsewhere.
template <class Pol = Production>
SCREE_HD inline ElasticTrial elastic_trial(const Params& P, const Sym3& sig, const Vars& v, const Sym3& deps) {
  ElasticTrial t;
  t.sig0 = sig;
  bool projected;
  t.f0 = yield_and_project<Pol>(P, t.sig0, v.e, v.kappa, false, projected, &t.at0);
  if (projected) t.f0 = 0;
  elastic_trial_from_start<Pol>(P, v, deps, t);
  return t;
}

/// The common cheap case of integrate(), alone: when the increment is elastic from a stressed
/// state, updates sig and v as integrate() would and returns true; otherwise (apex,
/// separation, plastic loading, non-finite input) returns false and changes nothing. The GPU
/// kernels run it first over all points and integrate() only over the others, so that the
/// common path runs in a fraction of the registers (docs/performance.md, entry 13).
///
/// It takes the start stress as admissible (f <= kFtol) and skips integrate()'s start check,
/// a full yield evaluation, a seventh of the 2D elastic kernel (performance log, entry 19):
/// every state integrate() leaves is admissible at its own (sig, e, kappa), and the next step
/// starts from the same values up to the round-off of the co-rotation. The two paths differ
/// only for a start outside the surface whose trial ends inside; then integrate() starts the
/// trial from the start scaled back onto the surface, this from the start itself, and both
/// end admissible. From an integrator's own state that needs a start f within round-off
/// above kFtol (1e-9): a difference of at most 1e-9 p g in q.
template <class Pol = Production>
SCREE_HD inline bool integrate_elastic(const Params& P, Sym3& sig, Vars& v, const Sym3& deps) {
  if (!finite_sym(sig) || !finite_sym(deps) || !(mean_pressure(sig) > P.papex)) return false;
  ElasticTrial t;
  t.sig0 = sig;
  elastic_trial_from_start<Pol>(P, v, deps, t);
  if (!t.elastic) return false;
  sig = t.sig_tr;
  v.e = t.e1;
  return true;
}

/// One stress update of the frictional model: sig (tension positive) and the internal
/// variables v over the strain increment deps. Always returns a defined state: p >= 0,
/// no tension, finite values.
template <class Pol = Production>
SCREE_HD inline void integrate(const Params& P, Sym3& sig, Vars& v, const Sym3& deps) {
  if (!finite_sym(sig)) sig = Sym3::zero();
  if (!finite_sym(deps)) {  // nothing sensible to integrate
    v.e = fmax(v.e, Real(1e-6));
    return;
  }
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  const Sym3 sig_in = sig;
  const Vars v_in = v;
#endif
  if (!(mean_pressure(sig) > P.papex)) {
    // ---- apex: stress-free point (after separation or at a free surface)
    const Real tr = deps.trace();
    Real e_mid, e1;
    void_ratios_mid_end(1 + v.e, tr, e_mid, e1);
    apex_update<Pol>(P, sig, v, deps, e_mid, e1);
    v.e = e1;
    return;
  }
  const ElasticTrial t = elastic_trial<Pol>(P, sig, v, deps);
  const Real tr = t.tr, ope0 = t.ope0, e1 = t.e1, f0 = t.f0;
  const Sym3& sig_tr = t.sig_tr;
  sig = t.sig0;
  if (t.separates) {
    separate(sig, v, deps, 1);
    v.e = e1;
    return;
  }
  if (t.elastic) {  // elastic: the common cheap path
    sig = sig_tr;
    v.e = e1;
    return;
  }
  const Real ftr = t.ftr;
  bool projected;
  // ---- elastic fraction alpha of the increment
  Real alpha = 0;
  Rate r1u;               // rate at the start of the current substep for the whole remaining
  bool have_r1u = false;  // increment (linear in it: reused, scaled, after a rejection)
  if (f0 < -kFtol) {
    alpha = yield_crossing<Pol>(P, sig, v.kappa, ope0, deps, 0, f0, 1, ftr);
  } else {
    Rate r0;
    const bool ok0 = plastic_rate<Pol>(P, sig, v.kappa, v.e, deps, ope0 * expm1(tr), r0, &t.at0);
    if (ok0 && r0.num >= 0) {
      r1u = r0;  // loading from the start: this is the first Euler rate
      have_r1u = true;
    } else if (ok0) {
      // elastic unloading first, re-yielding later in the increment: find a point inside
      Sym3 tmp;
      Real alo = -1, flo = 0;
      for (int j = 1; j < 10; ++j) {
        const Real a = Real(0.1) * j;
        const Real fa = elastic_path_yield<Pol>(P, sig, v.kappa, ope0, deps, a, tmp);
        if (fa < -kFtol) {
          alo = a;
          flo = fa;
        } else if (alo > 0) {
          break;
        }
      }
      if (alo > 0) alpha = yield_crossing<Pol>(P, sig, v.kappa, ope0, deps, alo, flo, 1, ftr);
    }
  }
  if (alpha > 0) {
    Sym3 sa;
    if (elastic_predictor<Pol>(P, sig, void_ratio_at(ope0, tr, Real(0.5) * alpha), deps * alpha, sa)) sig = sa;
  }
  // ---- plastic part: modified Euler with local error control (Sloan et al. 2001)
  const Sym3 drem = deps * (1 - alpha);
  Real T = 0, dT = 1, dT_relaxed = -1;
  Real ea = void_ratio_at(ope0, tr, alpha);  // e at the start of the substep (the last eb)
  // The local error the control accepts near zero stress, where the floor s_e makes it absolute:
  // STOL x s_e (0.1 Pa with STOL = 1e-3).
  const Real snear = P.stol * P.serr;
  bool at_apex = false;  // the path has reached the stress-free apex: the remainder is done there
  bool stiff_tried = false;  // implicit returns tried for the remainder (README step 5), once
  bool apex_searched = false;  // the crossing of the apex searched (diagnostics only)
  PointRatios at;              // g(theta) and M_p's parts at (sig, ea) from the last drift correction
  int n = 0;
  while (T < 1) {
    ++n;
    if (Pol::stiff_returns && !stiff_tried && n > kStiffAfter && 1 - T > kStiffRemaining * dT) {
      // ---- a stiff remainder: the substep the error control asks for is set by the elastic
      // stiffness (about p/(3G |de_d|): hundreds of substeps near the apex, or where M_p is
      // tiny at a large void ratio), not by the curvature of the path.
      stiff_tried = true;
      const Real margin = stiff_return_margin<Pol>(P, sig, ea, drem);
      const StiffOutcome o = margin >= kStiffMargin
                                 ? stiff_remainder<Pol>(P, sig, v, ope0, tr, alpha, T, drem,
                                                   margin >= kStiffApexMargin || mean_pressure(sig) <= P.pmin)
                                 : kStiffDeclined;
      if (o == kStiffDone) break;
      if (o == kStiffApex) {
        at_apex = true;
        break;
      }
    }
    // bounded work: after kMaxSubsteps substeps the error control is switched off and the
    // substep is not allowed below 1/kMaxSubsteps of what then remained; after 3 kMaxSubsteps
    // the remainder is done in one step.
    const bool relaxed = n > kMaxSubsteps;
    if (relaxed && dT_relaxed < 0) dT_relaxed = (1 - T) / kMaxSubsteps;
    if (relaxed) dT = fmin(fmax(dT, dT_relaxed), 1 - T);
    if (n > 3 * kMaxSubsteps) dT = 1 - T;
    const Real eb = void_ratio_at(ope0, tr, alpha + (1 - alpha) * (T + dT));
    if (!have_r1u)
      have_r1u = plastic_rate<Pol>(P, sig, v.kappa, ea, drem, (1 + ea) * expm1(tr * (1 - alpha)), r1u, &at);
    Rate r1, r2;
    Sym3 sn = sig;
    Real kn = v.kappa, R = Real(1e300);
    const bool ok = have_r1u && heun_substep<Pol>(P, sig, v.kappa, r1u, drem, dT, eb, eb - ea, r1, r2, sn, kn);
    if (ok) R = heun_error(P, r1, r2, sn, kn);
    const bool reject = R > P.stol && !relaxed && dT > kMinSubstep;
    // A Heun end state beyond the apex from a substep whose error fails the test does not say
    // that the path reaches the apex, only that the substep is too coarse (the Euler rate,
    // extrapolated, overshoots): rejected below like any other (README step 4). Searching its
    // crossing cost 8 rate evaluations for nothing on grains that extend from tens of Pa to a
    // few (performance log, entry 21).
    if ((!ok || !(mean_pressure(sn) > P.papex)) && !(reject && R < Real(1e299) && norm(sig) > snear))
      R = Real(1e300);
    if (!(R < Real(1e299))) {
      // p would drop to zero within the substep (Heun or Euler end state at p <= p_apex): the
      // path reaches the stress-free apex. This used to cut dT by 10 (regrowing by 1.1 per
      // accepted substep): on the C-2 column collapse, grains at a few tenths of a Pa that
      // load towards the apex then took 1,000-3,000 substeps in one update (93,163 of the
      // 93,320 rejections in such updates were these cuts) and separated in the end all the
      // same, and on the GPU a step lasts as long as its slowest update. Instead:
      const Real ph = mean_pressure(sn);
      if (!have_r1u || (ph <= P.papex && (norm(sig) <= snear || n > 3 * kMaxSubsteps))) {
        // - already within the error the control accepts per substep (STOL x s_e) of the
        //   apex, and heading there: finish at the apex (also when the rates fail at sig, or
        //   when the work bound is spent). Only here, on the way to the apex: a grain being
        //   compressed from a small stress takes the ordinary path and builds stress.
        at_apex = true;
        break;
      }
      if (!(ph <= P.papex)) {  // a rate could not be evaluated (not finite): smaller substep
        if (dT > kMinSubstep && n <= 3 * kMaxSubsteps) {
          dT = fmax(Real(0.1) * dT, kMinSubstep);
          continue;
        }
        at_apex = true;
        break;
      }
      // - otherwise locate the crossing: Pegasus on the substep size x in (0, dT) with the
      //   pressure of the Heun end state as the function, aiming a little above zero (pt).
      //   A Heun state within STOL x s_e of the apex whose local error passes the usual test
      //   is accepted, and the remainder done at the apex; one whose error fails gives the
      //   next substep size (Sloan's rule); with no such state after kApexIter evaluations the
      //   substepping goes on from the largest size with p > pt at its end.
      const Real pt = P.papex + Real(0.25) * snear;
      Real xa = 0, ha = mean_pressure(sig) - pt, xb = dT, hb = ph - pt, xpos = 0, xnext = -1;
      apex_searched = true;
      for (int it = 0; it < kApexIter; ++it) {
        ++n;  // one rate evaluation, like a rejected substep (bounded work)
        const Real x = pegasus_point(xa, ha, xb, hb);
        if (!(x > 0 && x < dT)) break;
        const Real ex = void_ratio_at(ope0, tr, alpha + (1 - alpha) * (T + x));
        const bool okx = heun_substep<Pol>(P, sig, v.kappa, r1u, drem, x, ex, ex - ea, r1, r2, sn, kn);
        const Real px = mean_pressure(sn);
        if (okx && px > P.papex) {
          const Real Rx = heun_error(P, r1, r2, sn, kn);
          if (Rx > P.stol && !relaxed) {
            // a substep of this size is too coarse to say where the path meets the apex (its
            // Euler rate, extrapolated, overshoots), at the crossing or short of it: the next
            // size by the error control, as after any rejection (README step 4)
            xnext = x * fmax(substep_factor(P, Rx), Real(0.1));
            break;
          }
          if (norm(sn) <= snear) {  // the crossing, to within what the error control accepts
            sig = sn;
            v.kappa = kn;
            v.epsEq += Real(0.5) * (r1.deq + r2.deq);
            T += x;
            ea = ex;
            at_apex = true;
            break;
          }
          xpos = fmax(xpos, x);
        }
        pegasus_bracket(x, px - pt, xa, ha, xb, hb);
      }
      if (at_apex) break;
      dT = fmax(xnext > 0 ? xnext : (xpos > 0 ? xpos : Real(0.1) * dT), Real(1e-3) * kMinSubstep);
      continue;
    }
    if (reject) {  // smaller substep (Sloan et al. 2001)
      dT = fmax(dT * fmax(substep_factor(P, R), Real(0.1)), kMinSubstep);
      continue;
    }
    sig = sn;  // accept
    have_r1u = false;
    v.kappa = kn;
    v.epsEq += Real(0.5) * (r1.deq + r2.deq);
    T += dT;
    ea = eb;
    yield_and_project<Pol>(P, sig, eb, v.kappa, true, projected, &at);  // drift correction
    if (T >= 1 - Real(1e-12)) break;
    const Real fac = R > 0 ? fmin(substep_factor(P, R), Real(1.1)) : Real(1.1);
    dT = fmin(fmax(dT * fac, kMinSubstep), 1 - T);
  }
#if defined(SCREE_SIMSAND_REPORT_SUBSTEPS)
  if (n > SCREE_SIMSAND_REPORT_SUBSTEPS)
    printf("simsand-substeps %d apex %d sig %.17g %.17g %.17g %.17g %.17g %.17g e %.17g kappa %.17g "
           "deps %.17g %.17g %.17g %.17g %.17g %.17g\n",
           n, at_apex ? 1 : 0, sig_in[0], sig_in[1], sig_in[2], sig_in[3], sig_in[4], sig_in[5], v_in.e, v_in.kappa,
           deps[0], deps[1], deps[2], deps[3], deps[4], deps[5]);
#endif
  // paths: 1 implicit returns tried, 2 the apex crossing searched, 4 the remainder at the apex
  diag::report_work(unsigned(n), (stiff_tried ? 1u : 0u) | (apex_searched ? 2u : 0u) | (at_apex ? 4u : 0u));
  if (at_apex) {
    // the remainder of the increment at the apex: the point separates (sigma = 0, the
    // deviatoric strain of the remainder is plastic: kappa and epsEq grow); the next update
    // starts from the apex branch. Not the apex branch over the remainder: its one elastic trial
    // from zero rebuilds K |tr deps| at once where the converged path (many small increments)
    // stays at the apex, dragged back by the contractive flow (replayed C-2 updates: 25-60 Pa
    // instead of 0).
    separate(sig, v, drem, 1 - fmin(fmax(T, Real(0)), Real(1)));
  }
  v.e = e1;
  if (!finite_sym(sig) || !(mean_pressure(sig) >= 0)) sig = Sym3::zero();
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

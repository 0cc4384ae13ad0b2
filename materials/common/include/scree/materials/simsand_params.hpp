// SIMSAND-type critical-state frictional model: its constants.
//
// Params (what the kernels read, with the derived constants), Vars (the internal variables
// integrated with the stress), Constants (the constants by name, as the dictionary gives
// them: simsand_spec.hpp) and the evaluation policies. "eq. N" is the phase-transition
// paper (Feng, Liang, Yin & Hu 2025, IJNAMG); materials/simsand/README.md lists the
// parameters and every decision. The formulas: simsand_formulas.hpp; the stress
// integration: simsand_integrator.hpp; all of it: simsand_model.hpp.
//
// Units: SI (stresses and pressures in Pa), angles in radians except phi_c in Constants
// (degrees, as the dictionary gives it).
#pragma once

#include <cmath>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"

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
  int nmax;      ///< the bound on an update's work: substeps with error control (bound_substep)
};

/// The default of `maxSubsteps` (Params::nmax): above what the paper cases' updates take at
/// their tolerance (1e-2); at tighter tolerances a few updates reach it.
inline constexpr int kDefaultMaxSubsteps = 1000;

/// Internal variables integrated together with the stress.
struct Vars {
  Real e;      ///< void ratio
  Real kappa;  ///< deviatoric plastic strain eps_d^p (hardening variable, eq. 14)
  Real epsEq;  ///< equivalent plastic strain integral of sqrt(2/3 deps^p : deps^p)
};

/// How the model is evaluated, fixed at compile time: the plugins' kernels carry neither a
/// field nor a branch for it. Every function of the formulas and the integrator that depends on
/// it is a template on this policy, defaulting to Production; the tests instantiate the references.
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
  int maxSubsteps = kDefaultMaxSubsteps;  ///< substeps with error control per update (then relaxed)
};

/// Host: Params, with the derived constants, from the named constants.
inline Params make_params(const Constants& k) {
  Params P{};
  P.K0 = k.K0;
  P.nu = k.nu;
  P.n = k.n;
  P.pat = k.pat;
  const Real phi = k.phic_deg * kPi / 180;
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
  P.nmax = k.maxSubsteps;
  return P;
}

}  // namespace scree::materials::simsand

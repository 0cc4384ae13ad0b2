// Shared parameter sets (Feng et al. 2025, Tables 1-3) and small drivers for the material tests.
// Params are built directly (no dictionaries), so these tests need only the headers.
#pragma once

#include <cmath>
#include <functional>

#include "kineticTheory/KineticTheory.hpp"
#include "phaseTransition/PhaseTransition.hpp"
#include "scree/core/constants.hpp"
#include "scree/material/material.hpp"
#include "simsand/Simsand.hpp"

namespace scree::materials::mtest {

/// Table 1 (frictional element tests, Fig. 4).
inline simsand::Params table1(bool lode = true, double stol = 1e-4) {
  return simsand::make_params({.K0 = 150, .nu = 0.22, .n = 0.6, .pat = 101300, .phic_deg = 30, .eref = 0.937,
                               .lambda = 0.022, .xi = 0.71, .Ad = 4, .kp = 0.001, .np = 1, .nd = 1, .pmin = 1.0,
                               .stol = stol, .lode = lode});
}
/// Table 3, column-collapse column (frictional part).
inline simsand::Params table3_collapse_f() {
  return simsand::make_params({.K0 = 120, .nu = 0.2, .n = 0.5, .pat = 101300, .phic_deg = 19.8, .eref = 0.977,
                               .lambda = 0.0596, .xi = 0.365, .Ad = 0.7, .kp = 0.0044, .np = 2.4, .nd = 2.9,
                               .pmin = 1.0, .stol = 1e-4, .lode = true});
}
/// Table 3, element-test column (frictional part).
inline simsand::Params table3_element_f() {
  return simsand::make_params({.K0 = 120, .nu = 0.235, .n = 0.5, .pat = 101300, .phic_deg = 23, .eref = 0.910,
                               .lambda = 0.122, .xi = 0.71, .Ad = 0.5, .kp = 0.001, .np = 1, .nd = 1, .pmin = 1.0,
                               .stol = 1e-4, .lode = true});
}
/// Collisional constants from (rho_p, d, V_sd, V_m, eps_n, mu_p).
inline kt::Params collisional(double rho_p, double d, double Vsd, double Vm, double eps_n, double mu_p,
                              bool zeta1 = true, double g0max = 1000) {
  return kt::make_params(kt::Constants{.rho_p = rho_p,
                                       .d = d,
                                       .Vsd = Vsd,
                                       .Vm = Vm,
                                       .eps = kt::effective_restitution(eps_n, mu_p),
                                       .Vcap = kt::cap_solid_fraction(Vsd, Vm, g0max),
                                       .Vmin = 1e-3,
                                       .zeta1 = zeta1 ? 1.0 : 0.0});
}
/// Table 2 (collisional element tests, Fig. 5).
inline kt::Params table2() { return collisional(1500, 1e-3, 0.6, 0.4, 0.6, 0.2); }
/// Table 3 column collapse (collisional part): e_sd = 0.62.
inline kt::Params table3_collapse_c() { return collisional(2650, 1.25e-3, 1 / 1.62, 0.4, 0.6, 0.2); }

inline StrainIncrement shear_increment(double dgamma, double dt, bool spin = true) {
  StrainIncrement inc;
  inc.deps = Sym3::zero();
  inc.deps[3] = 0.5 * dgamma;
  inc.spin = Spin3{spin ? 0.5 * dgamma : 0.0, 0, 0};
  inc.dt = dt;
  inc.J = 1;
  return inc;
}

inline Sym3 k0_stress(double sv, double K0) { return Sym3{{-K0 * sv, -sv, -K0 * sv, 0, 0, 0}}; }
inline Sym3 iso_stress(double p) { return Sym3{{-p, -p, -p, 0, 0, 0}}; }

inline bool finite(const Sym3& s) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(s[i])) return false;
  return true;
}

}  // namespace scree::materials::mtest

// Parameters of the SIMSAND-type frictional model: the dictionary entries and their reader,
// shared by every material that uses the model (simsand, phaseTransition). Host code only.
// The model itself: simsand_model.hpp.
#pragma once

#include <string>

#include "scree/materials/simsand_model.hpp"
#include "scree/params/spec.hpp"

namespace scree::materials::simsand {

/// Declare the frictional parameters (eqs. 12-18 of Feng et al. 2025).
inline void add_frictional_spec(ParamSpec& s) {
  s.scalar("referenceBulkModulus", "-", "K_0: dimensionless reference bulk modulus (eq. 13)").positive();
  s.scalar("poissonRatio", "-", "nu: Poisson's ratio; G = 3(1-2nu)/(2(1+nu)) K").range(0.0, 0.5).open_max();
  s.scalar("elasticExponent", "-", "n: pressure exponent of the stiffness (eq. 13)").range(0.0, 0.95);
  s.scalar("atmosphericPressure", "Pa", "p_at: reference pressure of eqs. (13) and (16)")
      .positive()
      .default_value(101300.0);
  s.scalar("criticalFrictionAngle", "deg", "phi_c: critical-state friction angle (M_c = 6 sin/(3 - sin))")
      .range(0.0, 60.0)
      .open_min();
  s.scalar("referenceCriticalVoidRatio", "-", "e_ref: critical void ratio at p = 0 (eq. 16)").positive();
  s.scalar("criticalStateLambda", "-", "lambda: slope parameter of the critical-state line (eq. 16)")
      .non_negative();
  s.scalar("criticalStateXi", "-", "xi: nonlinearity of the critical-state line (eq. 16)").positive();
  s.scalar("dilatancyConstant", "-", "A_d: stress-dilatancy constant (eq. 15)").non_negative();
  s.scalar("plasticModulusConstant", "-", "k_p: hardening constant of eq. (14)").positive();
  s.scalar("peakStrengthExponent", "-", "n_p: interlocking exponent of the peak friction angle (eq. 17)")
      .non_negative();
  s.scalar("phaseTransformationExponent", "-",
           "n_d: interlocking exponent of the phase-transformation angle (eq. 18)")
      .non_negative();
  s.word("lodeDependence", "M(theta): 'sheng' (Mohr-Coulomb vertices, smooth) or 'none' (M_c everywhere)")
      .choices({"sheng", "none"})
      .default_value("sheng");
  s.scalar("minPressure", "Pa", "p_min: stiffness regularisation, K uses p + p_min (free surfaces)")
      .positive()
      .default_value(1.0);
  s.scalar("integrationTolerance", "-", "relative local error tolerance of the substepping")
      .range(1e-10, 1e-1)
      .default_value(1e-4);
}
inline Params read_frictional(const ParamReader& r) {
  return make_params(Constants{.K0 = r.scalar("referenceBulkModulus"),
                               .nu = r.scalar("poissonRatio"),
                               .n = r.scalar("elasticExponent"),
                               .pat = r.scalar("atmosphericPressure"),
                               .phic_deg = r.scalar("criticalFrictionAngle"),
                               .eref = r.scalar("referenceCriticalVoidRatio"),
                               .lambda = r.scalar("criticalStateLambda"),
                               .xi = r.scalar("criticalStateXi"),
                               .Ad = r.scalar("dilatancyConstant"),
                               .kp = r.scalar("plasticModulusConstant"),
                               .np = r.scalar("peakStrengthExponent"),
                               .nd = r.scalar("phaseTransformationExponent"),
                               .pmin = r.scalar("minPressure"),
                               .stol = r.scalar("integrationTolerance"),
                               .lode = r.word("lodeDependence") == "sheng"});
}

}  // namespace scree::materials::simsand

// Parameters of the SIMSAND-type frictional model: the dictionary entries and their reader,
// shared by every material that uses the model (simsand, phaseTransition). Host code only.
// The model itself: simsand_model.hpp.
#pragma once

#include <string>

#include "scree/materials/granular_spec.hpp"
#include "scree/materials/simsand_model.hpp"
#include "scree/params/spec.hpp"

namespace scree::materials::simsand {

/// Declare the frictional parameters (eqs. 12-18 of Feng et al. 2025). Each doc string gives
/// the typical values (the paper's Table 3: element test / column collapse / flume; Table 1
/// for Fig. 4) and each range what the model admits, so that `scree --list-plugins` shows
/// both and a value outside is refused with its file:line. The upper bounds lie far above
/// any sand's and catch a value in the wrong unit (kPa for Pa, the whole stiffness for K_0).
inline void add_frictional_spec(ParamSpec& s) {
  s.scalar("referenceBulkModulus", "-",
           "K_0: dimensionless reference bulk modulus (eq. 13); typical 100-200 for sands (Table 3: 120 / 120 / "
           "130; Table 1: 150)")
      .range(0.0, 1e4)
      .open_min();
  s.scalar("poissonRatio", "-",
           "nu: Poisson's ratio; G = 3(1-2nu)/(2(1+nu)) K; typical 0.2-0.25 (Table 3: 0.235 / 0.2 / 0.2)")
      .range(0.0, 0.5)
      .open_max();
  s.scalar("elasticExponent", "-",
           "n: pressure exponent of the stiffness (eq. 13); typical 0.5 (Table 3: 0.5 everywhere; Table 1: 0.6)")
      .range(0.0, 0.95);
  s.scalar("atmosphericPressure", "Pa",
           "p_at: reference pressure of eqs. (13) and (16), in Pa (the paper's 101.3 kPa is 101300)")
      .range(1e4, 1e6)
      .default_value(101300.0);
  s.scalar("criticalFrictionAngle", "deg",
           "phi_c: critical-state friction angle (M_c = 6 sin/(3 - sin)); typical 28-36 for sands (Table 3: 23 / "
           "19.8 / 38; Table 1: 30)")
      .range(0.0, 60.0)
      .open_min();
  s.scalar("referenceCriticalVoidRatio", "-",
           "e_ref: critical void ratio at p = 0 (eq. 16); typical 0.6-1.2 (Table 3: 0.910 / 0.977 / 0.977; "
           "Table 1: 0.937); at most 2, where eq. (13)'s F(e) is held")
      .range(0.0, 2.0)
      .open_min();
  s.scalar("criticalStateLambda", "-",
           "lambda: slope parameter of the critical-state line (eq. 16); typical 0.02-0.13 (Table 3: 0.122 / "
           "0.0596 / 0.0596; Table 1: 0.022)")
      .range(0.0, 1.0);
  s.scalar("criticalStateXi", "-",
           "xi: nonlinearity of the critical-state line (eq. 16); typical 0.3-0.8 (Table 3: 0.71 / 0.365 / 0.365; "
           "Table 1: 0.71)")
      .range(0.0, 1.0)
      .open_min();
  s.scalar("dilatancyConstant", "-",
           "A_d: stress-dilatancy constant (eq. 15); typical 0.4-1 (Table 3: 0.5 / 0.7 / 0.4; Table 1: 4)")
      .range(0.0, 10.0);
  s.scalar("plasticModulusConstant", "-",
           "k_p: hardening constant of eq. (14), the eps_d^p at which half of M_p is mobilised; typical 0.001-0.005 "
           "(Table 3: 0.001 / 0.0044 / 0.0044; Table 1: 0.001)")
      .range(0.0, 1.0)
      .open_min();
  s.scalar("peakStrengthExponent", "-",
           "n_p: interlocking exponent of the peak friction angle (eq. 17); typical 1-3 (Table 3: 1 / 2.4 / 2.4; "
           "Table 1: 1)")
      .range(0.0, 10.0);
  s.scalar("phaseTransformationExponent", "-",
           "n_d: interlocking exponent of the phase-transformation angle (eq. 18); typical 1-3 (Table 3: 1 / 2.9 / "
           "2.9; Table 1: 1)")
      .range(0.0, 10.0);
  s.word("lodeDependence", "M(theta): 'sheng' (Mohr-Coulomb vertices, smooth) or 'none' (M_c everywhere)")
      .choices({"sheng", "none"})
      .default_value("sheng");
  s.scalar("minPressure", "Pa",
           "p_min: stiffness regularisation, K uses p + p_min (free surfaces); far below p_at (at most 1 kPa)")
      .range(0.0, 1000.0)
      .open_min()
      .default_value(1.0);
  s.scalar("integrationTolerance", "-",
           "relative local error tolerance of the substepping; typical 1e-3 (1e-2 in the paper's column and flume "
           "cases)")
      .range(1e-10, 1e-1)
      .default_value(1e-4);
  s.integer("maxSubsteps",
            "the bound on one update's work: after this many substeps the error control is off and the rest "
            "takes at least 1/maxSubsteps of what remained, after 3x this many the rest is one substep (at most "
            "3 maxSubsteps + 1 in all). Updates that reach it are counted in the run's log. The default bounds "
            "only rare long chains; 8-16 bounds the cost of a flowing step (materials/simsand/README.md)")
      .range(2, 1e6)
      .default_value(kDefaultMaxSubsteps);
}

/// The initial void ratio e0 of a material built on the model (simsand, phaseTransition):
/// typical values and the range eq. (13)'s F(e) follows, written once for both.
inline void add_initial_void_ratio(ParamSpec& s, const char* what) {
  s.scalar("initialVoidRatio", "-",
           std::string("e0") + what +
               "; typical 0.6-1.1 (Table 3: 0.99-1.05 / 0.95 / 0.90; Fig. 4: 0.80-0.95); at most 2, where eq. "
               "(13)'s F(e) is held")
      .range(0.0, 2.0)
      .open_min();
}
/// The bound on an update's work, as the run's log names it (material.hpp, work_bound).
inline std::string work_bound(const Params& P) { return "maxSubsteps " + std::to_string(P.nmax); }

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
                               .lode = r.word("lodeDependence") == "sheng",
                               .maxSubsteps = static_cast<int>(r.integer("maxSubsteps"))});
}

}  // namespace scree::materials::simsand

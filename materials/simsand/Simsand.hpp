// simsand: SIMSAND-type critical-state frictional model (Feng et al. 2025 section 3.2, eqs. 12-18).
//
// Nonlinear elasticity K(e, p) (eq. 13), a Mohr-Coulomb-type yield surface with hyperbolic
// hardening towards the void-ratio dependent peak ratio M_p (eq. 14; M_p tends to M_c as
// e -> e_c), stress-dilatancy (eq. 15), a curved critical-state line (eq. 16) and the
// interlocking laws for the peak and phase-transformation friction angles (eqs. 17-18), 3D
// with a Lode-angle dependent M. The formulas (scree/materials/simsand_formulas.hpp) and the
// stress integration (simsand_integrator.hpp) live in materials/common, shared with
// phaseTransition; README.md lists the parameters and every decision.
//
// This is the purely frictional model that the paper compares with (section 4.1.3).
//
// Dispersed points: below a solid fraction V_min = 1/(1 + e) (minSolidFraction) the grains
// of a point no longer touch, so there is no contact network to carry a frictional stress:
// such a point carries none and sets no wave speed (README, "Dispersed points"). The same
// V_min and the same rule as phaseTransition's (kinetic_theory.hpp, dispersed()), so that
// the two models of the paper's comparison differ only in the collisional stress.
#pragma once

#include <cmath>
#include <string>

#include "scree/material/material.hpp"
#include "scree/materials/dispersed.hpp"
#include "scree/materials/simsand_model.hpp"
#include "scree/materials/simsand_spec.hpp"

namespace scree::materials {

struct Simsand {
  static constexpr const char* type_name = "simsand";

  struct Params {
    simsand::Params m;  ///< model constants
    Real rho_p;         ///< grain density [kg/m^3]
    Real e0;            ///< initial void ratio [-]
    Real Vmin = 0;      ///< smallest solid fraction of a contact network [-]; 0: none (dispersed())
  };
  struct State {
    Real e;      ///< void ratio [-]
    Real kappa;  ///< deviatoric plastic strain eps_d^p (hardening variable of eq. 14) [-]
    Real epsEq;  ///< equivalent plastic strain [-]
    Real rate;   ///< equivalent deviatoric strain rate of the last step [1/s]
  };

  static ParamSpec spec() {
    ParamSpec s(type_name,
                "SIMSAND-type critical-state frictional model (Feng et al. 2025 eqs. 12-18): nonlinear elasticity, "
                "hyperbolic hardening, stress-dilatancy, interlocking, Lode-angle dependence. Typical values: the "
                "paper's Table 3 (element test / column collapse / flume) and Table 1 (Fig. 4)");
    add_particle_density(s);
    simsand::add_frictional_spec(s);
    simsand::add_initial_void_ratio(s, "");
    add_min_solid_fraction(s,
                           "below this solid fraction 1/(1+e) a point is dispersed (its grains out of contact): it "
                           "carries no stress and sets no wave speed, as in phaseTransition");
    return s;
  }
  static Params read(const ParamReader& r) {
    Params p{};
    p.m = simsand::read_frictional(r);
    p.rho_p = r.scalar("particleDensity");
    p.e0 = r.scalar("initialVoidRatio");
    p.Vmin = r.scalar("minSolidFraction");
    return p;
  }
  static Real density(const Params& p) { return p.rho_p / (1 + p.e0); }

  static State initial_state(const Params& p, Sym3& sigma) {
    const simsand::Vars v = simsand::initial_vars(p.m, sigma, p.e0);
    return State{v.e, v.kappa, v.epsEq, 0};
  }

  /// Whether a point of void ratio e is dispersed: its solid fraction 1/(1+e) below V_min.
  /// (A stretched point's void ratio follows its volume: 1 + e = (1 + e0) J.)
  SCREE_HD static bool dispersed(const Params& p, Real e) { return dispersed_below(p.Vmin, e); }

  /// Returns whether the update reached the bound on its work (maxSubsteps).
  SCREE_HD static bool update(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    simsand::Vars v{s.e, s.kappa, s.epsEq};
    const bool bounded = simsand::integrate(p.m, sigma, v, inc.deps);
    result(p, s, sigma, v, inc);
    return bounded;
  }
  /// update() in turns (material.hpp): the integration in flight; the same result as update().
  using Work = simsand::Integration;
  SCREE_INLINE static bool update_begin(const Params& p, const State& s, const Sym3& sigma, const StrainIncrement& inc,
                                        Work& w) {
    w.sig = sigma;
    w.v = simsand::Vars{s.e, s.kappa, s.epsEq};
    return simsand::integrate_begin(p.m, w, inc.deps);
  }
  SCREE_INLINE static bool update_turn(const Params& p, Work& w) { return simsand::integrate_turn(p.m, w); }
  SCREE_INLINE static bool update_end(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc, Work& w) {
    const bool bounded = simsand::integrate_end(p.m, w);
    sigma = w.sig;
    result(p, s, sigma, w.v, inc);
    return bounded;
  }
  static std::string work_bound(const Params& p) { return simsand::work_bound(p.m); }
  /// The elastic case of update() alone (material.hpp: optional update_elastic).
  SCREE_HD static bool update_elastic(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    simsand::Vars v{s.e, s.kappa, s.epsEq};
    if (!simsand::integrate_elastic(p.m, sigma, v, inc.deps)) return false;
    result(p, s, sigma, v, inc);
    return true;
  }
  /// The state after an update (sigma, v) over inc, and no stress for a dispersed point.
  SCREE_HD static void result(const Params& p, State& s, Sym3& sigma, const simsand::Vars& v,
                              const StrainIncrement& inc) {
    commit(s, v, inc);
    sigma = sigma * (dispersed(p, s.e) ? Real(0) : Real(1));  // a select, not a branch
  }
  SCREE_HD static void commit(State& s, const simsand::Vars& v, const StrainIncrement& inc) {
    s.e = v.e;
    s.kappa = v.kappa;
    s.epsEq = v.epsEq;
    s.rate = inc.dt > 0 ? equivalent_deviatoric_strain(inc.deps) / inc.dt : Real(0);
  }

  /// The p-wave speed; none for a dispersed point (no contacts: the stiffness of eq. 13 at
  /// p_min and a density of 1e-3 of the grains' or less would otherwise set the step, one
  /// stretched point slowing the whole run by orders of magnitude; README, "Dispersed points").
  SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3& sigma, Real rho, Real) {
    const Real c = simsand::pwave_speed(p.m, s.e, pressure(sigma), rho);
    return dispersed(p, s.e) ? Real(0) : c;
  }

  static void describe(OutputFields<Simsand>& out) {
    out.state("voidRatio", &State::e, "-", "void ratio e");
    out.state("plasticStrain", &State::epsEq, "-", "equivalent plastic strain, integral of sqrt(2/3 deps^p:deps^p)");
    out.state("deviatoricPlasticStrain", &State::kappa, "-", "eps_d^p, the hardening variable of eq. (14)");
    out.state("deviatoricStrainRate", &State::rate, "1/s",
              "equivalent deviatoric strain rate sqrt(2/3 dev D:dev D) of the last step (gamma_dot/sqrt(3) in "
              "simple shear)");
    out.derived_tensor("frictionalStress", "Pa", "sigma_f (= sigma for this model), tension positive",
                       [](const Params&, const State&, const Sym3& sig) { return sig; });
    out.derived("frictionalPressure", "Pa", "p_f = -tr(sigma)/3 (compression positive)",
                [](const Params&, const State&, const Sym3& sig) { return pressure(sig); });
    out.derived("frictionalDeviatoricStress", "Pa", "q_f = sqrt(3/2 s:s)",
                [](const Params&, const State&, const Sym3& sig) { return deviatoric_stress(sig); });
    out.derived("criticalVoidRatio", "-", "e_c(p_f), eq. (16)", [](const Params& p, const State&, const Sym3& sig) {
      return simsand::critical_void_ratio(p.m, pressure(sig));
    });
    out.derived("elasticEnergy", "J/m^3",
                "elastic energy stored per volume, an estimate (eq. 13 is hypoelastic: simsand_model.hpp)",
                [](const Params& p, const State& s, const Sym3& sig) { return simsand::elastic_energy(p.m, s.e, sig); });
    out.derived("peakStressRatio", "-", "M_p (eq. 17, triaxial compression)",
                [](const Params& p, const State& s, const Sym3& sig) {
                  return simsand::ratios(p.m, s.e, pressure(sig)).Mp;
                });
    out.derived("phaseTransformationRatio", "-", "M_pt (eq. 18, triaxial compression)",
                [](const Params& p, const State& s, const Sym3& sig) {
                  return simsand::ratios(p.m, s.e, pressure(sig)).Mpt;
                });
  }
};

}  // namespace scree::materials

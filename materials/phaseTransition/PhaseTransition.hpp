// phaseTransition: frictional (SIMSAND-type) + collisional (kinetic theory) stresses in
// parallel (Feng, Liang, Yin & Hu 2025, IJNAMG, section 3, eq. 1):
//
//   sigma = sigma_f + sigma_col                                                     (eq. 1)
//
// Both parts see the same strain increment and share the void ratio e (1 + e follows the
// volume). sigma_f is integrated incrementally (simsand_integrator.hpp, eqs. 12-18) and stored in
// the state (co-rotated here with the step's spin, Hughes-Winget); sigma_col is recomputed
// every step from the granular temperature T and the strain rate D = deps/dt
// (kinetic_theory.hpp, eqs. 19-28), T being integrated exactly over the step.
//
// p and q outputs are compression positive. README.md lists the parameters and decisions.
#pragma once

#include <cmath>
#include <cstddef>

#include "scree/material/material.hpp"
#include "scree/materials/kinetic_theory.hpp"
#include "scree/materials/kinetic_theory_spec.hpp"
#include "scree/materials/simsand_model.hpp"
#include "scree/materials/simsand_spec.hpp"

namespace scree::materials {

struct PhaseTransition {
  static constexpr const char* type_name = "phaseTransition";
  /// update() builds sigma from the state (sigma_f + sigma_col) and never reads the stress
  /// it is given: the kernel skips loading and co-rotating it (particle_pass.hpp).
  static constexpr bool reads_stress = false;

  struct Params {
    simsand::Params f;  ///< frictional constants
    kt::Params c;       ///< collisional constants (with their prepared factors)
    Real e0;            ///< initial void ratio [-]
    Real T0;            ///< initial granular temperature [m^2/s^2]
  };
  struct State {
    Sym3 sigf;   ///< frictional stress sigma_f (tension positive) [Pa]
    Real e;      ///< void ratio [-]
    Real T;      ///< granular temperature [m^2/s^2]
    Real epsEq;  ///< equivalent plastic strain [-]
    Real kappa;  ///< deviatoric plastic strain eps_d^p (hardening variable) [-]
    Real rate;   ///< equivalent deviatoric strain rate sqrt(2/3 dev D:dev D) of the last step [1/s]
    Real trD;    ///< volumetric strain rate tr D of the last step (tension positive) [1/s]
  };
  /// sigma_f's yz and xz components stay zero in plane strain (2D): the kernels skip them.
  static constexpr unsigned plane_zero_slots = plane_tensor_slots(offsetof(State, sigf) / sizeof(Real));

  static ParamSpec spec() {
    ParamSpec s(type_name,
                "Phase-transition granular model (Feng et al. 2025): SIMSAND-type frictional stress + kinetic-theory "
                "collisional stress driven by the granular temperature, sigma = sigma_f + sigma_col (eq. 1). Typical "
                "values: the paper's Table 3 (element test / column collapse / flume)");
    kt::add_collisional_spec(s);  // includes particleDensity and initialGranularTemperature
    simsand::add_frictional_spec(s);
    simsand::add_initial_void_ratio(s, " (shared by both parts)");
    return s;
  }
  static Params read(const ParamReader& r) {
    Params p{};
    p.f = simsand::read_frictional(r);
    p.c = kt::read_collisional(r);
    p.e0 = r.scalar("initialVoidRatio");
    p.T0 = r.scalar("initialGranularTemperature");
    return p;
  }
  static Real density(const Params& p) { return p.c.rho_p / (1 + p.e0); }

  /// The initial stress is taken as total; sigma_f = sigma + p_col(e0, T0) I (sigma_col is
  /// isotropic at rest), then made admissible (no tension, on or inside the yield surface).
  static State initial_state(const Params& p, Sym3& sigma) {
    State s{};
    const kt::Coefficients c = coefficients(p, p.e0);
    const Sym3 scol = kt::collisional_stress(c, p.T0, Sym3::zero());
    Sym3 sf = sigma - scol;
    const simsand::Vars v = simsand::initial_vars(p.f, sf, p.e0);
    s.sigf = sf;
    s.e = v.e;
    s.T = p.T0;
    s.epsEq = v.epsEq;
    s.kappa = v.kappa;
    sigma = sf + scol;
    return s;
  }

  /// Returns whether the frictional update reached the bound on its work (maxSubsteps).
  SCREE_HD static bool update(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    return update_with<simsand::Production>(p, s, sigma, inc);
  }
  static std::string work_bound(const Params& p) { return simsand::work_bound(p.f); }
  /// update() with the frictional part evaluated under the policy Pol (simsand_params.hpp:
  /// the tests compare Production with the reference evaluations).
  template <class Pol>
  SCREE_HD static bool update_with(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    // frictional part: co-rotate the stored sigma_f (the framework rotated only sigma)
    Sym3 sf = corotate(s.sigf, inc.spin);
    simsand::Vars v{s.e, s.kappa, s.epsEq};
    const bool bounded = simsand::integrate<Pol>(p.f, sf, v, inc.deps);  // eqs. (12)-(18); updates e
    collisional(p, s, sf, v, sigma, inc);
    return bounded;
  }
  /// update() in turns (material.hpp): the frictional integration in flight (eqs. 12-18),
  /// then the collisional part at the end; the same result as update().
  using Work = simsand::Integration;
  template <class Pol = simsand::Production>
  SCREE_INLINE static bool update_begin(const Params& p, const State& s, const Sym3&, const StrainIncrement& inc,
                                        Work& w) {
    // frictional part: co-rotate the stored sigma_f (the framework rotated only sigma)
    w.sig = corotate(s.sigf, inc.spin);
    w.v = simsand::Vars{s.e, s.kappa, s.epsEq};
    return simsand::integrate_begin<Pol>(p.f, w, inc.deps);  // updates e
  }
  template <class Pol = simsand::Production>
  SCREE_INLINE static bool update_turn(const Params& p, Work& w) {
    return simsand::integrate_turn<Pol>(p.f, w);
  }
  SCREE_INLINE static bool update_end(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc, Work& w) {
    const bool bounded = simsand::integrate_end(p.f, w);
    collisional(p, s, w.sig, w.v, sigma, inc);
    return bounded;
  }
  /// The same when the frictional increment is elastic; false (nothing changed) otherwise
  /// (material.hpp: optional update_elastic).
  SCREE_HD static bool update_elastic(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    Sym3 sf = corotate(s.sigf, inc.spin);
    simsand::Vars v{s.e, s.kappa, s.epsEq};
    if (!simsand::integrate_elastic(p.f, sf, v, inc.deps)) return false;
    collisional(p, s, sf, v, sigma, inc);
    return true;
  }
  /// Store the frictional result (sf, v) and add the collisional part at the shared void ratio.
  SCREE_HD static void collisional(const Params& p, State& s, const Sym3& sf, const simsand::Vars& v, Sym3& sigma,
                                   const StrainIncrement& inc) {
    s.e = v.e;
    s.kappa = v.kappa;
    s.epsEq = v.epsEq;
    const Real inv_dt = inc.dt > 0 ? 1 / inc.dt : Real(0);
    const Sym3 D = inc.deps * inv_dt;
    const kt::Coefficients c = coefficients(p, s.e);
    const kt::RateInvariants ri = kt::rate_invariants(D);
    s.rate = sqrt(Real(2) / 3 * ri.dev2);
    s.trD = ri.tr;
    // Grains in free flight (kt::dispersed): no contact network and no collisional continuum,
    // so no stress of either kind; T is carried unchanged (no stress, no work). Selects, not
    // a branch: an early return made the register-capped elastic kernel spill.
    const bool flying = kt::dispersed(p.c, s.e);
    const Real T = kt::update_temperature(c, s.T, ri, inc.dt);  // eq. (27)
    s.T = flying ? s.T : T;
    const Real keep = flying ? Real(0) : Real(1);
    s.sigf = sf * keep;  // the frictional result, none for a dispersed point
    sigma = (sf + kt::collisional_stress(c, T, D)) * keep;  // eq. (1) with eq. (19)
  }

  /// The collisional coefficients (eqs. 20-28) at the void ratio e. update() and wave_speed()
  /// both call this, so that the compiler computes them once when the kernel asks for the
  /// speed right after the update.
  SCREE_HD static kt::Coefficients coefficients(const Params& p, Real e) {
    return kt::coefficients(p.c, kt::solid_fraction(p.c, e));
  }

  /// The energy the collisions dissipated over the step, per volume [J/m^3]: Gamma dt of
  /// eq. (28) at the step's end; none for a dispersed point (material.hpp, optional: the
  /// energy ledger's collisional term; the frictional dissipation is what is left of the
  /// stress work, plugins/functionObjects/Energies.hpp).
  SCREE_HD static Real collisional_dissipation(const Params& p, const State& s, const StrainIncrement& inc) {
    const kt::Coefficients c = coefficients(p, s.e);
    return kt::dispersed(p.c, s.e) ? Real(0) : kt::dissipation_rate(c, s.T, s.trD) * inc.dt;
  }

  SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3&, Real rho, Real h) {
    const kt::Coefficients c = coefficients(p, s.e);
    const Real T = kt::step_temperature(p.c, c, s.T, s.rate, s.trD);  // timeStepTemperature
    const Real speed = simsand::pwave_speed(p.f, s.e, pressure(s.sigf), rho) + kt::sound_speed(p.c, c, T) +
                       kt::viscous_speed(c, T, rho, h);
    return kt::dispersed(p.c, s.e) ? Real(0) : speed;  // no stress, no wave (collisional() above)
  }

  static Real collisional_fraction(const State& s, const Sym3& sig) {
    const Real qf = deviatoric_stress(s.sigf), qc = deviatoric_stress(sig - s.sigf);
    return qf + qc > 0 ? qc / (qf + qc) : Real(0);
  }

  static void describe(OutputFields<PhaseTransition>& out) {
    out.state("voidRatio", &State::e, "-", "void ratio e (shared)");
    out.state("granularTemperature", &State::T, "m^2/s^2", "granular temperature T");
    out.state("plasticStrain", &State::epsEq, "-", "equivalent plastic strain, integral of sqrt(2/3 deps^p:deps^p)");
    out.state("deviatoricPlasticStrain", &State::kappa, "-", "eps_d^p, the hardening variable of eq. (14)");
    out.state("deviatoricStrainRate", &State::rate, "1/s",
              "equivalent deviatoric strain rate sqrt(2/3 dev D:dev D) of the last step (gamma_dot/sqrt(3) in "
              "simple shear)");
    out.state("frictionalStress", &State::sigf, "Pa", "sigma_f, tension positive");
    out.derived("frictionalPressure", "Pa", "p_f = -tr(sigma_f)/3 (compression positive)",
                [](const Params&, const State& s, const Sym3&) { return pressure(s.sigf); });
    out.derived("frictionalDeviatoricStress", "Pa", "q_f = sqrt(3/2 s_f:s_f)",
                [](const Params&, const State& s, const Sym3&) { return deviatoric_stress(s.sigf); });
    out.derived("collisionalPressure", "Pa", "p_col = -tr(sigma - sigma_f)/3 (compression positive)",
                [](const Params&, const State& s, const Sym3& sig) { return pressure(sig - s.sigf); });
    out.derived("collisionalDeviatoricStress", "Pa", "q_col of sigma_col = sigma - sigma_f",
                [](const Params&, const State& s, const Sym3& sig) { return deviatoric_stress(sig - s.sigf); });
    out.derived("shearViscosity", "Pa s", "eta (eq. 21)", [](const Params& p, const State& s, const Sym3&) {
      const kt::Coefficients c = coefficients(p, s.e);
      return c.eta_hat * sqrt(fmax(s.T, Real(0)));
    });
    out.derived("bulkViscosity", "Pa s", "gamma (eq. 22)", [](const Params& p, const State& s, const Sym3&) {
      const kt::Coefficients c = coefficients(p, s.e);
      return c.gam_hat * sqrt(fmax(s.T, Real(0)));
    });
    out.derived("collisionalFraction", "-", "K_col = q_col/(q_col + q_f) (section 4.1.2)",
                [](const Params&, const State& s, const Sym3& sig) { return collisional_fraction(s, sig); });
    out.derived("criticalVoidRatio", "-", "e_c(p_f), eq. (16)", [](const Params& p, const State& s, const Sym3&) {
      return simsand::critical_void_ratio(p.f, pressure(s.sigf));
    });
    out.derived("elasticEnergy", "J/m^3",
                "elastic energy of sigma_f stored per volume, an estimate (eq. 13 is hypoelastic: simsand_model.hpp)",
                [](const Params& p, const State& s, const Sym3&) { return simsand::elastic_energy(p.f, s.e, s.sigf); });
  }
};

}  // namespace scree::materials

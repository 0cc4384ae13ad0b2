// kineticTheory: purely collisional granular material (kinetic theory of dense granular
// gases, Garzó & Dufty 1999; Feng et al. 2025 section 3.3, eqs. 19-28, Appendices A-B).
//
//   sigma = sigma_col = -p_col(e, T) I + 2 eta(e, T) dev(D) + gamma(e, T) tr(D) I   (eq. 19)
//   3/2 rho_p V dT/dt = sigma_col : D - Gamma(e, T, tr D)                        (eq. 27)
//
// The stress is not incremental: it is recomputed every step from the granular temperature T
// (integrated exactly over the step, kinetic_theory.hpp) and the strain rate D = deps/dt.
// The void ratio follows the volume: 1 + e <- (1 + e) exp(tr deps).
//
// As the paper notes (section 4.1.3), this material alone cannot carry a static load (no
// stress at rest once T has decayed); it is meant for element tests and as the collisional
// half of phaseTransition. Formulas, decisions and parameters: README.md in this folder.
#pragma once

#include <cmath>
#include <string>

#include "scree/materials/kinetic_theory.hpp"
#include "scree/materials/kinetic_theory_spec.hpp"
#include "scree/material/material.hpp"

namespace scree::materials {

struct KineticTheory {
  static constexpr const char* type_name = "kineticTheory";

  struct Params {
    kt::Params c;  ///< collisional constants
    Real e0;       ///< initial void ratio [-]
    Real T0;       ///< initial granular temperature [m^2/s^2]
  };
  struct State {
    Real e;     ///< void ratio [-]
    Real T;     ///< granular temperature [m^2/s^2]
    Real rate;  ///< equivalent deviatoric strain rate of the last step sqrt(2/3 dev D:dev D) [1/s]
    Real trD;   ///< volumetric strain rate of the last step tr D [1/s] (tension positive)
  };

  static ParamSpec spec() {
    ParamSpec s(type_name,
                "Purely collisional granular material: kinetic theory (Garzo-Dufty 1999) with the granular "
                "temperature from the fluctuation-energy balance (Feng et al. 2025 eqs. 19-28)");
    kt::add_collisional_spec(s);
    s.scalar("initialVoidRatio", "-", "e0").positive();
    return s;
  }
  static Params read(const ParamReader& r) {
    Params p{};
    p.c = kt::read_collisional(r);
    p.e0 = r.scalar("initialVoidRatio");
    p.T0 = r.scalar("initialGranularTemperature");
    return p;
  }
  static Real density(const Params& p) { return p.c.rho_p / (1 + p.e0); }

  /// The stress is a function of T: any initial stress is replaced by -p_col(e0, T0) I.
  static State initial_state(const Params& p, Sym3& sigma) {
    State s{p.e0, p.T0, 0, 0};
    const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, p.e0));
    sigma = kt::collisional_stress(c, p.T0, Sym3::zero());
    return s;
  }

  SCREE_HD static void update(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    const Real tr = inc.deps.trace();
    s.e = fmax((1 + s.e) * exp(tr) - 1, Real(1e-6));  // 1 + e follows the volume
    const Real inv_dt = inc.dt > 0 ? 1 / inc.dt : Real(0);
    const Sym3 D = inc.deps * inv_dt;
    const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, s.e));
    const kt::RateInvariants ri = kt::rate_invariants(D);
    s.rate = sqrt(Real(2) / 3 * ri.dev2);
    s.trD = ri.tr;
    // Grains in free flight (kt::dispersed): no stress, T carried (selects, not a branch:
    // PhaseTransition.hpp says why).
    const bool flying = kt::dispersed(p.c, s.e);
    const Real T = kt::update_temperature(c, s.T, ri, inc.dt);  // eq. (27), exact for frozen coefficients
    s.T = flying ? s.T : T;
    sigma = kt::collisional_stress(c, T, D) * (flying ? Real(0) : Real(1));  // eq. (19)
  }

  /// The energy the collisions dissipated over the step, per volume [J/m^3]: Gamma dt of
  /// eq. (28) at the step's end (T and e after the update); none for a dispersed point
  /// (material.hpp, optional: the energy ledger's collisional term).
  SCREE_HD static Real collisional_dissipation(const Params& p, const State& s, const StrainIncrement& inc) {
    const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, s.e));
    return kt::dispersed(p.c, s.e) ? Real(0) : kt::dissipation_rate(c, s.T, s.trD) * inc.dt;
  }

  SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3&, Real rho, Real h) {
    const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, s.e));
    const Real T = kt::step_temperature(p.c, c, s.T, s.rate, s.trD);  // timeStepTemperature
    const Real speed = kt::sound_speed(p.c, c, T) + kt::viscous_speed(c, T, rho, h);
    return kt::dispersed(p.c, s.e) ? Real(0) : speed;  // no stress, no wave (update() above)
  }

  static void describe(OutputFields<KineticTheory>& out) {
    out.state("voidRatio", &State::e, "-", "void ratio e");
    out.state("granularTemperature", &State::T, "m^2/s^2", "granular temperature T");
    out.state("deviatoricStrainRate", &State::rate, "1/s",
              "equivalent deviatoric strain rate sqrt(2/3 dev D : dev D) of the last step (gamma_dot/sqrt(3) "
              "in simple shear)");
    out.derived("collisionalPressure", "Pa", "p_col = -tr(sigma_col)/3 (compression positive)",
                [](const Params&, const State&, const Sym3& sig) { return pressure(sig); });
    out.derived("collisionalDeviatoricStress", "Pa", "q_col = sqrt(3/2 s:s) of sigma_col",
                [](const Params&, const State&, const Sym3& sig) { return deviatoric_stress(sig); });
    out.derived("shearViscosity", "Pa s", "eta (eq. 21)", [](const Params& p, const State& s, const Sym3&) {
      const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, s.e));
      return c.eta_hat * sqrt(fmax(s.T, Real(0)));
    });
    out.derived("bulkViscosity", "Pa s", "gamma (eq. 22)", [](const Params& p, const State& s, const Sym3&) {
      const kt::Coefficients c = kt::coefficients(p.c, kt::solid_fraction(p.c, s.e));
      return c.gam_hat * sqrt(fmax(s.T, Real(0)));
    });
  }
};

}  // namespace scree::materials

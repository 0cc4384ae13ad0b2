// Parameters of the kinetic-theory (collisional) model: the dictionary entries and their
// reader, shared by every material that uses the model (kineticTheory, phaseTransition).
// Host code only. The model itself: kinetic_theory.hpp.
#pragma once

#include <string>
#include <vector>

#include "scree/materials/granular_spec.hpp"
#include "scree/materials/kinetic_theory.hpp"
#include "scree/params/spec.hpp"

namespace scree::materials::kt {

/// Declare the collisional parameters (eqs. 19-28 of Feng et al. 2025, Garzo & Dufty 1999).
/// Each doc string gives the typical values (the paper's Table 3: element test / column
/// collapse / flume; Table 2 for Fig. 5), each range what the model admits.
inline void add_collisional_spec(ParamSpec& s) {
  add_particle_density(s);
  s.scalar("diameter", "m",
           "grain diameter d (eqs. 21, 22, 28), in m; typical 1e-4-1e-2 (Table 3: 1e-3 / 1.25e-3 / 1e-3)")
      .range(0.0, 0.1)
      .open_min();
  s.scalar("voidRatioSd", "-",
           "e_sd: void ratio of the densest disordered packing, V_sd = 1/(1+e_sd) (eq. 25); typical 0.55-0.95 "
           "(Table 3: 0.92 / 0.62 / 0.60). Give this or solidFractionSd")
      .range(0.0, 2.0)
      .open_min()
      .optional();
  s.scalar("solidFractionSd", "-",
           "V_sd: solid fraction of the densest disordered packing (eq. 25); typical 0.6-0.64 (Table 2: 0.6)")
      .range(0.0, 1.0)
      .open_min()
      .open_max()
      .optional();
  s.scalar("solidFractionM", "-",
           "V_m: solid fraction where the dense branch of g0 starts (eq. 26); typical 0.4 (Tables 2-3)")
      .range(0.0, 1.0)
      .open_min()
      .open_max()
      .default_value(0.4);
  s.scalar("restitutionCoefficient", "-",
           "normal restitution coefficient eps_n (eq. 24); typical 0.6-0.9 (Table 3: 0.7 / 0.6 / 0.6)")
      .range(0.0, 1.0)
      .open_max();
  s.scalar("particleFriction", "-",
           "inter-particle friction coefficient mu_p (eq. 24); typical 0-0.5 (Table 3: 0.1 / 0.2 / 0.2)")
      .range(0.0, 2.0)
      .default_value(0.0);
  s.scalar("maxRadialDistribution", "-",
           "cap of g0 (eq. 25) as V -> V_sd: V is limited to V_sd - 2/g0max")
      .min(10.0)
      .default_value(1000.0);
  add_min_solid_fraction(s,
                         "below this solid fraction a point is dispersed (grains in free flight, the kinetic theory's "
                         "mean free path longer than the flow): it carries no stress and its granular temperature is "
                         "not produced (kinetic_theory.hpp, dispersed())");
  s.word("bulkViscosity", "gamma* of (A5): 'GD99' (Garzo & Dufty 1999, proportional to V^2 g0, the default) or "
                          "'printed' (the paper's (A5) as printed, V g0: 1/V times larger)")
      .choices({"GD99", "printed"})
      .default_value("GD99");
  s.word("dissipation", "collisional dissipation Gamma of eq. (28)/(B8): 'GD99' (proportional to V^2, the default) "
                        "or 'printed' (the paper's (B8) as printed, one factor V fewer: 1/V times larger)")
      .choices({"GD99", "printed"})
      .default_value("GD99");
  s.word("timeStepTemperature",
         "the granular temperature the time step's signal speeds assume: 'current' (T) or 'steady' (the larger of "
         "T and the steady temperature of the last step's strain rate, so that a point heated by compression within "
         "one step does not outrun the step chosen before it: kinetic_theory.hpp, step_temperature)")
      .choices({"current", "steady"})
      .default_value("current");
  s.boolean("firstOrderCooling", "include the divergence term zeta1* of the dissipation (B11-B14)")
      .default_value("true");
  s.scalar("initialGranularTemperature", "m^2/s^2",
           "T0 (Table 3 gives 1e-15 'x 10^3 m^2/s^2'; only needs to be negligibly small)")
      .non_negative()
      .default_value(1e-12);
  s.check([](const Dictionary& d, std::vector<InputError>& errors) {
    const bool a = d.has("voidRatioSd"), b = d.has("solidFractionSd");
    if (a == b)
      errors.emplace_back(d.where(), std::string("'") + d.name() +
                                         "': give exactly one of voidRatioSd (e_sd) and solidFractionSd (V_sd)");
    const double vm = d.has("solidFractionM") ? d.get_scalar("solidFractionM") : 0.4;
    const double vsd = a ? 1.0 / (1.0 + d.get_scalar("voidRatioSd")) : (b ? d.get_scalar("solidFractionSd") : 1.0);
    if ((a || b) && !(vsd > vm))
      errors.emplace_back(d.where(), std::string("'") + d.name() + "': V_sd = " + std::to_string(vsd) +
                                         " must exceed solidFractionM V_m = " + std::to_string(vm) +
                                         " (eq. 26)");
  });
}
inline Params read_collisional(const ParamReader& r) {
  Constants c{};
  c.rho_p = r.scalar("particleDensity");
  c.d = r.scalar("diameter");
  c.Vsd = r.has("voidRatioSd") ? 1 / (1 + r.scalar("voidRatioSd")) : r.scalar("solidFractionSd");
  c.Vm = r.scalar("solidFractionM");
  c.eps = effective_restitution(r.scalar("restitutionCoefficient"), r.scalar("particleFriction"));
  c.Vcap = cap_solid_fraction(c.Vsd, c.Vm, r.scalar("maxRadialDistribution"));
  c.Vmin = r.scalar("minSolidFraction");
  c.zeta1 = r.boolean("firstOrderCooling") ? 1 : 0;
  c.a5_printed = r.word("bulkViscosity") == "printed" ? 1 : 0;
  c.b8_printed = r.word("dissipation") == "printed" ? 1 : 0;
  c.steady_step = r.word("timeStepTemperature") == "steady" ? 1 : 0;
  return make_params(c);
}

}  // namespace scree::materials::kt

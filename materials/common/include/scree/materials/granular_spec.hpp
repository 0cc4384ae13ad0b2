// Dictionary entries every granular material of the paper has (simsand, kineticTheory,
// phaseTransition), declared once: the grains' density. Host code only.
#pragma once

#include "scree/params/spec.hpp"

namespace scree::materials {

/// particleDensity rho_p [kg/m^3]: typical values from the paper's Tables 2-3; the range
/// catches a density in g/cm^3 (2.65 for 2650).
inline void add_particle_density(ParamSpec& s) {
  s.scalar("particleDensity", "kg/m^3",
           "grain density rho_p, in kg/m^3; bulk density is rho_p/(1+e0); typical 2650 for quartz sand (Table 3: "
           "1050 polystyrene beads / 2650 / 2500; Table 2: 1500)")
      .range(100.0, 25000.0);
}

}  // namespace scree::materials

// Dispersed points, shared by the granular materials (kineticTheory, phaseTransition,
// simsand): a point whose solid fraction V = 1/(1+e) is below V_min (`minSolidFraction`) is
// grains apart, not a continuum; the materials give it no stress and no wave speed
// (materials/kineticTheory/README.md, KT-8; materials/simsand/README.md, "Dispersed
// points"). The rule, the keyword's range and its default are written here once.
#pragma once

#include "scree/core/config.hpp"
#include "scree/params/spec.hpp"

namespace scree::materials {

/// Whether a point of void ratio e is dispersed: 1/(1+e) < V_min.
SCREE_HD inline bool dispersed_below(Real Vmin, Real e) { return (1 + e) * Vmin > 1; }

/// minSolidFraction: (0, 0.1], default 1e-3 (the kinetic theory's mean free path is then
/// about 118 grain diameters; kinetic_theory.hpp, dispersed()). `doc` says what the material
/// does with such a point.
inline void add_min_solid_fraction(ParamSpec& s, const char* doc) {
  s.scalar("minSolidFraction", "-", doc).range(0.0, 0.1).open_min().default_value(1e-3);
}

}  // namespace scree::materials

// What a particle field is, apart from its values: the fields every body writes
// (standard_particle_fields), a material's own (PluginEntry::output_fields) and a
// two-phase body's, as snapshots carry them (output/snapshot.hpp) and scree --list-plugins
// lists them.
#pragma once

#include <string>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

struct FieldInfo {
  std::string name;
  int components = 1;  ///< 1 (scalar), 3 (vector: x y z, z = 0 in 2D) or 6 (symmetric tensor, Voigt order)
  std::string unit;    ///< SI, e.g. "Pa", "m/s"; "-" for a dimensionless one
  std::string doc;
};

/// The fields every body's snapshot carries, whatever its material, in the order
/// mpm/material_body.hpp writes them, besides its material's own; writers add particleId.
inline const std::vector<FieldInfo>& standard_particle_fields() {
  static const std::vector<FieldInfo> fields{
      {"velocity", 3, "m/s", "particle velocity"},
      {"displacement", 3, "m", "displacement from the initial position"},
      {"stress", 6, "Pa", "Cauchy stress, tension positive (xx yy zz xy yz zx)"},
      {"pressure", 1, "Pa", "mean stress p = -tr(sigma)/3, compression positive"},
      {"deviatoricStress", 1, "Pa", "von Mises stress q = sqrt(3/2 s:s)"},
      {"volume", 1, "m^3", "current volume (area per unit thickness in 2D)"},
      {"mass", 1, "kg", "particle mass (per unit thickness in 2D)"},
      {"density", 1, "kg/m^3", "mass / current volume"},
      {"bodyId", 1, "-", "index of the body in constant/bodies"},
      {"particleId", 1, "-", "the point's id, unique over the case and stable over the run (added by the writers)"}};
  return fields;
}

/// The entry of `name` in standard_particle_fields() (a name not there is a programming error).
inline const FieldInfo& standard_particle_field(const std::string& name) {
  for (const FieldInfo& f : standard_particle_fields())
    if (f.name == name) return f;
  static const FieldInfo none{};
  return none;
}

/// What a two-phase body (porous/) writes besides the standard fields, in the order of its
/// extra point columns (defined in porous/porous_media.cpp, which makes those columns).
SCREE_API const std::vector<FieldInfo>& two_phase_fields();

}  // namespace scree

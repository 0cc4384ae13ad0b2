// A case directory: its dictionaries, read and validated as a whole before anything runs.
//
//   case/
//     system/controlDict          time control, output, libs, writers {}, functions {}
//     system/mpmSchemes           update scheme, shape function, transfer, damping
//     system/gridDict             background grid: dimension, lower, upper, cellSize
//     constant/g                  gravity: value (0 -9.81);
//     constant/materialProperties one dictionary per material: name { type ...; ... }
//     constant/bodies             one dictionary per body (particle set): region,
//                                 material, particlesPerCell, velocity, initialStress
//     constant/boundaryConditions one dictionary per boundary condition
//
// Case::read parses every file, loads the plugins named in `libs`, and checks every
// dictionary against the parameter specs of the core and of the plugins it names,
// collecting every error (file:line) before throwing InputErrors. It creates nothing.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scree/case/settings.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"
#include "scree/plugin/loader.hpp"

namespace scree {

/// Whether an entry of a dictionary of named objects (constant/bodies, materialProperties,
/// boundaryConditions, the writers {} and functions {} of controlDict) names one: it is
/// neither a variable for $macros (a key starting with '_') nor the FoamFile header.
SCREE_API bool names_an_object(const Entry& e);

/// The entries of `d` that name an object and are dictionaries, in file order (a validated
/// case has no other).
SCREE_API std::vector<const Entry*> plugin_entries(const Dictionary& d);

/// The plugin the `type` of the named object `d` names (of kind `kind`); an unknown type
/// is an InputError at its line (a validated case has none).
SCREE_API const PluginEntry& plugin_of(const Registry& reg, PluginKind kind, const Dictionary& d);

/// The specs of the core's own dictionaries (documented by `scree --list-plugins case`).
struct CoreSpecs {
  std::shared_ptr<ParamSpec> control, schemes, grid, gravity, body;
  SCREE_API static const CoreSpecs& get();
};

class SCREE_API Case {
 public:
  /// Read and validate; throws InputErrors listing every problem found.
  static Case read(const std::filesystem::path& dir, PluginRuntime& runtime);

  const std::filesystem::path& dir() const { return dir_; }
  const Dictionary& control() const { return control_; }
  const Dictionary& schemes() const { return schemes_; }
  const Dictionary& grid() const { return grid_; }
  const Dictionary& gravity() const { return gravity_; }
  const Dictionary& materials() const { return materials_; }
  const Dictionary& bodies() const { return bodies_; }
  const Dictionary& boundaries() const { return boundaries_; }
  int dimension() const { return dimension_; }
  /// The named objects of the case (plugin_entries): the bodies, the materials, the
  /// boundary conditions, and the writers and function objects of system/controlDict.
  std::vector<const Entry*> body_entries() const { return plugin_entries(bodies_); }
  std::vector<const Entry*> material_entries() const { return plugin_entries(materials_); }
  std::vector<const Entry*> boundary_entries() const { return plugin_entries(boundaries_); }
  std::vector<const Entry*> writer_entries() const { return group_entries("writers"); }
  std::vector<const Entry*> function_entries() const { return group_entries("functions"); }
  /// The core dictionaries as typed settings, defaults applied (settings.hpp).
  const CaseSettings& settings() const { return settings_; }

 private:
  /// plugin_entries of the sub-dictionary `group` of controlDict (none without one).
  std::vector<const Entry*> group_entries(const char* group) const;

  std::filesystem::path dir_;
  Dictionary control_, schemes_, grid_, gravity_, materials_, bodies_, boundaries_;
  int dimension_ = 2;
  CaseSettings settings_;
};

}  // namespace scree

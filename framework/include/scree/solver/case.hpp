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

#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/solver/settings.hpp"

namespace scree {

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
  /// The core dictionaries as typed settings, defaults applied (settings.hpp).
  const CaseSettings& settings() const { return settings_; }

 private:
  std::filesystem::path dir_;
  Dictionary control_, schemes_, grid_, gravity_, materials_, bodies_, boundaries_;
  int dimension_ = 2;
  CaseSettings settings_;
};

}  // namespace scree

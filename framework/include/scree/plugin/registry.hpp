// The plugin registry: (kind, name) -> (parameter spec, factory).
//
// Kinds: material, boundaryCondition, writer, functionObject, and the two-phase
// formulation's retention and permeability models (porous/hydraulic_model.hpp). Each plugin library's
// entry point (SCREE_PLUGIN, plugin_api.hpp) adds its entries; built-in core entries
// are added by the core. Lookup of an unknown name throws an InputError listing the
// valid names of that kind.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/output/field_info.hpp"
#include "scree/params/spec.hpp"

namespace scree {

class PointMaterial;
class BoundaryCondition;
class Writer;
class FunctionObject;
class RetentionModel;
class PermeabilityModel;
template <int D>
class Body;
template <int D>
struct BodySetup;
struct SolverContext;

enum class PluginKind { material, boundaryCondition, writer, functionObject, retention, permeability };
SCREE_API const char* to_string(PluginKind k);
SCREE_API const std::vector<PluginKind>& all_plugin_kinds();

/// Factories of a material: a point-wise model (host) and MPM bodies in 2D and 3D
/// (which carry the material's kernels for both backends).
struct MaterialFactory {
  std::function<std::unique_ptr<PointMaterial>(const Dictionary&)> point;
  std::function<std::unique_ptr<Body<2>>(const Dictionary&, const BodySetup<2>&)> body2;
  std::function<std::unique_ptr<Body<3>>(const Dictionary&, const BodySetup<3>&)> body3;
};

struct PluginEntry {
  PluginKind kind;
  std::string name;
  std::shared_ptr<const ParamSpec> spec;
  std::string library;  ///< the file it came from ("<core>" for built-ins)
  MaterialFactory material;  ///< kind == material
  std::vector<FieldInfo> output_fields;  ///< kind == material: its own output fields
  /// kind == boundaryCondition / writer / functionObject
  std::function<std::unique_ptr<BoundaryCondition>(const Dictionary&, const SolverContext&)> boundary;
  std::function<std::unique_ptr<Writer>(const Dictionary&, const SolverContext&)> writer;
  std::function<std::unique_ptr<FunctionObject>(const Dictionary&, const SolverContext&)> function_object;
  /// kind == functionObject: it reduces over the ranks of a decomposed run itself
  /// (FunctionObject's reduces_over_ranks, output/function_object.hpp).
  bool reduces_over_ranks = false;
  /// kind == retention / permeability
  std::function<std::unique_ptr<RetentionModel>(const Dictionary&)> retention;
  std::function<std::unique_ptr<PermeabilityModel>(const Dictionary&)> permeability;
};

class SCREE_API Registry {
 public:
  Registry();
  ~Registry();
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  /// Add an entry. A second entry of the same kind and name is an error naming both
  /// libraries.
  void add(PluginEntry e);

  /// The entry, or an InputError at `where`: "unknown material type 'simsnd'; did you
  /// mean 'simsand'? valid types: linearElastic, simsand, ...".
  const PluginEntry& get(PluginKind kind, const std::string& name, const SourceLocation& where) const;
  const PluginEntry* find(PluginKind kind, const std::string& name) const;
  std::vector<const PluginEntry*> entries(PluginKind kind) const;
  std::vector<std::string> names(PluginKind kind) const;

  /// A point-wise material from a material dictionary ({ type name; params... }),
  /// validated against its spec first (throws InputErrors listing every problem).
  std::unique_ptr<PointMaterial> make_point_material(const Dictionary& material_dict) const;

  /// The library being loaded (set by the loader while an entry point runs).
  void set_current_library(std::string lib) { current_library_ = std::move(lib); }

  // Typed helpers used by SCREE_PLUGIN entry points; defined in plugin_api.hpp so
  // that they are instantiated inside the plugin (with the plugin's kernels).
  template <class M>
  void add_material();
  template <class BC>
  void add_boundary_condition();
  template <class W>
  void add_writer();
  template <class F>
  void add_function_object();
  template <class R>
  void add_retention();
  template <class K>
  void add_permeability();

 private:
  std::map<std::pair<PluginKind, std::string>, PluginEntry> entries_;
  std::string current_library_ = "<core>";
};

}  // namespace scree

// Writing a plugin: one exported, versioned entry point per library.
//
//   #include "scree/plugin/plugin_api.hpp"
//   #include "MyMaterial.hpp"
//   SCREE_PLUGIN(registry) {
//     registry.add_material<MyMaterial>();
//   }
//
// SCREE_PLUGIN defines two C symbols, exported with Boost.DLL's BOOST_SYMBOL_EXPORT
// (everything else in the plugin stays hidden):
//   int  scree_plugin_abi_v1()                 -> kPluginAbiVersion the plugin was built with
//   void scree_register_v1(scree::Registry&)   -> adds the plugin's entries
// The "_v1" in the names is the entry-point protocol; kPluginAbiVersion is checked on
// load so that a plugin built against an incompatible core is refused with a message.
//
// add_material<M>() instantiates M's particle kernels here, inside the plugin, for both
// backends (when compiled as CUDA) and both dimensions.
#pragma once

#include <boost/config.hpp>
#include <memory>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/material/material.hpp"
#include "scree/mpm/material_body.hpp"
#include "scree/plugin/context.hpp"
#include "scree/output/function_object.hpp"
#include "scree/output/writer.hpp"
#include "scree/plugin/registry.hpp"
#include "scree/porous/hydraulic_model.hpp"

#include "scree/plugin/plugin_api_names.hpp"

#define SCREE_PLUGIN(registry_var)                                                              \
  static void scree_plugin_register_impl(::scree::Registry& registry_var);                       \
  extern "C" BOOST_SYMBOL_EXPORT int scree_plugin_abi_v1() { return ::scree::kPluginAbiVersion; } \
  extern "C" BOOST_SYMBOL_EXPORT void scree_register_v1(::scree::Registry& r) {                  \
    scree_plugin_register_impl(r);                                                               \
  }                                                                                              \
  static void scree_plugin_register_impl(::scree::Registry& registry_var)

namespace scree {

/// executeControl / executeInterval, accepted by every function object (the solver
/// schedules them; see output/function_object.hpp).
inline void declare_execute_control(ParamSpec& spec) {
  spec.word("executeControl", "when to run: writeTime (with the writers), timeStep (every executeInterval "
                              "steps) or runTime (every executeInterval seconds)")
      .choices({"writeTime", "timeStep", "runTime"})
      .default_value("writeTime");
  spec.scalar("executeInterval", "s or steps", "interval for timeStep/runTime").default_value(1.0).positive();
}

namespace detail {
/// A registry entry for plugin class P of `kind`: its name, and its spec (which also
/// accepts the `type` key that selected it).
template <class P>
PluginEntry plugin_entry(PluginKind kind) {
  PluginEntry e;
  e.kind = kind;
  e.name = P::type_name;
  auto spec = std::make_shared<ParamSpec>(P::spec());
  spec->allow_keys({"type"});
  if (kind == PluginKind::functionObject) declare_execute_control(*spec);
  e.spec = spec;
  return e;
}
}  // namespace detail

template <class M>
void Registry::add_material() {
  // The contract of material.hpp, one message per missing piece; the registration below is
  // compiled only for a material that meets it (no cascade of errors from the kernels).
  static_assert(check_material<M>(), "M does not meet the material contract (scree/material/material.hpp)");
  if constexpr (Material<M>) {
    PluginEntry e = detail::plugin_entry<M>(PluginKind::material);
    const auto spec = e.spec;
    {
      OutputFields<M> out;
      M::describe(out);
      for (const auto& f : out.fields()) e.output_fields.push_back({f.name, f.components, f.unit, f.doc});
    }
    e.material.point = [spec](const Dictionary& d) -> std::unique_ptr<PointMaterial> {
      ParamReader r(*spec, d);
      return std::make_unique<PointMaterialOf<M>>(M::read(r));
    };
    e.material.body2 = [spec](const Dictionary& d, const BodySetup<2>& setup) -> std::unique_ptr<Body<2>> {
      ParamReader r(*spec, d);
      return make_material_body<2, M>(M::read(r), setup);
    };
    e.material.body3 = [spec](const Dictionary& d, const BodySetup<3>& setup) -> std::unique_ptr<Body<3>> {
      ParamReader r(*spec, d);
      return make_material_body<3, M>(M::read(r), setup);
    };
    add(std::move(e));
  }
}

template <class BC>
void Registry::add_boundary_condition() {
  PluginEntry e = detail::plugin_entry<BC>(PluginKind::boundaryCondition);
  const auto spec = e.spec;
  e.boundary = [spec](const Dictionary& d, const SolverContext& ctx) -> std::unique_ptr<BoundaryCondition> {
    return std::make_unique<BC>(ParamReader(*spec, d), ctx);
  };
  add(std::move(e));
}

template <class W>
void Registry::add_writer() {
  PluginEntry e = detail::plugin_entry<W>(PluginKind::writer);
  const auto spec = e.spec;
  e.writer = [spec](const Dictionary& d, const SolverContext& ctx) -> std::unique_ptr<Writer> {
    return std::make_unique<W>(ParamReader(*spec, d), ctx);
  };
  add(std::move(e));
}

template <class F>
void Registry::add_function_object() {
  PluginEntry e = detail::plugin_entry<F>(PluginKind::functionObject);
  const auto spec = e.spec;
  e.function_object = [spec](const Dictionary& d, const SolverContext& ctx) -> std::unique_ptr<FunctionObject> {
    return std::make_unique<F>(ParamReader(*spec, d), ctx);
  };
  if constexpr (requires { F::reduces_over_ranks; }) e.reduces_over_ranks = F::reduces_over_ranks;
  add(std::move(e));
}

template <class R>
void Registry::add_retention() {
  PluginEntry e = detail::plugin_entry<R>(PluginKind::retention);
  const auto spec = e.spec;
  e.retention = [spec](const Dictionary& d) -> std::unique_ptr<RetentionModel> {
    return std::make_unique<R>(ParamReader(*spec, d));
  };
  add(std::move(e));
}

template <class K>
void Registry::add_permeability() {
  PluginEntry e = detail::plugin_entry<K>(PluginKind::permeability);
  const auto spec = e.spec;
  e.permeability = [spec](const Dictionary& d) -> std::unique_ptr<PermeabilityModel> {
    return std::make_unique<K>(ParamReader(*spec, d));
  };
  add(std::move(e));
}

}  // namespace scree

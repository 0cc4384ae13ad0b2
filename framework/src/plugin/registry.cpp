// The plugin registry.
#include "scree/plugin/registry.hpp"

#include <stdexcept>

#include "scree/material/material.hpp"
#include "scree/plugin/hydraulic_models.hpp"

namespace scree {

PointMaterial::~PointMaterial() = default;

const char* to_string(PluginKind k) {
  switch (k) {
    case PluginKind::material: return "material";
    case PluginKind::boundaryCondition: return "boundaryCondition";
    case PluginKind::writer: return "writer";
    case PluginKind::functionObject: return "functionObject";
    case PluginKind::retention: return "retention";
    case PluginKind::permeability: return "permeability";
  }
  return "?";
}

const std::vector<PluginKind>& all_plugin_kinds() {
  static const std::vector<PluginKind> k{PluginKind::material, PluginKind::boundaryCondition, PluginKind::writer,
                                         PluginKind::functionObject, PluginKind::retention,
                                         PluginKind::permeability};
  return k;
}

Registry::Registry() = default;
Registry::~Registry() = default;

void Registry::add(PluginEntry e) {
  e.library = current_library_;
  auto key = std::make_pair(e.kind, e.name);
  auto it = entries_.find(key);
  if (it != entries_.end()) {
    if (it->second.library == e.library) return;  // the same library loaded twice
    throw std::runtime_error(std::string("two plugins register the ") + to_string(e.kind) + " '" + e.name +
                             "': " + it->second.library + " and " + e.library);
  }
  entries_.emplace(std::move(key), std::move(e));
}

const PluginEntry* Registry::find(PluginKind kind, const std::string& name) const {
  auto it = entries_.find({kind, name});
  return it == entries_.end() ? nullptr : &it->second;
}

const PluginEntry& Registry::get(PluginKind kind, const std::string& name, const SourceLocation& where) const {
  if (const PluginEntry* e = find(kind, name)) return *e;
  const auto valid = names(kind);
  std::string msg = std::string("unknown ") + to_string(kind) + " type '" + name + "'";
  const std::string near = nearest_name(name, valid);
  if (!near.empty()) msg += "; did you mean '" + near + "'?";
  msg += " Valid types: ";
  for (std::size_t i = 0; i < valid.size(); ++i) msg += (i ? ", " : "") + valid[i];
  if (valid.empty()) msg += "(none loaded: check SCREE_PLUGIN_PATH and `libs` in system/controlDict)";
  throw InputError(where, msg);
}

std::vector<const PluginEntry*> Registry::entries(PluginKind kind) const {
  std::vector<const PluginEntry*> v;
  for (auto& [k, e] : entries_)
    if (k.first == kind) v.push_back(&e);
  return v;
}

std::vector<std::string> Registry::names(PluginKind kind) const {
  std::vector<std::string> v;
  for (auto& [k, e] : entries_)
    if (k.first == kind) v.push_back(k.second);
  return v;
}

HydraulicModelFactory hydraulic_models(const Registry& reg) {
  return {[&reg](const Dictionary& d) {
            return reg.get(PluginKind::retention, d.at("type").as_word(), d.at("type").where()).retention(d);
          },
          [&reg](const Dictionary& d) {
            return reg.get(PluginKind::permeability, d.at("type").as_word(), d.at("type").where()).permeability(d);
          }};
}

std::unique_ptr<PointMaterial> Registry::make_point_material(const Dictionary& d) const {
  const Entry& type = d.at("type");
  const PluginEntry& e = get(PluginKind::material, type.as_word(), type.where());
  std::vector<InputError> errors;
  validate(*e.spec, d, errors);
  if (!errors.empty()) throw InputErrors(std::move(errors));
  return e.material.point(d);
}

}  // namespace scree

// Loading plugin libraries (Boost.DLL) and owning them.
//
// A PluginRuntime holds the registry and every loaded library. Libraries stay loaded
// until the runtime is destroyed; the registry (whose factories live in the libraries)
// is destroyed first, and every object a plugin made must be destroyed before the
// runtime (the solver is created after it and destroyed before it).
//
// Search path, in order: the directories in SCREE_PLUGIN_PATH (':'-separated), then
// the install-relative plugin directory (<prefix>/lib/scree/plugins, found from the
// location of libscree.so). `libs ("libfoo.so" "/abs/libbar.so");` in a controlDict
// loads further libraries: a relative name is looked up in the case directory, then
// on the search path.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/plugin/registry.hpp"

namespace scree {

class SCREE_API PluginRuntime {
 public:
  PluginRuntime();
  ~PluginRuntime();
  PluginRuntime(const PluginRuntime&) = delete;
  PluginRuntime& operator=(const PluginRuntime&) = delete;

  /// The plugin directories searched (SCREE_PLUGIN_PATH first, then the install dir).
  std::vector<std::filesystem::path> search_path() const;
  /// Load every lib*.so in the search path (skipping files that are not Scree plugins
  /// with a warning on stderr only if they look like one but fail).
  void load_default_plugins();
  /// Load one library. Throws InputError at `where` when the file is missing, is not a
  /// Scree plugin (no entry point), or was built for another ABI version (the message
  /// names both versions).
  void load(const std::string& name_or_path, const SourceLocation& where = {},
            const std::filesystem::path& case_dir = {});
  /// Load the `libs (...)` of a controlDict.
  void load_libs(const Dictionary& control_dict, const std::filesystem::path& case_dir);

  Registry& registry();
  const Registry& registry() const;
  /// The libraries loaded so far (absolute paths).
  std::vector<std::string> loaded() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scree

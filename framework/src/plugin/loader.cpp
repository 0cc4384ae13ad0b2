// Loading plugin libraries with Boost.DLL.
#include "scree/plugin/loader.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <set>

#include "../io/files.hpp"
#include "scree/plugin/plugin_api_names.hpp"

namespace fs = std::filesystem;

namespace scree {

struct PluginRuntime::Impl {
  // Declaration order matters: members are destroyed in reverse, so the registry (whose
  // std::function factories hold code of the libraries) goes before the libraries.
  std::vector<boost::dll::shared_library> libraries;
  std::vector<std::string> paths;
  Registry registry;
};

PluginRuntime::PluginRuntime() : impl_(std::make_unique<Impl>()) {}
PluginRuntime::~PluginRuntime() = default;

Registry& PluginRuntime::registry() { return impl_->registry; }
const Registry& PluginRuntime::registry() const { return impl_->registry; }
std::vector<std::string> PluginRuntime::loaded() const { return impl_->paths; }

namespace {
/// Why the dynamic loader refuses the library at `path`, in its own words without the path
/// it repeats: Boost.DLL's exception has consumed dlerror() and ends with the errno text of
/// its own error code (": Bad file descriptor"), which is not the reason. A file that is not
/// an ELF object at all is said to be "not a shared object". `fallback`: the exception's
/// text, when dlopen accepts the file after all.
std::string dlopen_refusal(const fs::path& path, const std::string& fallback) {
  if (std::ifstream f(path, std::ios::binary); f) {
    char magic[4] = {};
    f.read(magic, 4);
    if (f.gcount() < 4 || magic[0] != 0x7f || magic[1] != 'E' || magic[2] != 'L' || magic[3] != 'F')
      return "not a shared object (the file has no ELF header)";
  }
  void* h = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (h) {
    dlclose(h);
    return fallback;
  }
  const char* e = dlerror();
  std::string why = e ? e : fallback;
  const std::string prefix = path.string() + ": ";
  if (why.compare(0, prefix.size(), prefix) == 0) why.erase(0, prefix.size());
  return why;
}
}  // namespace

std::vector<fs::path> PluginRuntime::search_path() const {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("SCREE_PLUGIN_PATH")) {
    std::string s(env);
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t end = std::min(s.find(':', start), s.size());
      if (end > start) dirs.emplace_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  const fs::path lib = reader::library_dir();
  if (!lib.empty()) dirs.push_back(lib / "scree" / "plugins");
  return dirs;
}

void PluginRuntime::load_default_plugins() {
  std::set<std::string> seen;
  for (const fs::path& dir : search_path()) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(dir, ec))
      if (f.path().extension() == ".so") files.push_back(f.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      // A name earlier on the search path shadows the same name later.
      if (!seen.insert(f.filename().string()).second) continue;
      load(f.string());
    }
  }
}

void PluginRuntime::load(const std::string& name, const SourceLocation& where, const fs::path& case_dir) {
  fs::path path(name);
  std::vector<fs::path> tried;
  if (!path.is_absolute()) {
    std::vector<fs::path> candidates;
    if (!case_dir.empty()) candidates.push_back(case_dir / path);
    for (const fs::path& d : search_path()) candidates.push_back(d / path);
    path.clear();
    for (const fs::path& c : candidates) {
      tried.push_back(c);
      std::error_code ec;
      if (fs::exists(c, ec)) {
        path = c;
        break;
      }
    }
  } else {
    tried.push_back(path);
    if (!fs::exists(path)) path.clear();
  }
  if (path.empty()) {
    std::string msg = "cannot find plugin library '" + name + "'; looked in:";
    for (auto& t : tried) msg += "\n    " + t.string();
    throw InputError(where, msg);
  }
  path = fs::weakly_canonical(path);
  if (std::find(impl_->paths.begin(), impl_->paths.end(), path.string()) != impl_->paths.end()) return;
  // dlopen reads the file: a named pipe or a device in its place would block or never end.
  if (std::error_code ec; !fs::is_regular_file(path, ec))
    throw InputError(where, "cannot load plugin library '" + name + "': " + path.string() + " is not a regular file");

  boost::dll::shared_library lib;
  try {
    lib.load(path, boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw InputError(where, "cannot load plugin library '" + path.string() + "': " + dlopen_refusal(path, e.what()));
  }
  if (!lib.has(SCREE_PLUGIN_ABI_SYMBOL) || !lib.has(SCREE_PLUGIN_ENTRY_SYMBOL))
    throw InputError(where, "'" + path.string() + "' is not a Scree plugin (it has no " SCREE_PLUGIN_ENTRY_SYMBOL
                            " entry point; build plugins with scree_add_plugin and SCREE_PLUGIN)");
  const int abi = lib.get<int()>(SCREE_PLUGIN_ABI_SYMBOL)();
  if (abi != kPluginAbiVersion)
    throw InputError(where, "plugin '" + path.string() + "' was built for Scree plugin ABI version " +
                                std::to_string(abi) + ", but this scree has ABI version " +
                                std::to_string(kPluginAbiVersion) + ": rebuild the plugin against this Scree");
  impl_->registry.set_current_library(path.string());
  try {
    lib.get<void(Registry&)>(SCREE_PLUGIN_ENTRY_SYMBOL)(impl_->registry);
  } catch (const std::exception& e) {
    impl_->registry.set_current_library("<core>");
    throw InputError(where, "plugin '" + path.string() + "' failed to register: " + e.what());
  }
  impl_->registry.set_current_library("<core>");
  impl_->libraries.push_back(std::move(lib));
  impl_->paths.push_back(path.string());
}

void PluginRuntime::load_libs(const Dictionary& control, const fs::path& case_dir) {
  const Entry* libs = control.find("libs");
  if (!libs) return;
  for (const Item& it : libs->single_item().list()) {
    if (it.kind() != Item::Kind::word && it.kind() != Item::Kind::string)
      throw InputError(it.where(), "libs: expected library names (\"libfoo.so\"), found " + it.kind_name());
    load(it.text(), it.where(), case_dir);
  }
}

}  // namespace scree

// Helpers for the output tests: temporary directories, hand-made snapshots, plugin
// instances through the runtime, CSV and .pvd reading.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "scree/io/dictionary.hpp"
#include "scree/output/function_object.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/output/writer.hpp"
#include "scree/params/spec.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/plugin/registry.hpp"
#include "scree/plugin/context.hpp"

namespace scree_test {

namespace fs = std::filesystem;

/// A fresh directory, removed (with its contents) at the end of the test.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("scree-output-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The plugin runtime with every plugin of the build tree (loaded once per process).
inline scree::PluginRuntime& runtime() {
  static scree::PluginRuntime* rt = [] {
    auto* r = new scree::PluginRuntime;  // never destroyed: plugin objects may outlive tests
    r->load_default_plugins();
    return r;
  }();
  return *rt;
}

/// Parse `text`, validate it against the plugin's spec (failing the test on errors).
inline scree::Dictionary checked_dict(scree::PluginKind kind, const std::string& type, const std::string& text,
                                      int dimension) {
  auto d = scree::Dictionary::parse(text, "test");
  const auto& e = runtime().registry().get(kind, type, {});
  std::vector<scree::InputError> errors;
  scree::validate(*e.spec, d, errors, dimension);
  for (const auto& err : errors) ADD_FAILURE() << err.what();
  return d;
}

inline std::unique_ptr<scree::Writer> make_writer(const std::string& text, const scree::SolverContext& ctx) {
  auto d = checked_dict(scree::PluginKind::writer, "vtk", text, ctx.dimension);
  return runtime().registry().get(scree::PluginKind::writer, "vtk", {}).writer(d, ctx);
}

inline std::unique_ptr<scree::FunctionObject> make_function(const std::string& type, const std::string& text,
                                                            const scree::SolverContext& ctx) {
  auto d = checked_dict(scree::PluginKind::functionObject, type, "type " + type + "; " + text, ctx.dimension);
  return runtime().registry().get(scree::PluginKind::functionObject, type, {}).function_object(d, ctx);
}

inline scree::SolverContext make_context(const fs::path& case_dir, const std::string& name, int dimension = 2) {
  scree::SolverContext c;
  c.case_dir = case_dir;
  c.name = name;
  c.dimension = dimension;
  c.body_names = {"left", "right"};
  c.gravity = dimension == 3 ? std::vector<double>{0, 0, -9.81} : std::vector<double>{0, -9.81};
  c.cell_size = 0.1;
  return c;
}

/// A body with particles at `pos` (z = 0 unless given) and ids `ids`; fields added with
/// add_field.
inline scree::BodySnapshot make_body(const std::string& name, int body_id,
                                     const std::vector<std::array<double, 3>>& pos,
                                     const std::vector<std::int64_t>& ids) {
  scree::BodySnapshot b;
  b.name = name;
  b.body_id = body_id;
  b.material = name + "Material";
  b.material_type = "linearElastic";
  b.n = static_cast<scree::Index>(pos.size());
  for (const auto& p : pos) b.position.insert(b.position.end(), p.begin(), p.end());
  b.id = ids;
  return b;
}

inline void add_field(scree::BodySnapshot& b, const std::string& name, int components, std::vector<double> values,
                      const std::string& unit = "-") {
  ASSERT_EQ(values.size(), static_cast<std::size_t>(components * b.n)) << name;
  b.fields.push_back({name, components, unit, "test field " + name, std::move(values)});
}

/// A CSV file: header cells and rows of cells.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    ADD_FAILURE() << "no column '" << name << "'";
    return 0;
  }
  double num(std::size_t row, const std::string& name) const { return std::stod(rows.at(row).at(col(name))); }
};

inline std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',')
      cells.emplace_back();
    else
      cells.back() += c;
  }
  return cells;
}

inline Csv read_csv(const fs::path& p) {
  Csv c;
  std::ifstream in(p);
  EXPECT_TRUE(in.good()) << "cannot open " << p;
  std::string line;
  if (std::getline(in, line)) c.header = split(line);
  while (std::getline(in, line)) {
    c.rows.push_back(split(line));
    EXPECT_EQ(c.rows.back().size(), c.header.size()) << p << ": " << line;
  }
  return c;
}

struct PvdItem {
  double time;
  std::string file;
};

/// The DataSets of a .pvd (an independent little parser, not the writer's).
inline std::vector<PvdItem> read_pvd(const fs::path& p) {
  std::ifstream in(p);
  EXPECT_TRUE(in.good()) << "cannot open " << p;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  std::vector<PvdItem> items;
  const std::regex ds(R"re(<DataSet timestep="([^"]*)" group="" part="0" file="([^"]*)"/>)re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), ds); it != std::sregex_iterator(); ++it)
    items.push_back({std::stod((*it)[1]), (*it)[2]});
  return items;
}

/// The scree executable's exit status and what it printed.
struct ScreeRun {
  int rc;
  std::string out;
};

/// Runs the scree executable of the build tree on the case `dir` with `args` (each with its
/// leading space), its output (stdout and stderr) to `log`.
inline ScreeRun run_scree(const fs::path& dir, const std::string& args, const fs::path& log) {
  const std::string cmd = std::string(SCREE_BINARY_DIR "/bin/scree") + " --case '" + dir.string() + "'" + args +
                          " > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream lf(log);
  std::stringstream out;
  out << lf.rdbuf();
  return {rc, out.str()};
}

/// Files in `dir` whose names start with '.' or contain ".tmp" (left-over temporaries).
inline std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string f = e.path().filename().string();
    if (f[0] == '.' || f.find(".tmp") != std::string::npos) out.push_back(f);
  }
  return out;
}

}  // namespace scree_test

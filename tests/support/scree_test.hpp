// Helpers shared by Scree's tests: temporary case directories, the plugin runtime, and
// the backend a test runs on (CPU by default; `--device=cuda` or SCREE_TEST_DEVICE=cuda
// runs the same test on the GPU, which the `gpu`-labelled CTest entries do).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "scree/exec/memory.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/plugin/plugin_api.hpp"
#include "scree/case/case.hpp"
#include "scree/solver/simulation.hpp"

namespace scree::test {

/// The backend chosen for this test process.
inline Device& test_device() {
  static Device d = [] {
    const char* e = std::getenv("SCREE_TEST_DEVICE");
    return (e && std::string(e) == "cuda") ? Device::cuda : Device::cpu;
  }();
  return d;
}

/// Call from main() (or use SCREE_TEST_MAIN) to accept --device=cuda|cpu.
inline void parse_device_flag(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--device=cuda") test_device() = Device::cuda;
    if (a == "--device=cpu") test_device() = Device::cpu;
  }
}

/// A plugin runtime with every plugin of the build tree loaded (one per process).
inline PluginRuntime& runtime() {
  // Never destroyed: plugins stay loaded until the process exits.
  static PluginRuntime* rt = [] {
    auto* r = new PluginRuntime();
    r->load_default_plugins();
    return r;
  }();
  return *rt;
}

/// A function object that does not reduce over ranks, as a third party's may not: in a
/// decomposed run it runs on the root with the whole case gathered there. It writes the
/// time and the number of points of every body at each execution to
/// postProcessing/<name>/wholeCase.csv. `testWholeCase` once register_whole_case() has
/// added it to runtime().
class WholeCase final : public FunctionObject {
 public:
  static constexpr const char* type_name = "testWholeCase";
  static ParamSpec spec() { return ParamSpec(type_name, "the whole case's point count (tests)"); }
  WholeCase(const ParamReader&, const SolverContext& ctx) : file_(ctx.post_processing_dir() / "wholeCase.csv") {}
  void execute(const Snapshot& s) override {
    std::filesystem::create_directories(file_.parent_path());
    std::ofstream out(file_, std::ios::app);
    std::int64_t n = 0;
    for (const BodySnapshot& b : s.bodies) n += b.n;
    out << s.time << "," << n << "\n";
  }

 private:
  std::filesystem::path file_;
};
inline void register_whole_case() {
  static const bool done = [] {
    runtime().registry().add_function_object<WholeCase>();
    return true;
  }();
  (void)done;
}

/// Copies the case directory `src` (a shipped case, cases/<name>, or one of its variants)
/// into `dst` as a user starts from it: without what a run of it or of a variant left there,
/// VTK/, postProcessing/, checkpoints/, hidden temporaries and lock files (the setup script's
/// default run leaves results in cases/elasticColumn, which made restart-sensitive tests
/// fail on a fresh machine). Every test that copies a shipped case copies it through this
/// function, or through copy_case() of tests/support/case_copy.py (the same rule, for
/// the Python tests). `dst` is created; files already there are overwritten.
inline void copy_case(const std::filesystem::path& src, const std::filesystem::path& dst) {
  namespace fs = std::filesystem;
  auto result = [](const fs::path& name) {
    const std::string n = name.string();
    return n == "VTK" || n == "postProcessing" || n == "checkpoints" || n.front() == '.' ||
           name.extension() == ".lock";
  };
  fs::create_directories(dst);
  for (auto it = fs::recursive_directory_iterator(src); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path rel = fs::relative(it->path(), src);
    if (result(it->path().filename())) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory())
      fs::create_directories(dst / rel);
    else
      fs::copy_file(it->path(), dst / rel, fs::copy_options::overwrite_existing);
  }
}

/// A case directory under the system temp directory, removed when the object dies.
class TempCase {
 public:
  explicit TempCase(const std::string& tag) {
    static std::mt19937_64 rng(std::random_device{}());
    dir_ = std::filesystem::temp_directory_path() / ("scree_test_" + tag + "_" + std::to_string(rng() % 1000000000));
    std::filesystem::create_directories(dir_ / "system");
    std::filesystem::create_directories(dir_ / "constant");
  }
  ~TempCase() {
    if (!std::getenv("SCREE_KEEP_TEST_CASES")) {
      std::error_code ec;
      std::filesystem::remove_all(dir_, ec);
    }
  }
  TempCase(const TempCase&) = delete;
  TempCase& operator=(const TempCase&) = delete;

  /// Write `text` to `rel` (e.g. "system/controlDict").
  void write(const std::string& rel, const std::string& text) const {
    std::ofstream(dir_ / rel) << text;
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

/// The dictionaries of a small case, as text.
struct CaseFiles {
  std::string control, schemes, grid, gravity = "value (0 -9.81);", materials, bodies, boundaries;
};

/// Write `f` into a case directory through `dir.write(relative path, text)` (a TempCase,
/// or any directory object with that member).
template <class Dir>
void write_case_files(const Dir& dir, const CaseFiles& f) {
  dir.write("system/controlDict", f.control);
  dir.write("system/mpmSchemes", f.schemes);
  dir.write("system/gridDict", f.grid);
  dir.write("constant/g", f.gravity);
  dir.write("constant/materialProperties", f.materials);
  dir.write("constant/bodies", f.bodies);
  dir.write("constant/boundaryConditions", f.boundaries);
}

inline RunOptions options(int threads = 2) {
  RunOptions o;
  o.device = test_device();
  o.threads = threads;
  o.progress = false;
  o.output = false;
  static std::ostringstream sink;
  o.log = &sink;
  return o;
}

/// The field `name` of body `b`; throws if the body has none.
inline const FieldData& field(const BodySnapshot& b, const char* name) {
  const FieldData* f = b.find(name);
  if (!f) throw std::runtime_error(std::string("no field ") + name);
  return *f;
}

/// A body's mass-weighted mean velocity and its centre of mass (z = 0 in 2D).
struct BodyMotion {
  std::array<double, 3> v, x;
};

/// Runs the case written in `tc` on `threads` threads and returns its first body's motion at
/// each of `times` (increasing): the blocks sliding and thrown in the boundary tests.
inline std::vector<BodyMotion> body_motion(const TempCase& tc, const std::vector<double>& times, int threads = 1) {
  Case c = Case::read(tc.dir(), runtime());
  Simulation sim(c, runtime(), options(threads));
  std::vector<BodyMotion> out;
  for (double t : times) {
    sim.advance_to(t);
    const Snapshot s = sim.snapshot();
    const BodySnapshot& b = s.bodies.at(0);
    const auto& v = field(b, "velocity").values;
    const auto& m = field(b, "mass").values;
    BodyMotion mo{{0, 0, 0}, {0, 0, 0}};
    double mass = 0;
    for (Index i = 0; i < b.n; ++i) {
      for (int d = 0; d < 3; ++d) {
        mo.v[d] += m[i] * v[3 * i + d];
        mo.x[d] += m[i] * b.position[3 * i + d];
      }
      mass += m[i];
    }
    for (int d = 0; d < 3; ++d) {
      mo.v[d] /= mass;
      mo.x[d] /= mass;
    }
    out.push_back(mo);
  }
  return out;
}

/// The least-squares slope of v(t): an acceleration fitted to velocities.
inline double least_squares_slope(const std::vector<double>& t, const std::vector<double>& v) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  const double n = static_cast<double>(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    st += t[i];
    sv += v[i];
    stt += t[i] * t[i];
    stv += t[i] * v[i];
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

}  // namespace scree::test

/// main() for test executables that accept --device=cuda.
#define SCREE_TEST_MAIN()                               \
  int main(int argc, char** argv) {                     \
    ::testing::InitGoogleTest(&argc, argv);             \
    ::scree::test::parse_device_flag(argc, argv);       \
    return RUN_ALL_TESTS();                             \
  }

// Fuzz target: a case directory with one file replaced, validated as `scree --check`
// validates it (Case::read, check_setup, existing_results), never run.
//
// Input: the first byte chooses the file, (byte - '0') mod 7 indexing kFiles below
// ('0' controlDict ... '6' g); the remaining bytes are its new contents. The other files
// are those of the seed case (SCREE_FUZZ_SEED_CASE, default cases/elasticColumn), copied
// once into a scratch directory per process; each input first restores the file the
// previous input replaced.
//
// Every input must end in a valid case or in InputError(s) each naming its file (and a
// line where the parser reports it); any other exception, a crash, a sanitizer report or
// a hang is a finding. The memory check is given 256 MiB of free memory
// (SCREE_TEST_FREE_MEMORY, the test hook of memory_estimate.hpp), so that a case too
// large for that is rejected before the checks that visit every node and particle: the
// fuzzer looks for wrong behaviour, not for cases that are merely large.
#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "fuzz_common.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/case/case.hpp"
#include "scree/case/setup_check.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kFiles[] = {"system/controlDict",          "system/gridDict",
                                  "system/mpmSchemes",           "constant/bodies",
                                  "constant/materialProperties", "constant/boundaryConditions",
                                  "constant/g"};
constexpr int kNumFiles = 7;

struct State {
  fs::path dir;                      // the scratch copy of the seed case
  std::string original[kNumFiles];   // the seed's contents ("" and !present: absent)
  bool present[kNumFiles] = {};
  int replaced = -1;                 // the file the last input replaced
  // Keeps every default plugin loaded for the whole process, so that the runtime made
  // for each input only adds a reference to each library instead of loading it anew.
  std::unique_ptr<scree::PluginRuntime> anchor;
};

State& state() {
  static State s = [] {
    State st;
    const char* seed = std::getenv("SCREE_FUZZ_SEED_CASE");
    const fs::path from = seed ? fs::path(seed) : fs::path(SCREE_SOURCE_DIR) / "cases/elasticColumn";
    st.dir = scree::fuzz::scratch_dir("case") / "case";
    fs::create_directories(st.dir / "system");
    fs::create_directories(st.dir / "constant");
    for (int i = 0; i < kNumFiles; ++i) {
      std::ifstream in(from / kFiles[i], std::ios::binary);
      if (!in) continue;
      std::stringstream ss;
      ss << in.rdbuf();
      st.original[i] = ss.str();
      st.present[i] = true;
      std::ofstream(st.dir / kFiles[i], std::ios::binary) << st.original[i];
    }
    // Validation only: one thread, and a memory limit that keeps the checks small.
    ::setenv("SCREE_TEST_FREE_MEMORY", "268435456", 1);
    omp_set_num_threads(1);
    st.anchor = std::make_unique<scree::PluginRuntime>();
    st.anchor->load_default_plugins();
    return st;
  }();
  return s;
}

void restore(State& s, int i) {
  std::error_code ec;
  if (s.present[i]) {
    std::ofstream(s.dir / kFiles[i], std::ios::binary | std::ios::trunc) << s.original[i];
  } else {
    fs::remove(s.dir / kFiles[i], ec);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)state();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  State& s = state();
  if (s.replaced >= 0) restore(s, s.replaced);
  const int which = static_cast<std::uint8_t>(data[0] - '0') % kNumFiles;
  {
    std::ofstream out(s.dir / kFiles[which], std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  s.replaced = which;

  try {
    scree::PluginRuntime rt;  // `libs` of a controlDict load into this one only
    rt.load_default_plugins();
    const scree::Case c = scree::Case::read(s.dir, rt);
    scree::SetupReport r = scree::check_setup(c, rt, true, scree::Device::cpu);
    for (const auto& w : r.warnings) scree::fuzz::check_located(w, false);
    for (const auto& e : r.errors) scree::fuzz::check_located(e, false);
    (void)scree::existing_results(c, rt.registry());
  } catch (const scree::InputErrors& e) {
    if (e.errors().empty()) scree::fuzz::finding("InputErrors without an error");
    for (const auto& err : e.errors()) scree::fuzz::check_located(err, false);
  } catch (const scree::InputError& e) {
    scree::fuzz::check_located(e, false);
  } catch (const std::exception& e) {
    scree::fuzz::finding(std::string("an exception other than InputError(s): ") + e.what());
  } catch (...) {
    scree::fuzz::finding("an exception that is no std::exception");
  }
  return 0;
}

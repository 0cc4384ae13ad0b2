// scree-bench: the performance harness (issue 6).
//
//   scree-bench [--device cpu|cuda|both] [--quick] [--cases column,flume,scaling]
//               [--steps N] [--cpu-steps N] [--max-particles N] [--csv FILE] [--json FILE]
//
// For each case and backend it runs the solver without output for a fixed number of
// steps (after warm-up steps that also capture the CUDA graphs) and reports:
//   particles, steps, ms/step, particle-steps/s, bytes of state per particle,
//   effective bandwidth = modelled bytes per step / time, against the device's measured
//   copy bandwidth, and the peak device memory.
// The modelled traffic is the floor of an ideal implementation: every particle column
// read and written once per particle pass, every grid field read and written once per
// grid update (see traffic_per_step). Output (VTK, function objects) is excluded.
//
// Cases: (a) cases/columnCollapse (the paper's 80,000 points at 1 mm); (b) cases/flume at
// 5 mm; (c) weak scaling of a granular block resting on a floor from 1e4 to 1e7 particles,
// for linearElastic and phaseTransition and each shape function.
#include <omp.h>

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#include <map>
#include <algorithm>
#include <unistd.h>

#include "scree/exec/memory.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/solver/case.hpp"
#include "scree/solver/simulation.hpp"

namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace {

struct Row {
  std::string name, device, material, shape, scheme;
  long long particles = 0, nodes = 0, steps = 0;
  double ms_per_step = 0, particle_steps_per_s = 0, bytes_per_particle = 0, effective_gbs = 0,
         copy_gbs = 0, peak_mb = 0;
};

/// Device-to-device (or host memcpy) bandwidth, counting bytes read plus bytes written.
double copy_bandwidth(scree::Device d) {
  const std::size_t n = (d == scree::Device::cuda ? 1024ull : 256ull) << 20;
  scree::Buffer<char> a(n, d), b(n, d);
  scree::mem::copy(b.data(), d, a.data(), d, n);  // warm-up
  scree::mem::synchronize(d);
  const int reps = 5;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < reps; ++i) scree::mem::copy(b.data(), d, a.data(), d, n);
  scree::mem::synchronize(d);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return 2.0 * n * reps / s / 1e9;
}

/// Modelled bytes per step: each particle pass reads and writes every particle column
/// once; each grid update reads and writes the grid set (1 + 4D fields) once.
double traffic_per_step(const scree::RunStats& st, const std::string& scheme, int dim) {
  const int passes = scheme == "USL" ? 1 : 2;
  const int grid_updates = scheme == "USL" ? 1 : 2;
  const double particle = 2.0 * passes * double(st.bytes_per_particle) * st.particles;
  const double grid = 2.0 * grid_updates * double(st.nodes) * (1 + 4 * dim) * sizeof(double);
  return particle + grid;
}

std::string read_word(const fs::path& file, const std::string& key, const std::string& def) {
  try {
    return scree::Dictionary::read_file(file).get_word_or(key, def);
  } catch (...) {
    return def;
  }
}

Row measure(scree::PluginRuntime& rt, const fs::path& dir, const std::string& name, scree::Device dev,
            int threads, long long warm, long long steps, double copy_gbs) {
  scree::Case c = scree::Case::read(dir, rt);
  scree::RunOptions o;
  o.device = dev;
  o.threads = threads;
  o.output = false;
  o.progress = false;
  static std::ostringstream sink;
  o.log = &sink;
  scree::mem::reset_peak(dev);
  scree::Simulation sim(c, rt, o);
  sim.run_steps(warm);
  scree::mem::synchronize(dev);
  const auto t0 = std::chrono::steady_clock::now();
  sim.run_steps(steps);
  scree::mem::synchronize(dev);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const scree::RunStats st = sim.stats();
  Row r;
  r.name = name;
  r.device = scree::to_string(dev);
  r.scheme = read_word(dir / "system/mpmSchemes", "updateScheme", "USF");
  r.shape = read_word(dir / "system/mpmSchemes", "shapeFunction", "linear");
  r.particles = st.particles;
  r.nodes = st.nodes;
  r.steps = steps;
  r.ms_per_step = 1e3 * s / steps;
  r.particle_steps_per_s = double(st.particles) * steps / s;
  r.bytes_per_particle = double(st.bytes_per_particle);
  r.effective_gbs = traffic_per_step(st, r.scheme, sim.dimension()) * steps / s / 1e9;
  r.copy_gbs = copy_gbs;
  r.peak_mb = double(st.peak_device_bytes) / (1 << 20);
  for (const scree::Entry& b : c.bodies().entries())
    if (b.is_dict()) {
      r.material = c.materials().sub(b.dict().get_word("material")).get_word("type");
      break;
    }
  return r;
}

/// A granular block of about n particles (4 per cell) resting on a floor.
fs::path write_block_case(const fs::path& root, long long n, const std::string& material, const std::string& shape,
                          const std::string& scheme, const fs::path& source_dir) {
  const long long cells = std::max(1LL, n / 4);
  const long long side = std::max(4LL, static_cast<long long>(std::llround(std::sqrt(double(cells)))));
  const double h = 1.0 / side;  // a 1 m x 1 m block
  std::ostringstream tag;
  tag << "block_" << material << "_" << shape << "_" << scheme << "_" << n;
  const fs::path d = root / tag.str();
  fs::create_directories(d / "system");
  fs::create_directories(d / "constant");
  auto put = [&](const std::string& rel, const std::string& text) { std::ofstream(d / rel) << text; };
  put("system/controlDict", "endTime 100;\ndeltaT " + std::to_string(0.2 * h / 60.0) + ";\nwriteInterval 100;\n");
  std::ostringstream grid;
  grid << "dimension 2;\nlower (0 0);\nupper (1.5 1.2);\ncellSize " << std::setprecision(12) << h << ";\n";
  put("system/gridDict", grid.str());
  put("system/mpmSchemes", "updateScheme " + scheme + ";\nshapeFunction " + shape + ";\n" +
                               (shape == "linear" ? "" : "transfer APIC;\n") + "sortInterval 50;\n");
  put("constant/g", "value (0 -9.81);\n");
  // Materials: the column-collapse sand from cases/columnCollapse, or an elastic solid.
  std::string mats;
  if (material == "phaseTransition") {
    std::ifstream f(source_dir / "constant/materialProperties");
    std::stringstream ss;
    ss << f.rdbuf();
    mats = ss.str();
  } else {
    mats = "sand { type linearElastic; E 5e6; nu 0.3; rho 1500; }\n";
  }
  put("constant/materialProperties", mats);
  put("constant/bodies", "block { material sand; region { type rectangle; lower (0 0); upper (1 1); } "
                         "particlesPerCell 2; initialStress { type geostatic; K0 0.5; } }\n");
  put("constant/boundaryConditions", "floor { type fixed; face yMin; } left { type slip; face xMin; }\n");
  return d;
}

void print(const std::vector<Row>& rows) {
  std::printf("\n%-34s %-5s %-15s %-8s %-4s %10s %8s %10s %12s %6s %9s %8s %9s\n", "case", "dev", "material", "shape",
              "schm", "particles", "steps", "ms/step", "p-steps/s", "B/p", "eff GB/s", "copy", "peak MB");
  for (const Row& r : rows)
    std::printf("%-34s %-5s %-15s %-8s %-4s %10lld %8lld %10.4f %12.4g %6.0f %9.1f %8.0f %9.1f\n", r.name.c_str(),
                r.device.c_str(), r.material.c_str(), r.shape.c_str(), r.scheme.c_str(), r.particles, r.steps,
                r.ms_per_step, r.particle_steps_per_s, r.bytes_per_particle, r.effective_gbs, r.copy_gbs, r.peak_mb);
  // GPU/CPU ratios for cases measured on both.
  for (const Row& g : rows)
    if (g.device == "cuda")
      for (const Row& c : rows)
        if (c.device == "cpu" && c.name == g.name)
          std::printf("GPU/CPU %-30s %8.1fx (particle-steps/s)\n", g.name.c_str(),
                      g.particle_steps_per_s / c.particle_steps_per_s);
}

void write_csv(const std::vector<Row>& rows, const std::string& path) {
  std::ofstream f(path);
  f << "case,device,material,shape,scheme,particles,nodes,steps,ms_per_step,particle_steps_per_s,"
       "bytes_per_particle,effective_GBps,copy_GBps,peak_device_MB\n";
  for (const Row& r : rows)
    f << r.name << ',' << r.device << ',' << r.material << ',' << r.shape << ',' << r.scheme << ',' << r.particles
      << ',' << r.nodes << ',' << r.steps << ',' << r.ms_per_step << ',' << r.particle_steps_per_s << ','
      << r.bytes_per_particle << ',' << r.effective_gbs << ',' << r.copy_gbs << ',' << r.peak_mb << '\n';
}

void write_json(const std::vector<Row>& rows, const std::string& path) {
  std::ofstream f(path);
  f << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    f << "  {\"case\": \"" << r.name << "\", \"device\": \"" << r.device << "\", \"material\": \"" << r.material
      << "\", \"shape\": \"" << r.shape << "\", \"scheme\": \"" << r.scheme << "\", \"particles\": " << r.particles
      << ", \"nodes\": " << r.nodes << ", \"steps\": " << r.steps << ", \"ms_per_step\": " << r.ms_per_step
      << ", \"particle_steps_per_s\": " << r.particle_steps_per_s << ", \"bytes_per_particle\": "
      << r.bytes_per_particle << ", \"effective_GBps\": " << r.effective_gbs << ", \"copy_GBps\": " << r.copy_gbs
      << ", \"peak_device_MB\": " << r.peak_mb << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  f << "]\n";
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description opts("scree-bench: Scree's performance harness\n\nOptions");
  opts.add_options()("help,h", "print this help")(
      "device", po::value<std::string>()->default_value("both"), "cpu, cuda or both (cuda only when a GPU is present)")(
      "quick", "tiny sizes and few steps (CI)")("cases", po::value<std::string>()->default_value("column,flume,scaling"),
                                                "comma-separated: column, flume, scaling")(
      "steps", po::value<long long>()->default_value(2000), "timed steps on the GPU")(
      "cpu-steps", po::value<long long>()->default_value(50), "timed steps on the CPU")(
      "max-particles", po::value<long long>()->default_value(10000000), "largest scaling size")(
      "threads", po::value<int>()->default_value(omp_get_max_threads()), "CPU threads")(
      "source-dir", po::value<std::string>()->default_value(SCREE_SOURCE_DIR), "the Scree source tree (for cases/)")(
      "csv", po::value<std::string>()->default_value("scree-bench.csv"), "CSV output")(
      "json", po::value<std::string>()->default_value("scree-bench.json"), "JSON output");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, opts), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "scree-bench: " << e.what() << "\n" << opts;
    return 2;
  }
  if (vm.count("help")) {
    std::cout << opts;
    return 0;
  }
  const bool quick = vm.count("quick");
  const fs::path src = vm["source-dir"].as<std::string>();
  const std::string want = vm["cases"].as<std::string>();
  const std::string devs = vm["device"].as<std::string>();
  std::vector<scree::Device> devices;
  if (devs == "cpu" || devs == "both") devices.push_back(scree::Device::cpu);
  if ((devs == "cuda" || devs == "both") && scree::mem::cuda_available()) devices.push_back(scree::Device::cuda);
  if (devs == "cuda" && devices.empty()) {
    std::cerr << "scree-bench: --device cuda: no CUDA GPU available\n";
    return 2;
  }
  const int threads = vm["threads"].as<int>();
  const long long gpu_steps = quick ? 20 : vm["steps"].as<long long>();
  const long long cpu_steps = quick ? 5 : vm["cpu-steps"].as<long long>();
  const long long max_n = quick ? 1000 : vm["max-particles"].as<long long>();

  scree::PluginRuntime rt;
  rt.load_default_plugins();
  const fs::path tmp = fs::temp_directory_path() / ("scree-bench-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  std::vector<Row> rows;
  std::map<scree::Device, double> copy;
  for (auto d : devices) copy[d] = copy_bandwidth(d);
  std::printf("copy bandwidth (read + write): ");
  for (auto& [d, bw] : copy) std::printf("%s %.1f GB/s  ", scree::to_string(d), bw);
  std::printf("\nCPU threads: %d\n", threads);

  auto run = [&](const fs::path& dir, const std::string& name, long long gsteps, long long csteps) {
    for (auto d : devices) {
      const long long steps = d == scree::Device::cuda ? gsteps : csteps;
      try {
        rows.push_back(measure(rt, dir, name, d, threads, std::max(2LL, steps / 10), steps, copy[d]));
        const Row& r = rows.back();
        std::printf("  %-34s %-4s %10lld particles %10.4f ms/step %12.4g particle-steps/s\n", name.c_str(),
                    r.device.c_str(), r.particles, r.ms_per_step, r.particle_steps_per_s);
        std::fflush(stdout);
      } catch (const std::exception& e) {
        std::printf("  %-34s %-4s failed: %s\n", name.c_str(), scree::to_string(d), e.what());
      }
    }
  };

  if (want.find("column") != std::string::npos) {
    const fs::path c = quick ? src / "cases/columnCollapse/variants/C-1" : src / "cases/columnCollapse";
    run(c, quick ? "column C-1 (10 mm)" : "column (1 mm, paper)", gpu_steps, cpu_steps);
  }
  if (want.find("flume") != std::string::npos && fs::exists(src / "cases/flume")) {
    const fs::path c = quick ? src / "cases/flume/variants/S-1" : src / "cases/flume";
    if (fs::exists(c)) run(c, quick ? "flume S-1 (20 mm)" : "flume (5 mm, paper)", gpu_steps, cpu_steps);
  }
  if (want.find("scaling") != std::string::npos) {
    for (const std::string mat : {"linearElastic", "phaseTransition"})
      for (const std::string shape : {"linear", "gimp", "bspline2"})
        for (long long n = quick ? 1000 : 10000; n <= max_n; n *= 10) {
          const fs::path d = write_block_case(tmp, n, mat, shape, "USL", src / "cases/columnCollapse");
          // The CPU gets the sizes up to 1e6 only (minutes otherwise).
          const auto saved = devices;
          if (n > 1000000) devices.erase(std::remove(devices.begin(), devices.end(), scree::Device::cpu), devices.end());
          run(d, "block " + mat + " " + shape + " " + std::to_string(n), std::max(20LL, gpu_steps / 4), cpu_steps);
          devices = saved;
        }
  }
  print(rows);
  write_csv(rows, vm["csv"].as<std::string>());
  write_json(rows, vm["json"].as<std::string>());
  std::printf("\nwrote %s and %s\n", vm["csv"].as<std::string>().c_str(), vm["json"].as<std::string>().c_str());
  std::error_code ec;
  fs::remove_all(tmp, ec);
  return 0;
}

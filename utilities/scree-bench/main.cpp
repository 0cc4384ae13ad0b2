// scree-bench: the performance harness (docs/performance.md).
//
//   scree-bench [--device cpu|cuda|both] [--quick] [--cases column,flume,scaling,cpu,updates]
//               [--kernels fast,reference,uncapped] [--steps N] [--cpu-steps N]
//               [--max-particles N] [--dimensions 2,3] [--column-steps N] [--column-late-at STEP] [--flume-steps N]
//               [--flume-late-at STEP]
//               [--csv FILE] [--json FILE]
//
// For each case, backend and kernel variant it runs the solver without output for a fixed
// number of steps (after warm-up steps that also capture the CUDA graphs) and reports:
//   particles, steps, ms/step, particle-steps/s, bytes of state per particle,
//   effective bandwidth = modelled bytes per step / time, against the device's measured
//   copy bandwidth, and the peak device memory.
// The modelled traffic is the floor of an ideal implementation: every particle column
// read and written once per particle pass, every grid field read and written once per
// grid update (see traffic_per_step). Output (VTK, function objects) is excluded.
//
// Cases: (a) cases/columnCollapse (the paper's 80,000 points at 1 mm), timed in three
// windows: before the release (the column at rest), right after it and later in the
// collapse (from step 60,000 by default; plastic flow, points sheared apart at the free
// surface, whose slowest stress updates set the step time); the wall time of the paper's
// 100,000 steps is estimated from them. (b) cases/flume at 5 mm, at rest, right after the
// release (at 0.05 s: step 2,500 at the case's dt of 2e-5 s) and later in the flow (from
// step 150,000 by default: about 1.3 s, the flow reaching the floor, where a step costs
// several times the first flowing steps'); the whole run takes about 406,000 steps.
// (c) weak scaling of a granular block resting on a floor from 1e4 to 1e7 particles,
// for linearElastic and phaseTransition and each shape function, in 2D (a square) and,
// with --dimensions 3, in 3D (a cube). (d) cpu: Scree's CPU
// backend against a straightforward scalar loop written for the comparison
// (scalar_mpm.hpp), particle-steps/s per core. (e) updates: the slow SIMSAND stress
// updates recorded in the column collapse (5 mm cells), replayed on one CPU thread (us per
// update; replay_updates).
// Kernel variants: fast (default), reference (KernelPolicy::reference_kernels(): the
// straightforward kernels), uncapped (fast, but the 2D stress kernel without its register
// cap: KernelPolicy::stress_blocks_per_sm = 0), split / unsplit (fast, with the stress pass
// always split in an elastic-only kernel and one for the rest, or never: KernelPolicy::
// split on / off; fast lets the solver time both and choose), elastic-uncapped
// (the split always, its elastic-only kernel without a register cap:
// KernelPolicy::elastic_blocks_per_sm = 0).
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

#include "linearElastic/LinearElastic.hpp"
#include "phaseTransition/PhaseTransition.hpp"
#include "scalar_mpm.hpp"
#include "scree/case/case.hpp"
#include "scree/exec/memory.hpp"
#include "scree/materials/simsand_recorded_updates.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/solver/simulation.hpp"

#if defined(SCREE_HAVE_CUDA)
#include <cuda_runtime_api.h>
#endif

namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace {

struct Row {
  std::string name, device, variant, material, shape, scheme;
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

std::string device_name(scree::Device d) {
  if (d == scree::Device::cpu) {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
      if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "cpu";
  }
#if defined(SCREE_HAVE_CUDA)
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) == cudaSuccess) {
    std::ostringstream os;
    os << prop.name << ", " << prop.multiProcessorCount << " SMs, " << (prop.totalGlobalMem >> 20) << " MiB, L2 "
       << (prop.l2CacheSize >> 20) << " MiB";
    return os.str();
  }
#endif
  return "cuda";
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

scree::RunOptions options_for(scree::Device dev, int threads, const std::string& variant) {
  scree::RunOptions o;
  o.device = dev;
  o.threads = threads;
  o.output = false;
  o.progress = false;
  scree::KernelPolicy& k = o.kernels;
  if (variant == "reference") k = scree::KernelPolicy::reference_kernels();
  if (variant == "uncapped") k.stress_blocks_per_sm = 0;
  if (variant == "split") k.split = scree::StressSplit::on;
  if (variant == "unsplit") k.split = scree::StressSplit::off;
  if (variant.rfind("speed-every-", 0) == 0) k.speed_every = std::stoi(variant.substr(12));
  if (variant.rfind("refill-lanes-", 0) == 0) k.refill_lanes = std::stoi(variant.substr(13));
  if (variant == "no-health") k.health_checks = false;
  if (variant == "no-refill") k.refill = false;
  // The energy ledger on, as a case with `energies { budget yes; }` runs it (ParticlePass's
  // Ledger kernels): what the budget costs a step; ledger-NAME: its kernels by name
  // (KernelPolicy::set_ledger_kernels: unsplit, whole), to time the older ones against
  if (variant == "ledger") o.energy_ledger = true;
  if (variant.rfind("ledger-", 0) == 0) o.energy_ledger = k.set_ledger_kernels(variant.substr(7));
  if (variant == "elastic-uncapped") {
    k.split = scree::StressSplit::on;
    k.elastic_blocks_per_sm = 0;
  }
  static std::ostringstream sink;
  o.log = &sink;
  return o;
}

Row make_row(const scree::Case& c, const fs::path& dir, const std::string& name, scree::Device dev,
             const std::string& variant, const scree::RunStats& st, int dim, long long steps, double seconds,
             double copy_gbs) {
  Row r;
  r.name = name;
  r.device = scree::to_string(dev);
  r.variant = variant;
  r.scheme = read_word(dir / "system/mpmSchemes", "updateScheme", "USF");
  r.shape = read_word(dir / "system/mpmSchemes", "shapeFunction", "linear");
  r.particles = st.particles;
  r.nodes = st.nodes;
  r.steps = steps;
  r.ms_per_step = 1e3 * seconds / steps;
  r.particle_steps_per_s = double(st.particles) * steps / seconds;
  r.bytes_per_particle = double(st.bytes_per_particle);
  r.effective_gbs = traffic_per_step(st, r.scheme, dim) * steps / seconds / 1e9;
  r.copy_gbs = copy_gbs;
  r.peak_mb = double(st.peak_device_bytes) / (1 << 20);
  if (const auto bodies = c.body_entries(); !bodies.empty())
    r.material = c.materials().sub(bodies.front()->dict().get_word("material")).get_word("type");
  return r;
}

/// A window of steps: timed (`steps` steps), or, with a label starting with '-', run untimed
/// to skip to the next: `steps` steps, or up to step `to_step` or time `to_time` where set.
struct Window {
  std::string label;
  long long steps = 0;
  long long to_step = -1;
  double to_time = -1;
};

/// Run `warm` steps, then time each window of the following steps (one row per timed
/// window). The time of a window is its steps' wall time, the host's progress bookkeeping
/// included, output excluded.
std::vector<Row> measure_windows(scree::PluginRuntime& rt, const fs::path& dir, const std::string& name,
                                 scree::Device dev, int threads, const std::string& variant, long long warm,
                                 const std::vector<Window>& windows, double copy_gbs) {
  scree::Case c = scree::Case::read(dir, rt);
  const scree::RunOptions o = options_for(dev, threads, variant);
  scree::mem::reset_peak(dev);
  scree::Simulation sim(c, rt, o);
  if (warm > 0) sim.run_steps(warm);
  scree::mem::synchronize(dev);
  std::vector<Row> rows;
  long long done = warm;
  for (const auto& [label, steps, to_step, to_time] : windows) {
    if (!label.empty() && label[0] == '-') {
      if (to_time >= 0)
        sim.advance_to(to_time);
      else
        sim.run_steps(to_step >= 0 ? std::max(0LL, to_step - static_cast<long long>(sim.steps())) : steps);
      done = static_cast<long long>(sim.steps());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    sim.run_steps(steps);
    scree::mem::synchronize(dev);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream nm;
    nm << name << (label.empty() ? "" : " " + label);
    rows.push_back(make_row(c, dir, nm.str(), dev, variant, sim.stats(), sim.dimension(), steps, s, copy_gbs));
    done += steps;
  }
  return rows;
}

/// The block's material: the column-collapse sand (phaseTransition) or an elastic solid
/// (linearElastic; twoPhase: the same solid as the skeleton of a two-phase body).
std::string material_dictionary(const std::string& material, const fs::path& source_dir) {
  if (material != "phaseTransition") return "sand { type linearElastic; E 5e6; nu 0.3; rho 1500; }\n";
  std::ifstream f(source_dir / "cases/columnCollapse/constant/materialProperties");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// A granular block of about n particles resting on a floor: in 2D a 1 m x 1 m block,
/// 4 points per cell; in 3D a 1 m cube, 8 points per cell, with slip walls at x = 0 and
/// z = 0 (the same block, quartered by its symmetry planes).
fs::path write_block_case(const fs::path& root, long long n, const std::string& material, const std::string& shape,
                          const std::string& scheme, const fs::path& source_dir, int dim = 2) {
  const long long cells = std::max(1LL, n / (dim == 2 ? 4 : 8));
  const double root_of_cells = dim == 2 ? std::sqrt(double(cells)) : std::cbrt(double(cells));
  const long long side = std::max(4LL, static_cast<long long>(std::llround(root_of_cells)));
  const double h = 1.0 / side;  // a 1 m block
  std::ostringstream tag;
  tag << (dim == 2 ? "block_" : "block3d_") << material << "_" << shape << "_" << scheme << "_" << n;
  const fs::path d = root / tag.str();
  fs::create_directories(d / "system");
  fs::create_directories(d / "constant");
  auto put = [&](const std::string& rel, const std::string& text) { std::ofstream(d / rel) << text; };
  put("system/controlDict", "endTime 100;\ndeltaT " + std::to_string(0.2 * h / 60.0) + ";\nwriteInterval 100;\n");
  std::ostringstream grid;
  if (dim == 2)
    grid << "dimension 2;\nlower (0 0);\nupper (1.5 1.2);\ncellSize " << std::setprecision(12) << h << ";\n";
  else
    grid << "dimension 3;\nlower (0 0 0);\nupper (1.25 1.1 1.25);\ncellSize " << std::setprecision(12) << h << ";\n";
  put("system/gridDict", grid.str());
  put("system/mpmSchemes", "updateScheme " + scheme + ";\nshapeFunction " + shape + ";\n" +
                               (shape == "linear" ? "" : "transfer APIC;\n") + "sortInterval 50;\n");
  put("constant/g", dim == 2 ? "value (0 -9.81);\n" : "value (0 -9.81 0);\n");
  put("constant/materialProperties", material_dictionary(material, source_dir));
  // twoPhase: the elastic block as the skeleton of unsaturated soil (porous/two_phase.hpp),
  // van Genuchten and Mualem, a water table at mid-height; K_l = 2 MPa keeps the undrained
  // wave (about 75 m/s) inside the fixed step's Courant number (0.25).
  const std::string pores =
      material == "twoPhase"
          ? "twoPhase { porosity 0.3; liquidBulkModulus 2e6; hydraulicConductivity 1e-4; "
            "retention { type vanGenuchten; p0 22295; lambda 0.671; Smin 0.23; Smax 1; } "
            "permeability { type mualemVanGenuchten; } initialPorePressure { type hydrostatic; waterTable 0.5; } } "
          : "";
  put("constant/bodies", std::string("block { material sand; region { ") +
                             (dim == 2 ? "type rectangle; lower (0 0); upper (1 1);"
                                       : "type box; lower (0 0 0); upper (1 1 1);") +
                             " } particlesPerCell 2; initialStress { type geostatic; K0 0.5; } " + pores + "}\n");
  put("constant/boundaryConditions", std::string("floor { type fixed; face yMin; } left { type slip; face xMin; }\n") +
                                         (dim == 3 ? "back { type slip; face zMin; }\n" : ""));
  return d;
}

void print(const std::vector<Row>& rows) {
  std::printf("\n%-44s %-4s %-9s %-15s %-8s %-4s %10s %7s %10s %11s %5s %8s %6s %9s\n", "case", "dev", "kernels",
              "material", "shape", "schm", "particles", "steps", "ms/step", "p-steps/s", "B/p", "eff GB/s", "copy",
              "peak MB");
  for (const Row& r : rows)
    std::printf("%-44s %-4s %-9s %-15s %-8s %-4s %10lld %7lld %10.4f %11.4g %5.0f %8.1f %6.0f %9.1f\n",
                r.name.c_str(), r.device.c_str(), r.variant.c_str(), r.material.c_str(), r.shape.c_str(),
                r.scheme.c_str(), r.particles, r.steps, r.ms_per_step, r.particle_steps_per_s, r.bytes_per_particle,
                r.effective_gbs, r.copy_gbs, r.peak_mb);
  // GPU/CPU ratios for cases measured on both.
  for (const Row& g : rows)
    if (g.device == "cuda")
      for (const Row& c : rows)
        if (c.device == "cpu" && c.name == g.name && c.variant == g.variant)
          std::printf("GPU/CPU %-40s %8.1fx (particle-steps/s)\n", g.name.c_str(),
                      g.particle_steps_per_s / c.particle_steps_per_s);
}

void write_csv(const std::vector<Row>& rows, const std::string& path) {
  std::ofstream f(path);
  f << "case,device,kernels,material,shape,scheme,particles,nodes,steps,ms_per_step,particle_steps_per_s,"
       "bytes_per_particle,effective_GBps,copy_GBps,peak_device_MB\n";
  for (const Row& r : rows)
    f << r.name << ',' << r.device << ',' << r.variant << ',' << r.material << ',' << r.shape << ',' << r.scheme
      << ',' << r.particles << ',' << r.nodes << ',' << r.steps << ',' << r.ms_per_step << ','
      << r.particle_steps_per_s << ',' << r.bytes_per_particle << ',' << r.effective_gbs << ',' << r.copy_gbs << ','
      << r.peak_mb << '\n';
}

void write_json(const std::vector<Row>& rows, const std::string& path) {
  std::ofstream f(path);
  f << "[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    f << "  {\"case\": \"" << r.name << "\", \"device\": \"" << r.device << "\", \"kernels\": \"" << r.variant
      << "\", \"material\": \"" << r.material << "\", \"shape\": \"" << r.shape << "\", \"scheme\": \"" << r.scheme
      << "\", \"particles\": " << r.particles << ", \"nodes\": " << r.nodes << ", \"steps\": " << r.steps
      << ", \"ms_per_step\": " << r.ms_per_step << ", \"particle_steps_per_s\": " << r.particle_steps_per_s
      << ", \"bytes_per_particle\": " << r.bytes_per_particle << ", \"effective_GBps\": " << r.effective_gbs
      << ", \"copy_GBps\": " << r.copy_gbs << ", \"peak_device_MB\": " << r.peak_mb << "}"
      << (i + 1 < rows.size() ? "," : "") << "\n";
  }
  f << "]\n";
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

/// The parameters of material `name` of a case, read as the plugin reads them.
template <class M>
typename M::Params case_material_params(const scree::Case& c, const std::string& name) {
  scree::ParamSpec spec = M::spec();
  spec.allow_keys({"type"});
  return M::read(scree::ParamReader(spec, c.materials().sub(name)));
}

/// Scree's CPU backend against the scalar loop on the same block (one thread each, then
/// Scree on every thread): particle-steps/s, and the ratio kept within 2 (docs/performance.md).
template <class M>
void cpu_comparison(scree::PluginRuntime& rt, const fs::path& root, const fs::path& src, const std::string& material,
                    long long n, long long steps, int threads, std::vector<Row>& rows) {
  const fs::path dir = write_block_case(root, n, material, "linear", "USL", src);
  const typename M::Params mp = case_material_params<M>(scree::Case::read(dir, rt), "sand");
  const long long cells = std::max(4LL, static_cast<long long>(std::llround(std::sqrt(double(std::max(1LL, n / 4))))));
  const double dt = 0.2 * (1.0 / cells) / 60.0;
  scree::bench::ScalarMpm<M> scalar(mp, static_cast<int>(cells), dt);
  scalar.step();  // warm-up
  const auto t0 = std::chrono::steady_clock::now();
  for (long long i = 0; i < steps; ++i) scalar.step();
  const double s_scalar = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Row r;
  r.name = "block " + material + " scalar loop 1 thread";
  r.device = "cpu";
  r.variant = "scalar";
  r.material = material;
  r.shape = "linear";
  r.scheme = "USL";
  r.particles = static_cast<long long>(scalar.size());
  r.steps = steps;
  r.ms_per_step = 1e3 * s_scalar / steps;
  r.particle_steps_per_s = double(r.particles) * steps / s_scalar;
  r.bytes_per_particle = sizeof(typename scree::bench::ScalarMpm<M>::Particle);
  rows.push_back(r);
  std::printf("  %-44s %10lld particles %10.4f ms/step %12.4g particle-steps/s\n", r.name.c_str(), r.particles,
              r.ms_per_step, r.particle_steps_per_s);
  for (int t : {1, threads}) {
    auto w = measure_windows(rt, dir, "block " + material + " scree " + std::to_string(t) + " thread" +
                                          (t > 1 ? "s" : ""),
                             scree::Device::cpu, t, "fast", 2, {{"", steps}}, 0);
    rows.push_back(w[0]);
    std::printf("  %-44s %10lld particles %10.4f ms/step %12.4g particle-steps/s (%.4g per core)\n",
                w[0].name.c_str(), w[0].particles, w[0].ms_per_step, w[0].particle_steps_per_s,
                w[0].particle_steps_per_s / t);
    if (t == 1)
      std::printf("  scalar loop / scree (1 thread), %s: %.2f (the target is at most 2)\n", material.c_str(),
                  r.particle_steps_per_s / w[0].particle_steps_per_s);
    if (threads == 1) break;
  }
}

/// (e) updates: the slow SIMSAND stress updates recorded in the column collapse at its shipped tolerance
/// (simsand-slow-updates-5mm-column.txt beside this file), replayed through simsand::integrate on one CPU thread with
/// the column case's own parameters. On the GPU the late step lasts as long as the slowest such update in one
/// lane, so their cost per update is the CPU's proxy for that step.
void replay_updates(scree::PluginRuntime& rt, const fs::path& src, std::vector<Row>& rows) {
  namespace ss = scree::materials::simsand;
  const fs::path data = src / "utilities/scree-bench/simsand-slow-updates-5mm-column.txt";
  std::ifstream in(data);
  if (!in) throw std::runtime_error(data.string() + ": cannot read the recorded updates");
  const std::vector<ss::RecordedUpdate> ups = ss::read_recorded_updates(in);
  if (ups.empty()) throw std::runtime_error(data.string() + ": no updates in it");
  const ss::Params P =
      case_material_params<scree::materials::PhaseTransition>(scree::Case::read(src / "cases/columnCollapse", rt), "sand")
          .f;
  double best = 1e300, sink = 0;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    for (const ss::RecordedUpdate& u : ups) {
      scree::Sym3 sig = u.sig;
      ss::Vars v = u.v;
      ss::integrate(P, sig, v, u.deps);
      sink += sig[0];
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  Row r;
  r.name = "simsand slow updates (replayed)";
  r.device = "cpu";
  r.variant = "fast";
  r.material = "phaseTransition";
  r.particles = static_cast<long long>(ups.size());
  r.steps = 1;
  r.ms_per_step = 1e3 * best;
  r.particle_steps_per_s = double(ups.size()) / best;
  rows.push_back(r);
  std::printf("  %-44s %10lld updates %8.2f us per update (best of 5; checksum %.6g)\n", r.name.c_str(), r.particles,
              1e6 * best / double(ups.size()), sink / 5);
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description opts("scree-bench: Scree's performance harness\n\nOptions");
  opts.add_options()("help,h", "print this help")(
      "device", po::value<std::string>()->default_value("both"), "cpu, cuda or both (cuda only when a GPU is present)")(
      "quick", "tiny sizes and few steps (CI)")(
      "cases", po::value<std::string>()->default_value("column,flume,scaling,cpu,updates"),
      "comma-separated: column, flume, scaling, cpu, updates (CPU: the recorded slow SIMSAND "
      "updates)")(
      "kernels", po::value<std::string>()->default_value("fast"),
      "comma-separated kernel variants: fast, reference (the straightforward kernels), uncapped (CUDA: no register "
      "cap on the 2D stress kernel), split / unsplit (the stress pass always / never split in an elastic-only kernel and one for the rest; "
      "fast chooses by timing both), elastic-uncapped (CUDA: always split, no register cap on the elastic-only kernel), speed-every-N (a fixed step's "
      "signal speed, for the stopCo check, every N steps: KernelPolicy::speed_every), no-health (the kernels' health checks off, "
      "to measure their cost: KernelPolicy::health_checks), ledger (the energy ledger kept, as a case with energies' "
      "`budget yes` runs: RunOptions::energy_ledger), ledger-whole (the ledger in its whole-pass kernel, "
      "transfer and stress passes: KernelPolicy::ledger_light_transfer and ledger_split off), ledger-unsplit (the "
      "ledger's stress pass never split: KernelPolicy::ledger_split off), no-refill (CUDA: the split's deferred points one per "
      "lane for the whole pass: KernelPolicy::refill off), refill-lanes-N (CUDA: the lanes of a warp done before they take "
      "new deferred points together: KernelPolicy::refill_lanes)")("steps", po::value<long long>()->default_value(2000), "timed steps on the GPU")(
      "cpu-steps", po::value<long long>()->default_value(50), "timed steps on the CPU")(
      "max-particles", po::value<long long>()->default_value(10000000), "largest scaling size")(
      "materials", po::value<std::string>()->default_value("linearElastic,phaseTransition"),
      "scaling materials: linearElastic, phaseTransition, twoPhase (the elastic block with pore liquid)")(
      "shapes", po::value<std::string>()->default_value("linear,gimp,bspline2"), "scaling shape functions")(
      "schemes", po::value<std::string>()->default_value("USL"), "scaling update schemes")(
      "dimensions", po::value<std::string>()->default_value("2"),
      "scaling block dimensions: 2 (a square, 4 points per cell), 3 (a cube, 8 points per cell) or 2,3")(
      "column-steps", po::value<long long>()->default_value(2000),
      "column collapse: steps timed after the release (release at step 10,000)")(
      "column-late-at", po::value<long long>()->default_value(60000),
      "column collapse: step from which a second flowing window of column-steps steps is timed (GPU; 0: none): "
      "the late collapse, whose step costs several times the first steps after the release")(
      "flume-steps", po::value<long long>()->default_value(2000),
      "flume: steps timed after the release (release at step 2,500)")(
      "flume-late-at", po::value<long long>()->default_value(150000),
      "flume: step from which a second flowing window of flume-steps steps is timed (GPU; 0: none): "
      "the flow down the slope, whose step costs several times the first steps after the release")(
      "cpu-particles", po::value<long long>()->default_value(100000), "size of the CPU comparison block")(
      "threads", po::value<int>()->default_value(omp_get_max_threads()), "CPU threads")(
      "source-dir", po::value<std::string>()->default_value(SCREE_SOURCE_DIR), "the Scree source tree (for cases/)")(
      "write-block", po::value<std::string>(),
      "write the scaling case's block of --max-particles particles (the first of --materials, --shapes, "
      "--schemes and --dimensions) under this directory, print its path and exit (measure/gpu-ncu-block.sh)")(
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
  for (const std::string& d : split(vm["dimensions"].as<std::string>()))
    if (d != "2" && d != "3") {
      std::cerr << "scree-bench: --dimensions: '" << d << "' is not a dimension (valid: 2, 3, or 2,3)\n";
      return 2;
    }
  const bool quick = vm.count("quick");
  const fs::path src = vm["source-dir"].as<std::string>();
  const auto want = split(vm["cases"].as<std::string>());
  auto wants = [&](const char* c) { return std::find(want.begin(), want.end(), c) != want.end(); };
  const auto variants = split(vm["kernels"].as<std::string>());
  for (const std::string& v : variants) {  // a misspelt variant would run as `fast` under its own name
    static const std::vector<std::string> known = [] {
      std::vector<std::string> k = {"fast",      "reference", "uncapped", "split",           "unsplit",
                                    "no-health", "ledger",    "elastic-uncapped", "no-refill"};
      for (const char* w : scree::KernelPolicy::kLedgerKernels) k.push_back(std::string("ledger-") + w);
      return k;
    }();
    auto numbered = [&](const std::string& prefix) {
      return v.rfind(prefix, 0) == 0 && v.size() > prefix.size() &&
             v.find_first_not_of("0123456789", prefix.size()) == std::string::npos;
    };
    if (!numbered("speed-every-") && !numbered("refill-lanes-") && std::find(known.begin(), known.end(), v) == known.end()) {
      std::cerr << "scree-bench: --kernels: unknown variant '" << v << "'; valid:";
      for (const std::string& k : known) std::cerr << " " << k << ",";
      std::cerr << " speed-every-N, refill-lanes-N\n";
      return 2;
    }
  }
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
  if (vm.count("write-block")) {
    const fs::path dir = write_block_case(vm["write-block"].as<std::string>(), max_n,
                                          split(vm["materials"].as<std::string>()).at(0),
                                          split(vm["shapes"].as<std::string>()).at(0),
                                          split(vm["schemes"].as<std::string>()).at(0), src,
                                          split(vm["dimensions"].as<std::string>()).at(0) == "3" ? 3 : 2);
    std::cout << dir.string() << "\n";
    return 0;
  }

  scree::PluginRuntime rt;
  rt.load_default_plugins();
  const fs::path tmp = fs::temp_directory_path() / ("scree-bench-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  std::vector<Row> rows;
  std::map<scree::Device, double> copy;
  for (auto d : devices) {
    copy[d] = copy_bandwidth(d);
    std::printf("%s: %s; copy bandwidth (read + write) %.1f GB/s\n", scree::to_string(d), device_name(d).c_str(),
                copy[d]);
  }
  std::printf("CPU threads: %d\n", threads);
  auto report = [&](const Row& r) {
    std::printf("  %-44s %-4s %-9s %10lld particles %10.4f ms/step %12.4g particle-steps/s\n", r.name.c_str(),
                r.device.c_str(), r.variant.c_str(), r.particles, r.ms_per_step, r.particle_steps_per_s);
    std::fflush(stdout);
  };

  // (a), (b): the paper's cases, in windows before and after the release; the wall time of
  // the run the paper reports is estimated from them (output excluded).
  struct Paper {
    const char* key;
    std::string name;
    fs::path dir;
    long long release, after, total;  // steps: to the release (at rest), timed after it, of the paper's run
    long long late_at;                // step of the late flowing window (0: none)
  };
  // The flowing window starts at the case's release (system/stages: _releaseTime), however
  // many steps its adaptive step takes to get there.
  auto release_time = [&](const fs::path& dir) {
    const scree::Case c = scree::Case::read(dir, rt);
    const scree::Entry* e = c.control().find("_releaseTime");
    return e ? e->as_scalar() : -1.0;
  };
  std::vector<Paper> paper;
  if (wants("column"))
    paper.push_back({"column", quick ? "column C-1 (10 mm)" : "column 1 mm (paper)",
                     quick ? src / "cases/columnCollapse/variants/C-1" : src / "cases/columnCollapse",
                     quick ? 20 : 10000, quick ? 10 : vm["column-steps"].as<long long>(), 100000,
                     quick ? 0 : vm["column-late-at"].as<long long>()});
  if (wants("flume"))
    paper.push_back({"flume", quick ? "flume S-1 (20 mm)" : "flume 5 mm (paper)",
                     quick ? src / "cases/flume/variants/S-1" : src / "cases/flume", quick ? 20 : 2500,
                     quick ? 10 : vm["flume-steps"].as<long long>(), 405933,
                     quick ? 0 : vm["flume-late-at"].as<long long>()});
  for (const Paper& pc : paper) {
    if (!fs::exists(pc.dir)) continue;
    for (auto d : devices)
      for (const std::string& v : variants) {
        if (d == scree::Device::cpu && v != "fast") continue;
        const bool gpu = d == scree::Device::cuda;
        // CPU: a short look at the rest state only (the collapse takes minutes per 1000 steps).
        const long long pre = gpu ? pc.release : std::min(pc.release, cpu_steps), warm = std::min(pre / 5, 2000LL);
        std::vector<Window> w = {{"at rest", pre - warm}};
        if (gpu) {
          w.push_back({"-", 0, -1, release_time(pc.dir)});
          w.push_back({"flowing", pc.after});
        }
        const bool late = gpu && pc.late_at > pc.release + pc.after;
        if (late) {
          w.push_back({"-", 0, pc.late_at});
          w.push_back({"flowing from step " + std::to_string(pc.late_at), pc.after});
        }
        try {
          auto r = measure_windows(rt, pc.dir, pc.name, d, threads, v, warm, w, copy[d]);
          for (const Row& x : r) {
            report(x);
            rows.push_back(x);
          }
          if (r.size() >= 2) {
            // the whole run (the column: the paper's 100,000 steps; the flume: the 405,933 its
            // case took at 2e-5 s): its steps to the release at rest, the rest at the flowing rate
            // (the first flowing window's up to the late window, the late one's after it)
            const long long early = late ? std::min(pc.late_at, pc.total) - pc.release : pc.total - pc.release;
            const double est = (r[0].ms_per_step * pc.release + r[1].ms_per_step * early +
                                (late ? r[2].ms_per_step * (pc.total - pc.release - early) : 0.0)) /
                               1e3;
            std::printf("  %-44s %-4s %-9s estimated wall time of a whole run's %lld steps: %.1f s\n", pc.name.c_str(),
                        r[0].device.c_str(), v.c_str(), pc.total, est);
          }
        } catch (const std::exception& e) {
          std::printf("  %-44s %-4s %-9s failed: %s\n", pc.name.c_str(), scree::to_string(d), v.c_str(), e.what());
        }
      }
  }

  if (wants("scaling")) {
    for (const std::string& dim_text : split(vm["dimensions"].as<std::string>()))
    for (const std::string& mat : split(vm["materials"].as<std::string>()))
      for (const std::string& shape : split(vm["shapes"].as<std::string>()))
        for (const std::string& scheme : split(vm["schemes"].as<std::string>()))
          for (long long n = quick ? 1000 : 10000; n <= max_n; n = n * 10 > max_n && n < max_n ? max_n : n * 10) {
            const int dim = dim_text == "3" ? 3 : 2;
            const fs::path dir = write_block_case(tmp, n, mat, shape, scheme, src, dim);
            const std::string block = dim == 2 ? "block " : "block3d ";
            for (auto d : devices) {
              // The CPU gets the sizes up to 1e6 only (minutes otherwise).
              if (d == scree::Device::cpu && n > 1000000) continue;
              for (const std::string& v : variants) {
                if (d == scree::Device::cpu && v != "fast") continue;
                const long long steps = d == scree::Device::cuda ? std::max(20LL, gpu_steps / 4) : cpu_steps;
                try {
                  auto r = measure_windows(rt, dir, block + mat + " " + shape + " " + scheme + " " + std::to_string(n),
                                           d, threads, v, std::max(2LL, steps / 10), {{"", steps}}, copy[d]);
                  report(r[0]);
                  rows.push_back(r[0]);
                } catch (const std::exception& e) {
                  std::printf("  %s%s %s %lld %s %s failed: %s\n", block.c_str(), mat.c_str(), shape.c_str(), n,
                              scree::to_string(d), v.c_str(), e.what());
                }
              }
            }
          }
  }

  if (wants("cpu") && std::find(devices.begin(), devices.end(), scree::Device::cpu) != devices.end()) {
    const long long n = quick ? 2000 : vm["cpu-particles"].as<long long>();
    cpu_comparison<scree::materials::LinearElastic>(rt, tmp, src, "linearElastic", n, cpu_steps, threads, rows);
    cpu_comparison<scree::materials::PhaseTransition>(rt, tmp, src, "phaseTransition", n, cpu_steps, threads, rows);
  }

  if (wants("updates")) replay_updates(rt, src, rows);

  print(rows);
  // Memory: peak device bytes per particle of the largest block, and what fits in 80 GB.
  for (const Row& r : rows)
    if (r.device == "cuda" && r.name.rfind("block", 0) == 0 && r.particles >= 1000000) {
      const double per = r.peak_mb * (1 << 20) / r.particles;
      std::printf("memory: %-44s %-9s %.0f B of state per particle, peak %.0f B per particle (grid and sort buffers "
                  "included): about %.2g particles in 80 GB\n",
                  r.name.c_str(), r.variant.c_str(), r.bytes_per_particle, per, 80e9 / per);
    }
  // Two-phase against single-phase: the same block, the same device and kernels.
  for (const Row& t : rows) {
    if (t.name.rfind("block twoPhase ", 0) != 0) continue;
    const std::string single = "block linearElastic " + t.name.substr(std::string("block twoPhase ").size());
    for (const Row& r : rows)
      if (r.name == single && r.device == t.device && r.variant == t.variant)
        std::printf("two-phase / single-phase %-40s %-4s %.3f (particle-steps/s)\n", t.name.c_str(), t.device.c_str(),
                    t.particle_steps_per_s / r.particle_steps_per_s);
  }
  write_csv(rows, vm["csv"].as<std::string>());
  write_json(rows, vm["json"].as<std::string>());
  std::printf("\nwrote %s and %s\n", vm["csv"].as<std::string>().c_str(), vm["json"].as<std::string>().c_str());
  std::error_code ec;
  fs::remove_all(tmp, ec);
  return 0;
}

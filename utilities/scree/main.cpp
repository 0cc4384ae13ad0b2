// scree: the solver executable.
//
//   scree [--case DIR] [--device cpu|cuda] [--threads N]    run a case
//   scree --case DIR --overwrite                              run it again, replacing its results
//   scree --case DIR --restart[=TIME]                         continue it from its newest checkpoint (or TIME's)
//   scree --case DIR --restart --accept-changes               ... although the case's physics changed since
//   scree --case DIR --check                                  validate a case and exit
//   (a case with a system/ensembleDict is an ensemble: each command runs, continues or
//   checks its members, scree/ensemble/ensemble.hpp)
//   scree --list-plugins [material|boundaryCondition|writer|functionObject|case|fields]
//   scree --version | --help
//
// Before anything runs, the case is validated as a whole (every dictionary, then the
// setup: bodies against the grid, boundary conditions, output directories; --check stops
// there), and a case that already has results (the files of its writers, its
// postProcessing/, checkpoints/) is not run over unless --overwrite is given. A run writes
// checkpoints (case/checkpoint.hpp); --restart, or `startFrom latestTime;` in
// system/controlDict, continues from the newest, appending to the results.
//
// The memory the run needs is estimated in that check, before anything is allocated; a
// case that does not fit in the free host (or GPU) memory is an error at the entry that
// drives it (memory_estimate.hpp). SCREE_TEST_FREE_MEMORY=<bytes> in the environment sets
// the free memory that check assumes: for tests only.
//
// Exit status: 0 success, 1 errors in the case (each printed as file:line:col: message,
// among them a case too large for the memory, or an allocation of its setup that failed),
// 2 bad command line, 3 a failure while running, 4 the case has results of an earlier run
// that this run would replace (nothing was run: move them, or give --overwrite), 5 the run
// went wrong (a non-finite field, particles leaving the grid en masse, an unstable step) and
// was stopped with a diagnosis, its last state written; 128 + N stopped by signal N
// (SIGINT 130, SIGTERM 143) after writing the state it reached; 6 the case is in use by
// another run (its lock, case/run_lock.hpp, names it; nothing was run).
#include <omp.h>
#include <signal.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "scree/case/case.hpp"
#include "scree/case/checkpoint.hpp"
#include "scree/case/run_lock.hpp"
#include "scree/case/setup_check.hpp"
#include "scree/comm/comm.hpp"
#include "scree/ensemble/ensemble.hpp"
#include "scree/exec/memory.hpp"
#include "scree/output/field_info.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/solver/simulation.hpp"
#include "scree/time/time_control.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

/// Fields a line each: name, kind, unit, meaning.
void print_fields(const std::vector<scree::FieldInfo>& fields, int indent) {
  auto kind = [](const scree::FieldInfo& f) {
    return std::string(f.components == 1 ? "scalar" : f.components == 3 ? "vector" : "tensor") + " [" + f.unit + "]";
  };
  std::size_t w = 0, u = 0;
  for (const auto& f : fields) w = std::max(w, f.name.size()), u = std::max(u, kind(f).size());
  for (const auto& f : fields)
    std::cout << std::string(static_cast<std::size_t>(indent), ' ') << f.name
              << std::string(w + 2 - f.name.size(), ' ') << kind(f) << std::string(u + 2 - kind(f).size(), ' ')
              << f.doc << "\n";
}

void print_plugins(const scree::PluginRuntime& rt, const std::string& only) {
  using scree::PluginKind;
  bool any = false;
  if (only.empty() || only == "fields") {
    std::cout << "== particle fields ==\n\n"
                 "Every body writes (writers' and function objects' `fields`; vectors x y z, tensors xx yy zz xy yz "
                 "zx):\n";
    print_fields(scree::standard_particle_fields(), 4);
    std::cout << "A two-phase body (twoPhase { ... } in constant/bodies) also writes:\n";
    print_fields(scree::two_phase_fields(), 4);
    std::cout << "and each material its own (listed under it below).\n\n";
    any = true;
  }
  if (only.empty() || only == "case") {
    const auto& cs = scree::CoreSpecs::get();
    std::cout << "== case dictionaries ==\n\n";
    for (auto* s : {cs.control.get(), cs.schemes.get(), cs.grid.get(), cs.gravity.get(), cs.body.get()}) {
      std::cout << s->name() << ": " << s->doc() << "\n" << s->describe(4) << "\n";
    }
    any = true;
  }
  for (PluginKind k : scree::all_plugin_kinds()) {
    if (!only.empty() && only != scree::to_string(k)) continue;
    any = true;
    std::cout << "== " << scree::to_string(k) << " ==\n\n";
    for (const scree::PluginEntry* e : rt.registry().entries(k)) {
      std::cout << e->name << "  (" << fs::path(e->library).filename().string() << ")\n";
      std::cout << "    " << e->spec->doc() << "\n";
      if (e->spec->params().empty())
        std::cout << "    (no parameters)\n";
      else
        std::cout << e->spec->describe(4);
      if (!e->output_fields.empty()) {
        std::cout << "    writes, besides every body's fields:\n";
        print_fields(e->output_fields, 6);
      }
      std::cout << "\n";
    }
  }
  if (!any) {
    std::cerr << "scree: --list-plugins: unknown kind '" << only
              << "'; valid: material, boundaryCondition, writer, functionObject, case, fields\n";
    std::exit(2);
  }
}

}  // namespace

int main(int argc, char** argv) {
  // The log is written a line at a time also into a file or a pipe (where stdout is
  // otherwise fully buffered): a run killed early leaves its header and every warning.
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);

  // Under mpirun every rank runs this program on its part of the case (comm/comm.hpp);
  // the root rank (0) speaks for the run, the others print only errors of their own.
  scree::comm_init(&argc, &argv);
  struct Finalize {
    ~Finalize() { scree::comm_finalize(); }
  } finalize;
  const std::shared_ptr<scree::Comm> world = scree::world();
  const int rank = world->rank(), ranks = world->size();
  if (rank != 0) std::cout.rdbuf(nullptr);
  std::ostream& err = rank == 0 ? std::cerr : std::cout;  // errors every rank finds alike: the root's
  // One GPU per rank, bound before anything touches a device.
  const int local = scree::local_rank();
  if (ranks > 1 && local < scree::mem::cuda_device_count()) scree::mem::select_cuda_device(local);

  po::options_description opts("scree: GPU material point method for granular flows and soils\n\nOptions");
  opts.add_options()
      ("help,h", "print this help")
      ("version", "print the version")
      ("case,c", po::value<std::string>()->default_value("."), "case directory")
      ("device,d", po::value<std::string>(), "backend: cpu or cuda (default: cuda when a GPU is present)")
      ("threads,t", po::value<int>(), "CPU threads (default: all cores)")
      ("check", "validate the case (every dictionary and plugin, and the setup: bodies against the grid, boundary "
                "conditions, output directories) and exit")
      ("overwrite", "run even though the case has results of an earlier run (the writers' files, postProcessing/): "
                    "they are replaced. Without it scree refuses to start, so that finished results are not lost")
      ("restart", po::value<std::string>()->implicit_value(""),
       "continue the case from its newest checkpoint (checkpoints/<time>.ckpt), or with --restart=TIME from the one "
       "at that time (newer ones are then removed), appending to its results (the same as `startFrom latestTime;` in "
       "system/controlDict)")
      ("accept-changes",
       "with --restart: continue although the case's physics (gridDict, mpmSchemes, g, materials, bodies, boundary "
       "conditions) changed since the checkpoint was written; without it such a restart is refused, naming the "
       "entries")
      ("list-plugins", po::value<std::string>()->implicit_value(""),
       "list plugins, their parameters and the fields they write: [material|boundaryCondition|writer|functionObject|case|fields]")
      ("max-steps", po::value<long long>()->default_value(-1), "stop after this many steps (benchmarks)")
      ("no-output", "run without writers and function objects (benchmarks)")
      ("no-graphs", "CUDA: launch every kernel instead of replaying CUDA graphs")
      ("no-refill", "CUDA: the stress updates the elastic-first split defers run one point per lane for the whole "
                    "pass, instead of lanes taking new points as theirs finish (to time one against the other)")
      ("reference-kernels", "run the straightforward particle and grid kernels instead of the fast ones (no "
                            "warp-combined scatter, no particle sorting, dense grid updates): a cross-check")
      ("profile", "time every kernel phase (synchronising after each) and print a table at the end");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, opts), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    err << "scree: " << e.what() << "\n" << opts << "\n";
    return 2;
  }
  if (vm.count("help")) {
    std::cout << opts << "\n";
    return 0;
  }
  if (vm.count("version")) {
    std::cout << "scree " << SCREE_VERSION << " (plugin ABI " << scree::kPluginAbiVersion << ", CUDA backend "
              << (scree::mem::cuda_compiled() ? "compiled" : "not compiled") << ", MPI "
              << (scree::mpi_compiled() ? "compiled: mpirun -np N scree runs a case on N ranks" : "not compiled")
              << ")\n";
    return 0;
  }

  scree::PluginRuntime rt;
  try {
    rt.load_default_plugins();
  } catch (const scree::InputError& e) {
    err << "scree: " << e.what() << "\n";
    return 1;
  }
  if (vm.count("list-plugins")) {
    print_plugins(rt, vm["list-plugins"].as<std::string>());
    return 0;
  }

  // The backend asked for (the GPU itself is looked for once the case is valid).
  scree::RunOptions opt;
  const std::string device = vm.count("device") ? vm["device"].as<std::string>() : std::string();
  if (!device.empty() && device != "cpu" && device != "cuda") {
    err << "scree: --device: expected cpu or cuda, found '" << device << "'\n";
    return 2;
  }
  if (device == "cuda" && !scree::mem::cuda_compiled()) {
    err << "scree: --device cuda: this build has no CUDA backend (configure with -DSCREE_WITH_CUDA=ON)\n";
    return 2;
  }
  // Ranks on one node share its cores.
  const char* local_size = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const int per_node = ranks > 1 ? std::max(1, local_size ? std::atoi(local_size) : ranks) : 1;
  opt.threads = vm.count("threads") ? vm["threads"].as<int>() : std::max(1, omp_get_max_threads() / per_node);
  if (opt.threads < 1) {
    err << "scree: --threads: expected a positive number\n";
    return 2;
  }
  opt.max_steps = vm["max-steps"].as<long long>();
  opt.output = !vm.count("no-output");
  if (vm.count("reference-kernels")) opt.kernels = scree::KernelPolicy::reference_kernels();
  opt.kernels.graphs = !vm.count("no-graphs");
  opt.kernels.refill = !vm.count("no-refill");
  opt.profile = vm.count("profile") > 0;
  opt.accept_changes = vm.count("accept-changes") > 0;

  const fs::path dir = vm["case"].as<std::string>();
  if (scree::EnsembleSpec::present(dir)) {
    // An ensemble: its members are cases of their own, each run by scree as a process.
    if (ranks > 1) {
      err << "scree: case " << dir.string() << " is an ensemble (" << scree::EnsembleSpec::kFile
          << "): it runs its members as processes of their own; run it without mpirun\n";
      return 2;
    }
    if (vm.count("restart") && !vm["restart"].as<std::string>().empty()) {
      err << "scree: --restart=TIME: an ensemble continues each member from its newest checkpoint (--restart)\n";
      return 2;
    }
    for (const char* o : {"max-steps", "no-output", "no-graphs", "no-refill", "reference-kernels", "profile", "accept-changes"})
      if (vm.count(o) && !vm[o].defaulted()) {
        err << "scree: --" << o << ": not for an ensemble (run a member's case, ensemble/member_NNNN, with it)\n";
        return 2;
      }
    scree::EnsembleRunOptions eo;
    eo.scree = fs::read_symlink("/proc/self/exe");
    eo.device = device;
    eo.threads = opt.threads;
    eo.overwrite = vm.count("overwrite") > 0;
    eo.restart = vm.count("restart") > 0;
    eo.check = vm.count("check") > 0;
    try {
      return scree::run_ensemble(dir, eo, rt);
    } catch (const std::exception& e) {  // the file system (a full disk, a member's folder not writable), a spawn
      err << "scree: ensemble of " << dir.string() << ": " << e.what() << "\n";
      return 3;
    }
  }
  try {
    scree::Case c = scree::Case::read(dir, rt);
    // The setup's checks (the run would reject what they find), reported together. The
    // memory's is against the backend the run would take (without a word of it here).
    const scree::Device memory_backend =
        device == "cuda" || (device.empty() && scree::mem::cuda_compiled() && scree::mem::cuda_available())
            ? scree::Device::cuda
            : scree::Device::cpu;
    scree::SetupReport setup = scree::check_setup(c, rt, opt.output, memory_backend, {ranks, per_node});
    for (const auto& w : setup.warnings) std::cout << "warning: " << w.what() << "\n";
    if (!setup.errors.empty()) throw scree::InputErrors(std::move(setup.errors));
    // Restart: from the newest checkpoint (--restart, or startFrom latestTime), or the one at TIME.
    std::vector<fs::path> newer;  // checkpoints after the one a --restart=TIME picked
    if (vm.count("restart") || c.settings().control.start_from_latest) {
      const auto checkpoints = scree::list_checkpoints(dir);
      const std::string at = vm.count("restart") ? vm["restart"].as<std::string>() : std::string();
      auto times = [&] {
        std::string list;
        for (const auto& f : checkpoints) list += (list.empty() ? "" : ", ") + f.stem().string();
        return list;
      };
      if (!at.empty()) {
        char* end = nullptr;
        const double want = std::strtod(at.c_str(), &end);
        if (end == at.c_str() || *end != '\0') {
          err << "scree: --restart=" << at << ": expected a time in seconds (a checkpoint's, as in checkpoints/<time>.ckpt)\n";
          return 2;
        }
        for (std::size_t i = 0; i < checkpoints.size(); ++i) {
          double t = 0;
          if (scree::checkpoint_time(checkpoints[i], t) && std::fabs(t - want) <= 1e-9 * std::max(1.0, std::fabs(want))) {
            opt.restart = checkpoints[i];
            newer.assign(checkpoints.begin() + static_cast<std::ptrdiff_t>(i) + 1, checkpoints.end());
          }
        }
        if (opt.restart.empty()) {
          err << "scree: --restart=" << at << ": case " << dir.string() << " has no checkpoint at t = " << at << " s; "
              << (checkpoints.empty() ? std::string("it has none") : "it has checkpoints at t = " + times() + " s") << "\n";
          return 2;
        }
      } else if (!checkpoints.empty()) {
        opt.restart = checkpoints.back();
      } else if (vm.count("restart")) {
        err << "scree: --restart: case " << dir.string() << " has no checkpoint (" <<
            scree::checkpoint_dir(dir).string() << "/<time>.ckpt) to continue from; run it from its start "
            "without --restart\n";
        return 2;
      } else {
        std::cout << "scree: startFrom latestTime: no checkpoint yet; the run starts from startTime" << std::endl;
      }
      double t_ck = 0;
      const double t_end = c.settings().control.time.end_time;
      if (!opt.restart.empty() && scree::checkpoint_time(opt.restart, t_ck) && scree::TimeControl::reached(t_ck, t_end) &&
          scree::TimeControl::reached(t_end, t_ck) && !vm.count("check")) {
        // The run it continues reached endTime already: nothing to run, nothing to write.
        std::cout << "scree: the run already reached endTime " << t_end << " s (checkpoint " << opt.restart.string()
                  << "); nothing to run. Raise endTime in system/controlDict to run on from it" << std::endl;
        return 0;
      }
      if (!opt.restart.empty() && scree::checkpoint_time(opt.restart, t_ck) && scree::TimeControl::reached(t_ck, t_end)) {
        const scree::Entry* e = c.control().find("endTime");
        err << (e ? e->where().str() + ": " : std::string()) << "endTime " << t_end
            << " s is not after the time of the checkpoint to continue from, " << opt.restart.string()
            << ": the run would do nothing. Raise endTime to run on from it"
            << (checkpoints.size() > 1 ? ", or continue from an older one with --restart=TIME (checkpoints at t = " +
                                             times() + " s)"
                                       : std::string())
            << "; nothing was run\n";
        return 1;
      }
    }
    if (vm.count("check") && !opt.restart.empty()) {
      // What the run would refuse of its checkpoint, said now: unreadable, another case's,
      // other physics (the solver checks the rest against the bodies it builds).
      scree::Checkpoint ck;
      try {
        ck = scree::Checkpoint::read(opt.restart);
      } catch (const std::exception& e) {
        err << "scree: --restart: " << e.what() << "; continue from another checkpoint (--restart=TIME) or run "
                                                   "the case from startTime (--overwrite)\n";
        return 1;
      }
      std::vector<scree::InputError> bad;
      if (!opt.accept_changes) bad = scree::physics_changes(ck.physics, c);
      std::size_t bodies = 0;
      for (const auto* e : scree::plugin_entries(c.bodies())) bodies += e != nullptr;
      if (ck.bodies.size() != bodies)
        bad.emplace_back(c.bodies().where(), "the checkpoint " + opt.restart.string() + " has " +
                                                 std::to_string(ck.bodies.size()) + " bodies, the case " +
                                                 std::to_string(bodies));
      if (!bad.empty()) {
        bad.emplace_back(bad.front().where(), "the checkpoint " + opt.restart.string() +
                                                  " does not fit the case as it is now (the entries above): run it "
                                                  "from startTime (--overwrite), restore them, or continue anyway with "
                                                  "--restart --accept-changes");
        throw scree::InputErrors(std::move(bad));
      }
    }
    const auto results = opt.output && opt.restart.empty() ? scree::existing_results(c, rt.registry())
                                                           : std::vector<fs::path>{};
    if (vm.count("check")) {
      std::cout << "scree: case " << dir.string() << " is valid\n";
      for (const std::string& line : setup.summary) std::cout << "scree: the run: " << line << "\n";
      std::cout << "scree: a run needs " << setup.memory << "\n";
      if (!opt.restart.empty()) std::cout << "scree: a run continues from " << opt.restart.string() << "\n";
      if (!results.empty())
        std::cout << "scree: note: it has results of an earlier run (" << results.front().string()
                  << (results.size() > 1 ? ", ..." : "") << "): a run replaces them only with --overwrite\n";
      return 0;
    }
    // One run at a time on a case (case/run_lock.hpp): taken before the results are looked
    // at, held to the end of main. A decomposed run's root takes it for all its ranks.
    std::optional<scree::RunLock> lock;
    std::string holder;
    if (rank == 0) lock = scree::RunLock::acquire(dir, holder);
    if (world->sum(std::uint64_t(rank == 0 && !lock ? 1 : 0)) > 0) {
      if (rank == 0)
        err << "scree: case " << dir.string() << " is in use by another run (" << holder
            << "; its lock: " << (dir / scree::RunLock::kFileName).string()
            << "); nothing was run. Wait for that run to end or stop it (kill -TERM <PID>: it writes the state it "
               "reached), or copy the case to run it beside it\n";
      return 6;
    }
    if (!results.empty() && !vm.count("overwrite")) {
      err << "scree: case " << dir.string() << " has results of an earlier run, which this run would replace:\n";
      const std::size_t shown = std::min<std::size_t>(results.size(), 5);
      for (std::size_t i = 0; i < shown; ++i) err << "    " << results[i].string() << "\n";
      if (results.size() > shown) err << "    ... and " << results.size() - shown << " more\n";
      err << "scree: nothing was run. To keep them, move them away (or copy the case); to replace them, run "
                   "again with --overwrite";
      if (!scree::list_checkpoints(dir).empty())
        err << "; to continue the earlier run from its newest checkpoint, run with --restart (--restart=TIME: "
               "from an older one)";
      err << "\n";
      return 4;
    }

    // Backend.
    const bool gpu = scree::mem::cuda_available();
    if (device == "cuda" && !gpu) {
      err << "scree: --device cuda: no usable CUDA GPU found\n";
      return 2;
    }
    if (device.empty()) {
      opt.device = gpu ? scree::Device::cuda : scree::Device::cpu;
      std::cout << "scree: backend " << scree::to_string(opt.device)
                << (gpu ? " (a CUDA GPU is present)"
                        : (scree::mem::cuda_compiled() ? " (no CUDA GPU found)" : " (built without CUDA)"))
                << std::endl;
    } else {
      opt.device = device == "cuda" ? scree::Device::cuda : scree::Device::cpu;
    }
    if (ranks > 1 && opt.device == scree::Device::cuda) {
      const int gpus = scree::mem::cuda_device_count();
      // Every rank finds this alike when the nodes are alike; the first one to say it ends the run.
      std::uint64_t over = local >= gpus ? 1 : 0;
      if (world->sum(over) > 0) {
        err << "scree: " << ranks << " ranks, and a node has " << gpus
            << " GPU(s) for its ranks: one rank per GPU (mpirun -np <GPUs per node x nodes>), or --device cpu\n";
        return 2;
      }
      std::cout << "scree: rank 0 on GPU " << local << " of its node" << std::endl;
    }
    world->barrier();  // every rank has read the case before the root writes anything
    if (rank == 0) scree::remove_temporaries(c, rt.registry());  // a killed run's, in every output place
    if (!newer.empty() && rank == 0) {
      // Going back to an older checkpoint: the newer ones belong to the run being replaced.
      std::cout << "scree: continuing from " << opt.restart.string() << "; removing the " << newer.size()
                << " newer checkpoint(s) of the run it replaces" << std::endl;
      for (const auto& f : newer) fs::remove(f);
    }

    opt.check_setup = false;  // done above
    // SIGINT (Ctrl-C) and SIGTERM (a batch system's stop): the run finishes its chunk of
    // steps (about 0.5 s at most), writes the state it reached and exits 128 + signal.
    // A second signal ends it at once (the default action, restored by SA_RESETHAND).
    struct sigaction sa {};
    sa.sa_handler = [](int sig) { scree::request_stop(sig); };
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    scree::Simulation sim(c, rt, opt);
    const auto t0 = std::chrono::steady_clock::now();
    const scree::RunStats st = sim.run();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // The whole run's wall time, and what it went to: the steps (their rate), and the
    // output the loop waited for (snapshots taken and handed to the output thread).
    std::cout << "scree: done: " << st.steps << " steps";
    if (st.last_step != st.steps)  // a restart: which steps of the whole run this process took
      std::cout << " (step " << st.last_step - st.steps << " to " << st.last_step << ")";
    std::cout << ", " << st.simulated_time << " s simulated in " << wall
              << " s wall (steps " << st.wall_seconds << " s at "
              << (st.wall_seconds > 0 ? st.steps / st.wall_seconds : 0) << " steps/s, output "
              << st.output_seconds << " s; " << st.particles << " particles)\n";
    if (st.split_steps > 0)  // KernelPolicy::split: what the tuner chose, for the record
      std::cout << "scree: stress pass split (elastic points first) in " << st.split_steps << " of " << st.steps
                << " steps, with the deferred updates in turns in " << st.refill_steps << "\n";
    if (st.lost_particles)
      std::cout << "scree: warning: " << st.lost_particles << " particle(s) left the grid during the run\n";
  } catch (const scree::RunInterrupted& e) {
    std::cout << std::flush;
    err << "scree: " << e.what() << "; the state at that time was written; the run did not reach endTime "
                 "(scree --restart continues it from its newest checkpoint)\n";
    return 128 + e.signal();
  } catch (const scree::RunFailure& e) {
    // The health checks stopped a run gone wrong (non-finite fields, points leaving the
    // grid, an unstable step); its last state was written for a look.
    std::cout << std::flush;
    err << "scree: error: " << e.what() << "\nscree: the state it stopped in was written; the run failed\n";
    return 5;
  } catch (const scree::InputErrors& e) {
    for (const auto& x : e.errors()) err << x.what() << "\n";
    err << "scree: " << e.errors().size() << " error(s) in case " << dir.string() << "; nothing was run\n";
    return 1;
  } catch (const scree::InputError& e) {
    err << e.what() << "\nscree: error in case " << dir.string() << "\n";
    return 1;
  } catch (const std::bad_alloc& e) {
    // An allocation after the setup (the setup's own name their entry: InputError above).
    std::cout << std::flush;
    std::cerr << "scree: " << (ranks > 1 ? "rank " + std::to_string(rank) + ": " : std::string()) << e.what()
              << "; the run failed (the case's memory estimate is checked before the run: scree --check)\n";
    if (ranks > 1) world->abort(3);  // the other ranks would wait for this one
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "scree: " << (ranks > 1 ? "rank " + std::to_string(rank) + ": " : std::string()) << e.what() << "\n";
    if (ranks > 1) world->abort(3);
    return 3;
  }
  return 0;
}

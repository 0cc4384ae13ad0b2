// Running a case: the time loop, output scheduling and progress.
//
//   PluginRuntime rt;  rt.load_default_plugins();
//   Case c = Case::read("cases/columnCollapse", rt);
//   Simulation sim(c, rt, RunOptions{});
//   sim.run();                 // to endTime, writing output and running function objects
//
// Tests and tools can also step a case themselves (advance_to, snapshot).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "scree/exec/memory.hpp"
#include "scree/output/snapshot.hpp"
#include "scree/plugin/loader.hpp"
#include "scree/solver/case.hpp"

namespace scree {

/// RunOptions::split_elastic. alternate: on and off by turns, a chunk of steps each (for
/// tests of the switch).
enum class StressSplit { automatic, on, off, alternate };

struct RunOptions {
  Device device = Device::cpu;
  int threads = 1;             ///< CPU threads (OpenMP)
  bool output = true;          ///< writers and function objects (off for benchmarks)
  bool use_graphs = true;      ///< CUDA: replay steps as CUDA graphs
  std::int64_t max_steps = -1; ///< stop after this many steps (benchmarks); -1: no limit
  bool progress = true;        ///< progress line on stdout
  bool profile = false;        ///< time every kernel phase (synchronising; no graphs) and report
  /// The straightforward kernels (verification and timing, docs/performance.md): one
  /// generic particle kernel with an atomic per particle and node, every grid node in the
  /// grid updates, the signal speed every step, and no re-sorting unless the case asks.
  /// The fast kernels' results equal these within round-off (the order of additions).
  bool reference_kernels = false;
  bool sparse_grid = true;     ///< fast kernels: grid updates on the tiles particles touched only
  /// CUDA, 2D: the stress kernel's register cap as blocks of 64 threads per SM
  /// (PassParams::stress_blocks_per_sm; 6: 170 registers, 12 warps per SM, measured 14-27%
  /// faster at rest on an H200 than the compiler's 254 registers; 0: no cap)
  int stress_blocks_per_sm = 6;
  /// Fast kernels: the elastic-first split of the stress pass (PassParams::split_elastic)
  /// for materials that provide update_elastic. automatic: on CUDA the solver times the
  /// run both ways now and then (every ~10 s of run time) and keeps the faster: the split
  /// gains for problems of many waves of threads (more warps per SM) and loses for those
  /// under a wave or two, where its two kernels run one after the other
  /// (docs/performance.md, entry 13); off on the CPU. on/off: always/never.
  StressSplit split_elastic = StressSplit::automatic;
  /// CUDA, 2D: the register cap of the split's elastic-only kernel as blocks of 64 threads
  /// per SM (10: 96 registers, 20 warps per SM; 0: the compiler's choice, 146 registers
  /// for phaseTransition)
  int elastic_blocks_per_sm = 10;
  std::ostream* log = nullptr; ///< messages (default std::cout)
};

struct RunStats {
  std::int64_t split_steps = 0;  ///< steps whose stress pass ran split (RunOptions::split_elastic)
  std::int64_t steps = 0;
  double simulated_time = 0;   ///< [s]
  double wall_seconds = 0;     ///< time-loop wall time, setup excluded [s]
  double output_seconds = 0;   ///< of which spent waiting for snapshots/output [s]
  std::int64_t particles = 0;
  std::int64_t nodes = 0;
  std::size_t bytes_per_particle = 0;
  std::size_t peak_device_bytes = 0;
  std::uint64_t lost_particles = 0;
};

class SCREE_API Simulation {
 public:
  Simulation(const Case& c, PluginRuntime& rt, const RunOptions& options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  int dimension() const;
  /// Run to endTime with output; returns the statistics.
  RunStats run();
  /// Advance to time t (no output unless `with_output`).
  void advance_to(double t, bool with_output = false);
  /// Run exactly n steps (no output).
  void run_steps(std::int64_t n);
  /// A host copy of every body (pending particle updates are applied first).
  Snapshot snapshot(bool with_grid = false);
  /// Set the velocities of body `body` (index in constant/bodies) before the first step:
  /// dimension() values per particle, in the order of snapshot().bodies[body].
  void set_velocities(std::size_t body, const std::vector<double>& v);
  double time() const;
  std::int64_t steps() const;
  RunStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scree

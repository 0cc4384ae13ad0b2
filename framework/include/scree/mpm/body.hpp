// A body: one set of particles with one material. The solver sees bodies only through
// this interface (one virtual call per pass per body); the kernels behind it are
// instantiated for the body's material inside the material's plugin (mpm/material_body.hpp).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scree/core/tensor.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/particle_pass.hpp"
#include "scree/mpm/shape_functions.hpp"
#include "scree/output/snapshot.hpp"

namespace scree {

/// Everything a material plugin needs to create a body.
template <int D>
struct BodySetup {
  std::string name;            ///< body name (constant/bodies)
  int body_id = 0;
  std::string material_name;   ///< entry name in constant/materials
  Exec exec;                   ///< backend and threads
  ShapeKind shape = ShapeKind::linear;
  Real gimp_half_length = 0.25;  ///< uGIMP particle half-length in cells (1/(2 n) for n per cell per axis)
  Transfer transfer = Transfer::flip;
  Real cell_size = 0;
  // Initial particles (host):
  std::vector<Vec<D>> x;       ///< positions [m]
  std::vector<Vec<D>> v;       ///< velocities [m/s]
  std::vector<Real> volume;    ///< volumes [m^3] (areas in 2D: per unit thickness)
  std::vector<Sym3> sigma;     ///< initial stress (tension positive) [Pa]
  Mat<D> velocity_gradient = Mat<D>::zero();  ///< of the initial velocity field (APIC's C_p) [1/s]
  std::int64_t first_id = 0;   ///< particle ids are first_id, first_id + 1, ... unless `ids` is given
  /// The points' ids when they are not consecutive: a rank of a decomposed run generates
  /// only the points of its box, each with the id it has in the whole body (first_id plus
  /// its place in the body's generation order).
  std::vector<std::int64_t> ids;
  /// Particle mass = mass_factor x the material's density x volume. A two-phase body's
  /// material is its skeleton, whose density is the grains' rho_s: its points carry the
  /// solid mass (1 - n0) rho_s V0 (porous/two_phase.hpp).
  Real mass_factor = 1;
  /// Columns every point carries beside the material's (a formulation's own per-point
  /// fields): sorted with the particles and written as output fields.
  struct ExtraColumn {
    std::string name, unit, doc;
    int components = 1;  ///< 1: a scalar; D: a vector (output with 3 components)
    Real initial = 0;    ///< the value every point starts with, unless `values` is given
    std::vector<Real> values;  ///< per point and component (point-major: p * components + k)
    bool output = true;  ///< written by the writers (false: internal state)
  };
  std::vector<ExtraColumn> extra;
};

template <int D>
class Body {
 public:
  virtual ~Body() = default;
  virtual const std::string& name() const = 0;
  virtual const std::string& material_type() const = 0;
  virtual Index size() const = 0;
  /// Run one particle pass (see particle_pass.hpp) on the body's backend.
  virtual void pass(const PassParams<D>& pp) = 0;
  /// Copy to the host and evaluate every output field.
  virtual void snapshot(BodySnapshot& out) const = 0;
  /// A snapshot taken without stopping the run: queues the copy of the particle data now
  /// (after the work already queued on the body's stream; the following steps may start
  /// at once) and returns a function that, called later on any thread, waits for the copy
  /// and builds the snapshot there. `copy_stream` (a cudaStream_t) carries the transfer to
  /// the host. This default copies and builds at once.
  virtual std::function<void(BodySnapshot&)> snapshot_async(void* copy_stream) {
    (void)copy_stream;
    auto s = std::make_shared<BodySnapshot>();
    snapshot(*s);
    return [s](BodySnapshot& out) { out = std::move(*s); };
  }
  /// Largest signal speed c + |v| over the particles (host evaluation, for the time
  /// step check before the run).
  virtual Real max_signal_speed(Real cell_size) const = 0;
  /// Device pointers (for tests and function objects that work on the device).
  virtual const ParticleArrays<D>& arrays() const = 0;
  /// The first of the extra columns of BodySetup::extra (column j at extra_columns() + j
  /// size(), on the backend), or null. Permuted with the particles by sort_by_cell.
  virtual Real* extra_columns() const { return nullptr; }
  /// Bytes of particle data per particle (benchmarks).
  virtual std::size_t bytes_per_particle() const = 0;
  /// Overwrite particle velocities (D values per particle, interleaved), e.g. to start
  /// from a mode shape (tests, scripted initial conditions). Only before the first step.
  virtual void set_velocities(const std::vector<Real>& v) = 0;
  /// Checkpoints (case/checkpoint.hpp): a host copy of every Real the body holds per
  /// particle (its storage block: particle_storage.hpp), and the state restored from such
  /// a copy; restore_state throws std::invalid_argument when `block` has another size.
  virtual std::vector<Real> save_state() const = 0;
  virtual void restore_state(const std::vector<Real>& block) = 0;
  /// The body's points replaced by the n points of `block` (a block as save_state gives,
  /// of n points: column c at c n), another count allowed: the points a rank holds after
  /// a migration between the boxes of a domain decomposition (case/decomposition.hpp).
  /// Every value is kept as it is.
  virtual void replace_state(const std::vector<Real>& block, Index n) = 0;
  /// Reorder particles by grid cell (locality for P2G atomics); ids move with them.
  virtual void sort_by_cell(const GridGeometry<D>& g) = 0;
  /// Whether the body's stress pass can run split (its material has update_elastic).
  virtual bool can_split_stress() const { return false; }
  /// Whether the split's deferred points can run their updates in turns (the material's
  /// update runs in turns: material_has_turns).
  virtual bool updates_in_turns() const { return false; }
  /// Empty the split's list counters (before the stress pass starts or stops splitting:
  /// while it does not split, no kernel clears them). Queued on the body's stream.
  virtual void reset_split() {}
  /// The bound on its material's stress update, e.g. "maxSubsteps 8" (material.hpp,
  /// work_bound), or "" when the material has none.
  virtual std::string work_bound() const { return {}; }
  /// The stress updates of this body that reached that bound since the body was made (on
  /// this rank). Waits for the body's queued work.
  virtual std::uint64_t bounded_updates() const { return 0; }
};

}  // namespace scree

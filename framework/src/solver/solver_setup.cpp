// Solver<D>: construction. The grid from system/gridDict, the bodies from constant/bodies
// (particles generated, each body's kernels made by its material's plugin), the boundary
// conditions' node constraints, the writers and function objects, and the first time step.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <new>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "scree/case/case_model.hpp"
#include "scree/plugin/hydraulic_models.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/case/overburden.hpp"
#include "scree/case/particle_generation.hpp"
#include "scree/case/setup_check.hpp"
#include "../case/hydraulic_nodes.hpp"
#include "solver.hpp"

#if defined(SCREE_HAVE_CUDA)
#include <cuda_runtime_api.h>
#endif

namespace scree {

template <int D>
Solver<D>::Solver(const Case& c, PluginRuntime& rt, const RunOptions& o)
    : case_(c),
      settings_(c.settings()),
      rt_(rt),
      opt_(o),
      log_(o.log ? *o.log : std::cout),
      comm_(o.comm ? o.comm : world()),
      time_(c.settings().control.time, c.settings().grid.cell_size),
      progress_(log_, isatty(STDOUT_FILENO) && (!o.log || o.log == &std::cout), c.settings().control.time.start_time,
                c.settings().control.time.end_time) {
  if (const std::string e = policy_.check(); !e.empty()) throw std::invalid_argument("kernel policy: " + e);
  exec_.device = o.device;
  exec_.threads = std::max(1, o.threads);
  setup_streams();
  for (int d = 0; d < D; ++d) gravity_[d] = settings_.gravity[d];
  sort_interval_ = policy_.sort_interval(settings_.schemes.sort_interval);

  setup_grid();
  run_start_ = settings_.control.time.start_time;
  std::optional<Checkpoint> restart;
  if (!opt_.restart.empty()) {  // read first: the writers continue their series from its time
    restart = Checkpoint::read(opt_.restart, comm_->rank(), comm_->size());
    run_start_ = ctx_.start_time = restart->time;
  }
  host_ctl_ = time_.initial();
  ctl_.resize(1, exec_.device);
  sync_control_to_device();
  setup_bodies();
  if (decomposed()) report_decomposition();
  ctx_.start_time = run_start_;
  {  // health: the run stops once more than maxLostFraction of the points left the grid
    const double f = settings_.control.max_lost_fraction;
    const double n = static_cast<double>(std::accumulate(body_totals_.begin(), body_totals_.end(), std::uint64_t(0)));
    host_ctl_.lost_stop = f < 1 ? static_cast<unsigned long long>(std::floor(f * n)) + 1 : 0;
    if (decomposed()) {  // the ranks' lost points are summed at every step (reduce_clock)
      lost_stop_global_ = host_ctl_.lost_stop;
      host_ctl_.lost_stop = 0;
    }
    sync_control_to_device();
  }
  setup_split();
  // A decomposed run keeps the split the policy sets: every rank runs the same kernels, and
  // the root's tuner choosing for all cost the scaling runs its trials (docs/multi-gpu.md).
  if (decomposed()) tuner_.reset();
  setup_boundaries();
  energy_ledger_ = opt_.energy_ledger;
  if (opt_.output) setup_output();  // a decomposed run: the root's, and every rank's writers of pieces
  if (decomposed()) energy_ledger_ = comm_->max(static_cast<std::uint64_t>(energy_ledger_)) != 0;
  if (energy_ledger_ && split_ && !policy_.ledger_split) {  // the ledger's whole-pass kernel: no split to tune
    split_ = refill_ = false;
    tuner_.reset();
  }
  setup_passes();
  if (restart) {
    restore(*restart);
    return;
  }
  // A run from startTime: the checkpoints of an earlier run are not its own.
  if (opt_.output && root()) purge_checkpoints(case_.dir(), 0);
  if (time_.start(host_ctl_, comm_->max(static_cast<double>(max_signal_speed())), log_)) sync_control_to_device();
  if (decomposed()) migrate();  // the points are in their boxes: this measures the fastest, which sets the next
}

template <int D>
void Solver<D>::restore(const Checkpoint& ck) {
  const std::string file = opt_.restart.string();
  auto mismatch = [&](const std::string& what) {
    return InputError(case_.bodies().where(),
                      "the checkpoint " + file + " does not fit this case: " + what +
                          ". The case changed since it was written: run it from startTime (without --restart "
                          "or startFrom latestTime; --overwrite replaces the old results), or restore the case");
  };
  if (std::vector<InputError> changed = physics_changes(ck.physics, case_); !changed.empty()) {
    if (!opt_.accept_changes) {
      const SourceLocation at = changed.front().where();
      changed.emplace_back(at, "the checkpoint " + file +
                                   " was written with other physics (the entries above): a restart would continue its "
                                   "state under them and rewrite its results with a mix of both. Run the case from "
                                   "startTime (--overwrite), restore those entries, or continue anyway with --restart "
                                   "--accept-changes");
      throw InputErrors(std::move(changed));
    }
    if (root())
      for (const InputError& e : changed)
        log_ << "warning: --accept-changes: " << e.what() << std::endl;
  }
  if (ck.dimension != D)
    throw mismatch("it is " + std::to_string(ck.dimension) + "D, the case " + std::to_string(D) + "D");
  if (ck.bodies.size() != bodies_.size())
    throw mismatch("it has " + std::to_string(ck.bodies.size()) + " bodies, the case " +
                   std::to_string(bodies_.size()));
  if (decomposed() && !ck.decomposition.empty()) {
    // The boxes the run had (it may have rebalanced): on as many ranks, the points return to
    // the ranks that held them, in their order.
    try {
      int a = 0, b = 0;
      stencil_reach(settings_.schemes.shape, a, b);
      adopt(from_tree_code<D>(global_, ck.decomposition, comm_->size(), comm_->rank(), a, b, decomp_.slack));
    } catch (const std::invalid_argument&) {  // another rank count, or the grid changed: the case's own boxes stay
    }
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Checkpoint::Body& b = ck.bodies[i];
    const std::string name = ctx_.body_names[i];
    if (b.name != name) throw mismatch("its body " + std::to_string(i + 1) + " is '" + b.name + "', not '" + name + "'");
    if (b.material_type != bodies_[i]->material_type())
      throw mismatch("body '" + name + "' is of material type " + b.material_type + ", not " +
                     bodies_[i]->material_type());
    const std::uint64_t n = body_totals_[i];
    const std::uint64_t columns = bodies_[i]->bytes_per_particle() / sizeof(Real);
    if (b.particles != n || b.columns != columns)
      throw mismatch("body '" + name + "' has " + std::to_string(b.particles) + " particles of " +
                     std::to_string(b.columns) + " values, the case's " + std::to_string(n) + " of " +
                     std::to_string(columns));
    if (decomposed()) {  // this rank's points of the whole body
      Index kept = 0;
      std::vector<Real> mine = keep_own(b.data, static_cast<Index>(b.data.size() / b.columns), kept);
      bodies_[i]->replace_state(mine, kept);
    } else {
      bodies_[i]->restore_state(b.data);
    }
  }
  if (static_cast<bool>(porous_) != !ck.liquid.empty())
    throw mismatch(porous_ ? "it has no pore liquid, the case has two-phase bodies"
                           : "it has a pore liquid, the case no two-phase body");
  if (porous_) {
    std::vector<Real> liquid = ck.liquid;  // the checkpoint's sums over the ranks stay with the root's share
    if (decomposed() && !root()) std::fill(liquid.begin(), liquid.end(), Real(0));
    porous_->restore_state(liquid);
  }

  // The clock as it was, with the case's settings of now: a restart may change deltaT,
  // maxCo, maxDeltaT and the health limits (and endTime, which the loop aims at).
  StepControl c{};
  std::memcpy(&c, ck.clock.data(), sizeof c);
  c.dt_max = host_ctl_.dt_max;
  c.cfl = host_ctl_.cfl;
  c.h = host_ctl_.h;
  c.lost_stop = host_ctl_.lost_stop;
  c.stop_co = host_ctl_.stop_co;
  if (decomposed() && !root()) {  // the checkpoint's sums over the ranks stay with the root's clock
    c.lost = 0;
    c.energy.clear();
  }
  host_ctl_ = c;
  sync_control_to_device();
  step_ = ck.step;
  sorted_at_ = ck.sorted_at;
  writes_ = ck.writes;
  if (output_ && !output_->restore(ck.schedule))
    log_ << "note: the function objects differ from those of the checkpoint; they start on their schedules at t = "
         << ck.time << " s\n";
  log_ << "Restarting from " << file << ": t = " << ck.time << " s, step " << ck.step << std::endl;
  if (decomposed()) migrate(false);  // what the run did at this write time: the next migration's step, a rebalance due
}

template <int D>
Solver<D>::~Solver() {
  output_.reset();  // joins the output thread: writers finish before they are destroyed
  own_piece_writers_.clear();
  rank_functions_.clear();
  own_functions_.clear();
  graphs_.reset();
#if defined(SCREE_HAVE_CUDA)
  if (stream_) cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
  if (copy_stream_) cudaStreamDestroy(static_cast<cudaStream_t>(copy_stream_));
#endif
}

template <int D>
void Solver<D>::setup_streams() {
#if defined(SCREE_HAVE_CUDA)
  if (exec_.device != Device::cuda) return;
  auto make = [] {
    cudaStream_t s;
    const cudaError_t e = cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking);
    if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error in cudaStreamCreate: ") + cudaGetErrorString(e));
    return s;
  };
  stream_ = make();
  exec_.stream = stream_;
  copy_stream_ = make();
  // A decomposed step waits on the host for its exchanges: no graph can hold it.
  if (policy_.graphs && !opt_.profile && comm_->size() == 1) graphs_ = std::make_unique<StepGraphs>(stream_);
#endif
}

template <int D>
void Solver<D>::setup_grid() {
  const GridSettings& gs = settings_.grid;
  global_ = grid_ = grid_geometry<D>(gs);
  for (int d = 0; d < D; ++d)
    if (!whole_cells(gs.lower[d], gs.upper[d], gs.cell_size))
      log_ << "warning: system/gridDict: the domain's extent along axis " << d
           << " is not a whole number of cells; it is extended to " << grid_.cells[d] << " cells\n";
  // A decomposed run allocates its part once the points are cut into boxes (decompose_bodies).
  if (comm_->size() == 1) allocate_grid();
  else ctx_ = plugin_context<D>(case_, grid_, exec_.device);
}

template <int D>
void Solver<D>::allocate_grid() {
  // Two sets of nodal fields (grid.hpp), one allocation each.
  static_assert(sizeof(GridFields<D>) == kGridFieldCount<D> * sizeof(Real*), "GridFields<D> has kGridFieldCount<D> fields");
  const Index nn = grid_.num_nodes();
  for (int s = 0; s < 2; ++s) {
    try {
      grid_data_[s].resize(static_cast<std::size_t>(nn) * kGridFieldCount<D>, exec_.device);
      tile_stamps_[s].resize(static_cast<std::size_t>(Tiles<D>::total(grid_)), exec_.device);
    } catch (const std::bad_alloc& e) {
      throw out_of_memory(0, e);
    }
    Real* b = grid_data_[s].data();
    int k = 0;
    auto next = [&] { return b + static_cast<std::size_t>(k++) * nn; };
    sets_[s].mass = next();
    for (int d = 0; d < D; ++d) sets_[s].momentum[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].force[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].velocity[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].velocity_new[d] = next();
  }
  ctx_ = plugin_context<D>(case_, grid_, exec_.device);
}

template <int D>
void Solver<D>::setup_bodies() {
  const Registry& reg = rt_.registry();
  const SchemeSettings& sch = settings_.schemes;
  std::int64_t next_id = 0;
  int id = 0;
  Real min_mass = 1e300;
  body_totals_.clear();
  if (decomposed()) decompose_case();  // this rank's box first: each rank makes only its points
  for (const Entry* e : case_.body_entries()) {
    if (!e->dict().has("twoPhase")) continue;
    // A two-phase body (porous/two_phase.hpp): the case runs the two-phase step, USL only.
    if (sch.update_scheme != UpdateScheme::USL) {
      const Entry* u = case_.schemes().find("updateScheme");
      throw InputError(u ? u->where() : case_.schemes().where(),
                       "updateScheme: a case with a two-phase body (" + e->key() +
                           ", twoPhase) runs the USL scheme; set `updateScheme USL;`");
    }
    // Quadratic B-splines with more than one point per cell make liquid at a closed surface
    // (a closed column gains water that no boundary let in; GIMP and linear shapes keep it to
    // round-off). Until the surface's nodes are right for their wider kernel, such a case is
    // refused rather than run wrong.
    if (sch.shape == ShapeKind::bspline2) {
      const Entry* sf = case_.schemes().find("shapeFunction");
      throw InputError(sf ? sf->where() : case_.schemes().where(),
                       "shapeFunction: a case with a two-phase body (" + e->key() +
                           ", twoPhase) runs with linear or gimp shape functions; bspline2 does not keep the pore "
                           "liquid's balance at the surface yet");
    }
    try {  // the pore liquid's nodal fields
      // The bodies' retention and permeability models, by their type, from the plugins.
      porous_ = std::make_unique<PorousMedia<D>>(hydraulic_models(reg), grid_, exec_, gravity_, sch.shape,
                                                 Real(0.5) / BodySettings::read(e->dict()).particles_per_cell);
    } catch (const std::bad_alloc& err) {
      throw out_of_memory(0, err);
    }
    break;
  }
  if (porous_ && decomposed()) set_porous_halo();
  // The overburden of a geostatic stress from the material above (case/overburden.hpp):
  // every body's columns, each with its density (a two-phase body's mixture's), over the
  // whole lattice, so every rank holds the same columns. Gravity off one axis: none, and
  // generate_particles says why.
  std::optional<Overburden<D>> overburden;
  bool wanted = false;
  for (const Entry* e : case_.body_entries()) wanted = wanted || takes_overburden(e->dict());
  if (wanted && norm(gravity_) > 0 && gravity_axis(gravity_) >= 0) {
    overburden.emplace(gravity_);
    for (const Entry* e : case_.body_entries()) {
      const Real density = body_density(e->dict());
      overburden->add_body(e->dict(), global_,
                           DensityProfile{density, porous_ ? porous_->mixture_density(e->dict(), density)
                                                           : std::function<Real(Real)>{}},
                           case_.dir());
    }
  }
  std::size_t part = 0;  // the body's part of the memory estimate (0: the grid)
  for (const Entry* e : case_.body_entries()) {
    ++part;
    try {
      setup_body(*e, id, next_id, min_mass, overburden ? &*overburden : nullptr);
    } catch (const std::bad_alloc& err) {
      throw out_of_memory(part, err);
    }
  }
  mass_eps_ = sch.mass_tolerance * min_mass;
}

template <int D>
InputError Solver<D>::out_of_memory(std::size_t part, const std::bad_alloc& e) const {
  // The estimate check_setup made passed (or was not run): say what the part needs.
  const MemoryEstimate m = estimate_memory(case_, rt_.registry(), exec_.device, opt_.output, {comm_->size(), 1});
  const MemoryPart& p = m.parts.at(part);
  // A Buffer's allocation says its space; another one (a host vector) is the host's.
  const auto* oom = dynamic_cast<const mem::OutOfMemory*>(&e);
  const Device space = oom ? oom->device() : Device::cpu;
  const double bytes =
      space == Device::cuda ? p.backend() : p.host() + (exec_.device == Device::cpu ? p.backend() : 0);
  const std::string what = part == 0 ? "the grid's " + std::to_string(grid_.num_nodes()) + " nodes"
                                     : "the particles of " + p.what + " (about " +
                                           std::to_string(static_cast<long long>(p.count)) + ")";
  return InputError(p.where, p.key + ": " + what + " need about " + mem::format_bytes(bytes) + " of " +
                                 (space == Device::cuda ? "GPU" : "host") +
                                 " memory, and an allocation for them failed (" + e.what() +
                                 "); nothing was run. scree --check compares the case's memory with what is free");
}

template <int D>
Real Solver<D>::body_density(const Dictionary& b) const {
  const Dictionary& mat = case_.materials().sub(BodySettings::read(b).material);
  const Entry& type = mat.at("type");
  return rt_.registry().get(PluginKind::material, type.as_word(), type.where()).material.point(mat)->density();
}

template <int D>
void Solver<D>::setup_body(const Entry& e, int& id, std::int64_t& next_id, Real& min_mass,
                           const Overburden<D>* overburden) {
  const Registry& reg = rt_.registry();
  const SchemeSettings& sch = settings_.schemes;
  const Dictionary& b = e.dict();
  const BodySettings bs = BodySettings::read(b);
  const Dictionary& mat = case_.materials().sub(bs.material);
  const Entry& type = mat.at("type");
  const PluginEntry& pe = reg.get(PluginKind::material, type.as_word(), type.where());
  const Real density = body_density(b);

  // Generated in the whole grid's lattice (grid_ is this rank's part of it in a decomposed run).
  PointFilter<D> mine;
  if (decomposed())
    mine = [this](const Vec<D>& x) { return decomp_.owner(x, global_) == comm_->rank(); };
  // A two-phase body's geostatic stress is its mixture's total stress (prepare makes it effective).
  const std::function<Real(Real)> profile = porous_ ? porous_->mixture_density(b, density) : nullptr;
  GeneratedParticles<D> gp =
      generate_particles<D>(b, global_, density, gravity_, case_.dir(), mine, overburden, profile);
  body_totals_.push_back(gp.total);
  BodySetup<D> s;
  s.name = e.key();
  s.body_id = id++;
  s.material_name = bs.material;
  s.exec = exec_;
  s.shape = sch.shape;
  s.gimp_half_length = Real(0.5) / bs.particles_per_cell;
  s.transfer = sch.transfer;
  s.cell_size = grid_.h;
  s.x = std::move(gp.x);
  s.v = std::move(gp.v);
  s.volume = std::move(gp.volume);
  s.sigma = std::move(gp.sigma);
  s.velocity_gradient = gp.velocity_gradient;
  s.first_id = next_id;
  s.ids = std::move(gp.index);  // places in the body (a rank's part of it), made ids in place
  for (std::int64_t& i : s.ids) i += next_id;
  next_id += static_cast<std::int64_t>(gp.total);
  const bool porous = porous_ && porous_->prepare(b, s, density);
  // Every point of a body has the same volume: the same smallest mass on every rank,
  // whether it holds points of the body or not.
  min_mass = std::min(min_mass, gp.point_volume * density * s.mass_factor);
  std::unique_ptr<Body<D>> body;
  if constexpr (D == 2) body = pe.material.body2(mat, s);
  else body = pe.material.body3(mat, s);
  if (porous) porous_->attach(body.get());
  material_names_.push_back(bs.material);
  bodies_.push_back(std::move(body));
}

template <int D>
void Solver<D>::setup_split() {
  for (auto& b : bodies_) can_split_ = can_split_ || b->can_split_stress();
  can_split_ = can_split_ && !policy_.reference;
  const StressSplit s = policy_.split;
  split_ = can_split_ && (s == StressSplit::on || s == StressSplit::alternate ||
                          (s == StressSplit::automatic && exec_.device == Device::cuda));
  for (auto& b : bodies_) can_refill_ = can_refill_ || b->updates_in_turns();
  can_refill_ = can_refill_ && can_split_ && policy_.refill;
  refill_ = split_ && can_refill_;
  if (split_ && s == StressSplit::automatic) tuner_.emplace(can_refill_ ? 3 : 2);
}

template <int D>
void Solver<D>::setup_output() {
  const Registry& reg = rt_.registry();
  std::vector<std::unique_ptr<Writer>> writers;
  for (const Entry* e : case_.writer_entries())
    writers.push_back(plugin_of(reg, PluginKind::writer, e->dict()).writer(e->dict(), named(ctx_, e->key())));
  // A decomposed run's function objects that reduce over ranks are made on every rank and
  // see the run's ranks; the others only on the root, with one rank.
  auto fo_context = [&](const std::string& key, bool reduces) {
    SolverContext c = named(ctx_, key);
    c.comm = decomposed() && reduces ? comm_ : nullptr;
    return c;
  };
  if (!root()) {  // a decomposed run's other ranks: the writers of pieces, the reducing function objects
    for (auto& w : writers)
      if (w->writes_pieces()) piece_writers_.push_back(own_piece_writers_.emplace_back(std::move(w)).get());
    for (const Entry* e : case_.function_entries()) {
      const PluginEntry& pe = plugin_of(reg, PluginKind::functionObject, e->dict());
      FunctionObject* fo = nullptr;
      if (pe.reduces_over_ranks) {
        fo = own_functions_.emplace_back(pe.function_object(e->dict(), fo_context(e->key(), true))).get();
        energy_ledger_ = energy_ledger_ || fo->needs_energy_ledger();
      }
      rank_functions_.push_back(fo);
    }
    return;
  }
  std::vector<OutputSchedule::Function> functions;
  for (const Entry* e : case_.function_entries()) {
    const Dictionary& d = e->dict();
    const PluginEntry& pe = plugin_of(reg, PluginKind::functionObject, d);
    OutputSchedule::Function fn;
    fn.object = pe.function_object(d, fo_context(e->key(), pe.reduces_over_ranks));
    fn.reduces = pe.reduces_over_ranks;
    energy_ledger_ = energy_ledger_ || fn.object->needs_energy_ledger();
    const ParamReader r(*pe.spec, d);  // executeControl, executeInterval: declare_execute_control
    const std::string ec = r.word("executeControl");
    using Control = OutputSchedule::Function::Control;
    fn.control = ec == "timeStep" ? Control::timeStep : (ec == "runTime" ? Control::runTime : Control::writeTime);
    fn.interval = r.scalar("executeInterval");
    functions.push_back(std::move(fn));
  }
  const ControlSettings& cs = settings_.control;
  output_ = std::make_unique<OutputSchedule>(std::move(writers), std::move(functions),
                                             cs.write_control == WriteControl::timeStep, cs.write_interval,
                                             cs.time.start_time);
  if (decomposed()) {
    output_->set_decomposed();
    piece_writers_ = output_->piece_writers();
    std::string reduced, gathered;
    for (std::size_t i = 0; i < case_.function_entries().size(); ++i) {
      rank_functions_.push_back(output_->reducing(i));
      (rank_functions_.back() ? reduced : gathered) += " " + case_.function_entries()[i]->key();
    }
    if (!reduced.empty()) log_ << "Function objects reduced over the ranks:" << reduced << "\n";
    if (!gathered.empty())
      log_ << "Function objects on rank 0, the whole case gathered there when they are due:" << gathered << "\n";
  }
}

template <int D>
void Solver<D>::setup_boundaries(bool warn) {
  boundaries_.clear();
  node_laws_.clear();
  if (porous_) porous_->clear_conditions();
  WallSet set(NodeLattice::of(ctx_));
  const Registry& reg = rt_.registry();
  for (const Entry* e : case_.boundary_entries()) {
    const Dictionary& d = e->dict();
    auto bc = plugin_of(reg, PluginKind::boundaryCondition, d).boundary(d, named(ctx_, e->key()));
    const std::size_t before = set.table().size();
    bc->constrain(set);
    // A decomposed run: the nodes of every rank (whose wall tables may differ: one sum per condition).
    std::uint64_t none = 0, nodes = 0;
    // Walls and conditions on the pore liquid are counted; a node law selects its own nodes.
    bool counted = set.table().size() > before;
    for (std::size_t i = before; i < set.table().size(); ++i) {
      none += set.count(static_cast<int>(i)) == 0;
      nodes += static_cast<std::uint64_t>(set.count(static_cast<int>(i)));
    }
    // A condition on the pore liquid (rainfall, ponding, porePressure, seepageFace) as a wall.
    if (const auto* hc = dynamic_cast<const HydraulicCondition*>(bc.get())) {
      const std::uint64_t n = hydraulic_reach(*hc, NodeLattice::of(ctx_)).nodes.size();
      none += n == 0;
      nodes += n;
      counted = true;
    }
    if (counted && (decomposed() ? comm_->sum(nodes) == 0 : none > 0) && warn)
      log_ << "warning: " << d.where().str() << ": boundary condition '" << e->key() << "' selects no grid node\n";
    if (bc->has_node_law()) node_laws_.push_back(bc.get());
    // A condition on the pore liquid (porous/hydraulic_condition.hpp) goes to the porous media.
    if (auto errors = needs_two_phase(*e, *bc, porous_ != nullptr); !errors.empty()) throw errors.front();
    if (const auto* hc = dynamic_cast<const HydraulicCondition*>(bc.get())) porous_->add_condition(hc);
    boundaries_.push_back(std::move(bc));
  }
  has_walls_ = !set.table().empty();
  if (has_walls_) {
    walls_.resize(set.table().size(), exec_.device);
    walls_.copy_from_host(set.table());
    masks_.resize(set.masks().size(), exec_.device);
    masks_.copy_from_host(set.masks());
  }
  if (porous_)
    porous_->set_walls(has_walls_ ? walls_.data() : nullptr, has_walls_ ? masks_.data() : nullptr, set.table(),
                       set.masks());
}

template <int D>
void Solver<D>::set_velocities(std::size_t body, const std::vector<Real>& v) {
  if (step_ > 0) throw std::logic_error("set_velocities: only before the first step");
  bodies_.at(body)->set_velocities(v);
  if (time_.start(host_ctl_, comm_->max(static_cast<double>(max_signal_speed())), log_)) sync_control_to_device();
}

template void Solver<2>::set_velocities(std::size_t, const std::vector<Real>&);
template void Solver<3>::set_velocities(std::size_t, const std::vector<Real>&);

// The rest of Solver<D> is instantiated in solver.cpp, solver_output.cpp and diagnosis.cpp.
template Solver<2>::Solver(const Case&, PluginRuntime&, const RunOptions&);
template Solver<3>::Solver(const Case&, PluginRuntime&, const RunOptions&);
template Solver<2>::~Solver();
template Solver<3>::~Solver();

}  // namespace scree

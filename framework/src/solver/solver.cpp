// Solver<D> (see solver.hpp).
#include "solver.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "scree/material/material.hpp"
#include "scree/params/spec.hpp"
#include "scree/solver/particle_generation.hpp"

#if defined(SCREE_HAVE_CUDA)
#include <cuda_runtime_api.h>
#endif

namespace scree {

// ------------------------------------------------------------------ OutputThread

OutputThread::OutputThread() : thread_([this] { loop(); }) {}
OutputThread::~OutputThread() {
  {
    std::lock_guard lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}
void OutputThread::submit(Job job) {
  std::unique_lock lock(m_);
  cv_.wait(lock, [this] { return jobs_.empty() || error_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  jobs_.push_back(std::move(job));
  cv_.notify_all();
}
void OutputThread::drain() {
  std::unique_lock lock(m_);
  cv_.wait(lock, [this] { return (jobs_.empty() && !busy_) || error_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}
void OutputThread::loop() {
  std::unique_lock lock(m_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    busy_ = true;
    lock.unlock();
    try {
      job();
    } catch (...) {
      lock.lock();
      if (!error_) error_ = std::current_exception();
      busy_ = false;
      cv_.notify_all();
      continue;
    }
    lock.lock();
    busy_ = false;
    cv_.notify_all();
  }
}

// ------------------------------------------------------------------ helpers

namespace {

std::string fmt_time(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

#if defined(SCREE_HAVE_CUDA)
void cuda_check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(e));
}
#endif

}  // namespace

// ------------------------------------------------------------------ construction

template <int D>
Solver<D>::Solver(const Case& c, PluginRuntime& rt, const RunOptions& o)
    : case_(c), rt_(rt), opt_(o), log_(o.log ? *o.log : std::cout) {
  exec_.device = o.device;
  exec_.threads = std::max(1, o.threads);
#if defined(SCREE_HAVE_CUDA)
  if (exec_.device == Device::cuda) {
    cudaStream_t s;
    cuda_check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreate");
    stream_ = s;
    exec_.stream = s;
    cuda_check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreate");
    copy_stream_ = s;
  }
#endif
  tty_ = isatty(STDOUT_FILENO) && (!o.log || o.log == &std::cout);

  const Dictionary& sch = c.schemes();
  const std::string scheme = sch.get_word_or("updateScheme", "USF");
  scheme_ = scheme == "USL" ? UpdateScheme::USL : (scheme == "MUSL" ? UpdateScheme::MUSL : UpdateScheme::USF);
  const std::string shape = sch.get_word_or("shapeFunction", "linear");
  shape_ = shape == "gimp" ? ShapeKind::gimp : (shape == "bspline2" ? ShapeKind::bspline2 : ShapeKind::linear);
  transfer_ = sch.get_word_or("transfer", "FLIP") == "APIC" ? Transfer::apic : Transfer::flip;
  pic_fraction_ = sch.get_scalar_or("picFraction", 0.0);
  max_volume_ratio_ = sch.get_scalar_or("maxVolumeRatio", std::numeric_limits<double>::infinity());
  // Particles sorted by cell keep a warp's stencils together (its P2G adds combine before
  // the atomics) and the gathers in cache; the fast kernels re-sort every 200 steps unless
  // the case says otherwise (a particle crosses a 1 mm cell in ~100 steps at 1 m/s and
  // dt = 1e-5 s, and neighbours move together; a sort costs about two passes over the
  // particle data and ends a chunk of steps).
  sort_interval_ = sch.get_integer_or("sortInterval", o.reference_kernels ? 0 : 200);
  sparse_ = o.sparse_grid && !o.reference_kernels;
  mass_tolerance_ = sch.get_scalar_or("massTolerance", 1e-6);
  if (const Entry* d = sch.find("damping")) {
    const Dictionary& dd = d->dict();
    if (dd.get_word_or("type", "local") == "local") {
      damping_ = dd.get_scalar("coefficient");
      damping_start_ = dd.get_scalar_or("startTime", 0.0);
      damping_end_ = dd.get_scalar_or("endTime", 1e300);
    }
  }
  const auto g = c.gravity().at("value").as_scalar_list();
  for (int d = 0; d < D; ++d) gravity_[d] = g[d];

  setup_grid();
  setup_time();
  setup_bodies();
  for (auto& b : bodies_) can_split_ = can_split_ || b->can_split_stress();
  can_split_ = can_split_ && !o.reference_kernels;
  split_ = can_split_ && (o.split_elastic == StressSplit::on || o.split_elastic == StressSplit::alternate ||
                          (o.split_elastic == StressSplit::automatic && exec_.device == Device::cuda));
  tuner_.active = split_ && o.split_elastic == StressSplit::automatic;
  setup_boundaries();
  if (opt_.output) setup_output();
  check_time_step();
}

template <int D>
Solver<D>::~Solver() {
  output_thread_.reset();  // joins: writers finish before they are destroyed
  destroy_graphs();
#if defined(SCREE_HAVE_CUDA)
  if (stream_) cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
  if (copy_stream_) cudaStreamDestroy(static_cast<cudaStream_t>(copy_stream_));
#endif
}

template <int D>
void Solver<D>::setup_grid() {
  const Dictionary& gd = case_.grid();
  const auto lo = gd.at("lower").as_scalar_list(), hi = gd.at("upper").as_scalar_list();
  const Real h = gd.get_scalar("cellSize");
  const int ghost = static_cast<int>(gd.get_integer_or("ghostLayers", 2));
  grid_.h = h;
  grid_.ghost = ghost;
  for (int d = 0; d < D; ++d) {
    grid_.lower[d] = lo[d];
    grid_.upper[d] = hi[d];
    const Real cells = (hi[d] - lo[d]) / h;
    const int nc = static_cast<int>(std::ceil(cells - 1e-9));
    if (std::fabs(cells - std::round(cells)) > 1e-6)
      log_ << "warning: system/gridDict: the domain's extent along axis " << d
           << " is not a whole number of cells; it is extended to " << nc << " cells\n";
    grid_.upper[d] = lo[d] + nc * h;
    grid_.n[d] = nc + 1 + 2 * ghost;
    grid_.origin[d] = lo[d] - ghost * h;
    grid_.offset[d] = 0;
  }
  const Index nn = grid_.num_nodes();
  const int fields = 1 + 4 * D;
  for (int s = 0; s < 2; ++s) {
    grid_data_[s].resize(static_cast<std::size_t>(nn) * fields, exec_.device);
    Real* b = grid_data_[s].data();
    int k = 0;
    auto next = [&] { return b + static_cast<std::size_t>(k++) * nn; };
    tile_stamps_[s].resize(static_cast<std::size_t>(Tiles<D>::total(grid_)), exec_.device);
    sets_[s].mass = next();
    for (int d = 0; d < D; ++d) sets_[s].momentum[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].force[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].velocity[d] = next();
    for (int d = 0; d < D; ++d) sets_[s].velocity_new[d] = next();
  }

  ctx_.case_dir = case_.dir();
  ctx_.dimension = D;
  ctx_.device = exec_.device;
  ctx_.cell_size = h;
  for (int d = 0; d < D; ++d) {
    ctx_.grid_origin.push_back(grid_.origin[d]);
    ctx_.domain_lower.push_back(grid_.lower[d]);
    ctx_.domain_upper.push_back(grid_.upper[d]);
    ctx_.grid_nodes.push_back(grid_.n[d]);
    ctx_.gravity.push_back(gravity_[d]);
  }
}

template <int D>
void Solver<D>::setup_time() {
  const Dictionary& cd = case_.control();
  start_time_ = cd.get_scalar_or("startTime", 0.0);
  end_time_ = cd.get_scalar("endTime");
  delta_t_ = cd.get_scalar("deltaT");
  adaptive_ = cd.get_bool_or("adjustTimeStep", false);
  progress_interval_ = cd.get_integer_or("progressInterval", 0);
  ctx_.start_time = start_time_;
  ctx_.end_time = end_time_;
  ctx_.delta_t = delta_t_;

  host_ctl_ = StepControl{};
  host_ctl_.t[0] = start_time_;
  host_ctl_.dt[0] = delta_t_;
  host_ctl_.t_target = end_time_;
  host_ctl_.dt_max = adaptive_ ? cd.get_scalar_or("maxDeltaT", delta_t_) : delta_t_;
  host_ctl_.cfl = adaptive_ ? cd.get_scalar_or("maxCo", 0.5) : 0;
  host_ctl_.h = grid_.h;
  ctl_.resize(1, exec_.device);
  sync_control_to_device();
}

template <int D>
void Solver<D>::setup_bodies() {
  const Registry& reg = rt_.registry();
  std::int64_t next_id = 0;
  int id = 0;
  Real min_mass = 1e300;
  for (const Entry& e : case_.bodies().entries()) {
    if (!e.is_dict() || e.key() == "FoamFile" || e.key()[0] == '_') continue;
    const Dictionary& b = e.dict();
    const std::string mat_name = b.get_word("material");
    const Dictionary& mat = case_.materials().sub(mat_name);
    const Entry& type = mat.at("type");
    const PluginEntry& pe = reg.get(PluginKind::material, type.as_word(), type.where());
    const Real density = pe.material.point(mat)->density();

    GeneratedParticles<D> gp = generate_particles<D>(b, grid_, density, gravity_);
    BodySetup<D> s;
    s.name = e.key();
    s.body_id = id++;
    s.material_name = mat_name;
    s.exec = exec_;
    s.shape = shape_;
    const int ppc = static_cast<int>(b.get_integer_or("particlesPerCell", 2));
    s.gimp_half_length = Real(0.5) / ppc;
    s.transfer = transfer_;
    s.cell_size = grid_.h;
    s.x = std::move(gp.x);
    s.v = std::move(gp.v);
    s.volume = std::move(gp.volume);
    s.sigma = std::move(gp.sigma);
    s.velocity_gradient = gp.velocity_gradient;
    s.first_id = next_id;
    next_id += static_cast<std::int64_t>(s.x.size());
    for (Real v : s.volume) min_mass = std::min(min_mass, v * density);
    std::unique_ptr<Body<D>> body;
    if constexpr (D == 2) body = pe.material.body2(mat, s);
    else body = pe.material.body3(mat, s);
    ctx_.body_names.push_back(e.key());
    bodies_.push_back(std::move(body));
  }
  mass_eps_ = mass_tolerance_ * min_mass;
}

template <int D>
void Solver<D>::setup_boundaries() {
  ConstraintSet set(ctx_);
  const Registry& reg = rt_.registry();
  for (const Entry& e : case_.boundaries().entries()) {
    if (!e.is_dict() || e.key() == "FoamFile" || e.key()[0] == '_') continue;
    const Dictionary& d = e.dict();
    const Entry& type = d.at("type");
    const PluginEntry& pe = reg.get(PluginKind::boundaryCondition, type.as_word(), type.where());
    SolverContext c = ctx_;
    c.name = e.key();
    auto bc = pe.boundary(d, c);
    const std::size_t before = set.table().size();
    bc->constrain(set);
    for (std::size_t i = before; i < set.table().size(); ++i)
      if (set.count(static_cast<int>(i)) == 0)
        log_ << "warning: " << d.where().str() << ": boundary condition '" << e.key()
             << "' selects no grid node\n";
    boundaries_.push_back(std::move(bc));
  }
  has_constraints_ = !set.table().empty();
  if (has_constraints_) {
    constraints_.resize(set.table().size(), exec_.device);
    constraints_.copy_from_host(set.table());
    masks_.resize(set.masks().size(), exec_.device);
    masks_.copy_from_host(set.masks());
  }
}

template <int D>
void Solver<D>::setup_output() {
  const Dictionary& cd = case_.control();
  const Registry& reg = rt_.registry();
  const std::string wc = cd.get_word_or("writeControl", "adjustableRunTime");
  write_schedule_.control = wc == "timeStep" ? Scheduled::Control::timeStep : Scheduled::Control::runTime;
  write_schedule_.interval = cd.get_scalar("writeInterval");
  write_schedule_.next_time = start_time_;
  write_schedule_.next_step = 0;
  if (const Entry* w = cd.find("writers")) {
    for (const Entry& e : w->dict().entries()) {
      if (!e.is_dict() || e.key()[0] == '_') continue;
      const Entry& type = e.dict().at("type");
      const PluginEntry& pe = reg.get(PluginKind::writer, type.as_word(), type.where());
      SolverContext c = ctx_;
      c.name = e.key();
      writers_.push_back(pe.writer(e.dict(), c));
      writers_want_grid_ |= writers_.back()->wants_grid();
    }
  }
  if (const Entry* f = cd.find("functions")) {
    for (const Entry& e : f->dict().entries()) {
      if (!e.is_dict() || e.key()[0] == '_') continue;
      const Dictionary& d = e.dict();
      const Entry& type = d.at("type");
      const PluginEntry& pe = reg.get(PluginKind::functionObject, type.as_word(), type.where());
      SolverContext c = ctx_;
      c.name = e.key();
      functions_.push_back(pe.function_object(d, c));
      Scheduled s;
      const std::string ec = d.get_word_or("executeControl", "writeTime");
      s.control = ec == "timeStep" ? Scheduled::Control::timeStep
                                   : (ec == "runTime" ? Scheduled::Control::runTime : Scheduled::Control::writeTime);
      s.interval = d.get_scalar_or("executeInterval", 1.0);
      s.next_time = start_time_;
      s.next_step = 0;
      function_schedule_.push_back(s);
    }
  }
  output_thread_ = std::make_unique<OutputThread>();
}

template <int D>
void Solver<D>::check_time_step() {
  Real cmax = 0;
  for (auto& b : bodies_) cmax = std::max(cmax, b->max_signal_speed(grid_.h));
  if (cmax <= 0) return;
  const Real stable = grid_.h / cmax;
  if (adaptive_) {
    host_ctl_.dt[0] = std::min<Real>(delta_t_, host_ctl_.cfl * stable);
    sync_control_to_device();
  } else if (delta_t_ > stable) {
    log_ << "warning: system/controlDict: deltaT " << delta_t_ << " s exceeds the stable time step " << stable
         << " s (h / c with the largest signal speed c = " << cmax
         << " m/s at the start); the run may blow up. Use a smaller deltaT or adjustTimeStep yes.\n";
    dt_warned_ = true;
  }
}

// A fixed step that was stable at the start may not stay so: the granular models stiffen
// with pressure and density (K ~ p^n, eq. 13 of seed 001), and an impact can raise p
// tenfold. Every 5 s of wall time the signal speed is measured again (one copy of the
// particle state to the host: milliseconds) and the first time the step exceeds h / c
// the user is told when, and what to do, before the run blows up.
template <int D>
void Solver<D>::watch_time_step() {
  if (adaptive_ || dt_warned_ || wall_ - dt_watch_wall_ < 5.0) return;
  dt_watch_wall_ = wall_;
  Real cmax = 0;
  for (auto& b : bodies_) cmax = std::max(cmax, b->max_signal_speed(grid_.h));
  if (!(cmax > 0) || delta_t_ <= grid_.h / cmax) return;
  log_ << "\nwarning: system/controlDict: at t = " << host_ctl_.t[step_ % 2] << " s (step " << step_
       << ") deltaT " << delta_t_ << " s exceeds the stable time step " << grid_.h / cmax
       << " s (h / c, largest signal speed c = " << cmax
       << " m/s); the run may blow up. Use adjustTimeStep yes (maxCo 0.5) or a smaller deltaT.\n";
  dt_warned_ = true;
}

// ------------------------------------------------------------------ the step

template <int D>
PassParams<D> Solver<D>::pass_params(unsigned flags, int gather_set, int scatter_set, int gather_parity) const {
  PassParams<D> pp;
  pp.flags = flags;
  pp.parity = static_cast<int>(step_ % 2);
  pp.gather_parity = gather_parity;
  pp.grid = grid_;
  pp.gather = sets_[gather_set];
  pp.scatter = sets_[scatter_set];
  pp.control = ctl_.data();
  pp.gravity = gravity_;
  pp.pic_fraction = pic_fraction_;
  pp.max_volume_ratio = max_volume_ratio_;
  pp.transfer = transfer_;
  pp.serial = exec_.device == Device::cpu && exec_.threads == 1;
  pp.reference = opt_.reference_kernels;
  pp.need_speed = adaptive_ || opt_.reference_kernels;
  pp.tile_stamps = sparse_ ? tile_stamps_[scatter_set].data() : nullptr;
  pp.stress_blocks_per_sm = opt_.stress_blocks_per_sm;
  pp.split_elastic = split_;
  pp.elastic_blocks_per_sm = opt_.elastic_blocks_per_sm;
  return pp;
}

template <int D>
GridUpdateParams<D> Solver<D>::grid_params(unsigned modes, int set) const {
  GridUpdateParams<D> gp;
  gp.modes = modes;
  gp.parity = static_cast<int>(step_ % 2);
  gp.grid = grid_;
  gp.cur = sets_[set];
  gp.other = sets_[1 - set];
  gp.control = ctl_.data();
  gp.constraints = has_constraints_ ? constraints_.data() : nullptr;
  gp.masks = has_constraints_ ? masks_.data() : nullptr;
  gp.mass_eps = mass_eps_;
  gp.damping = damping_;
  gp.damping_start = damping_start_;
  gp.damping_end = damping_end_;
  if (sparse_) {
    gp.cur_stamps = tile_stamps_[set].data();
    gp.other_stamps = tile_stamps_[1 - set].data();
  }
  return gp;
}

namespace {
/// The gather phases that finish step k (run fused into step k+1 or by flush()).
unsigned pending_flags(UpdateScheme s) {
  switch (s) {
    case UpdateScheme::USL: return kGatherVelocity | kGatherPosition | kStressFromNew;
    case UpdateScheme::USF: return kGatherVelocity | kGatherPosition;
    case UpdateScheme::MUSL: return kStressFromVelocity | kGatherPosition;
  }
  return 0;
}
}  // namespace

template <int D>
template <class F>
void Solver<D>::phase(const char* name, F&& f) {
  if (!opt_.profile) {
    f();
    return;
  }
  mem::synchronize(exec_.device);
  const auto t0 = std::chrono::steady_clock::now();
  f();
  mem::synchronize(exec_.device);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto& [n, t] : profile_)
    if (n == name) {
      t += s;
      return;
    }
  profile_.emplace_back(name, s);
}

template <int D>
void Solver<D>::report_profile() {
  if (profile_.empty()) return;
  double total = 0;
  for (auto& [n, t] : profile_) total += t;
  log_ << "Profile (synchronised per phase, " << step_ << " steps):\n";
  for (auto& [n, t] : profile_)
    log_ << "  " << std::left << std::setw(44) << n << std::right << std::setw(10) << std::setprecision(4)
         << 1e6 * t / std::max<std::int64_t>(1, step_) << " us/step  " << std::setw(5) << std::setprecision(3)
         << 100 * t / total << " %\n";
}

template <int D>
void Solver<D>::step() {
  const int p = static_cast<int>(step_ % 2);
  const int A = 1 - p, B = p;
  const unsigned pend = pending_ ? pending_flags(scheme_) : 0u;
  auto passes = [&](const char* name, unsigned flags, int g, int s, int gp) {
    phase(name, [&] {
      for (auto& b : bodies_) b->pass(pass_params(flags, g, s, gp));
    });
  };
  auto grid = [&](const char* name, unsigned modes) {
    phase(name, [&] { grid_update<D>(exec_, grid_params(modes, B)); });
  };
  switch (scheme_) {
    case UpdateScheme::USL:
      passes("particles: G2P + stress + P2G (fused)", pend | kScatterMassMomentum | kScatterForce, A, B, A);
      grid("grid: velocity, integration, clear", kNormalize | kIntegrate | kZeroOther | kAdvance);
      break;
    case UpdateScheme::USF:
      passes("particles: G2P + P2G mass, momentum", pend | kScatterMassMomentum, A, B, A);
      grid("grid: velocity, clear", kNormalize | kZeroOther);
      passes("particles: stress + P2G force", kStressFromVelocity | kScatterForce, B, B, B);
      grid("grid: integration", kIntegrate | kAdvance);
      break;
    case UpdateScheme::MUSL:
      passes("particles: stress, x + P2G m, p, f", pend | kScatterMassMomentum | kScatterForce, A, B, A);
      grid("grid: velocity, integration, clear", kNormalize | kIntegrate | kZeroForce | kZeroOther);
      passes("particles: G2P velocity + P2G momentum", kGatherVelocity | kScatterMomentum, B, B, B);
      grid("grid: remapped velocity", kRemap | kAdvance);
      break;
  }
  pending_ = true;
  ++step_;
}

template <int D>
void Solver<D>::flush() {
  if (!pending_) return;
  const int p = static_cast<int>(step_ % 2);  // parity of the next step
  const int last = 1 - p;                     // set and parity of the last step
  for (auto& b : bodies_) b->pass(pass_params(pending_flags(scheme_), last, last, last));
  pending_ = false;
}

template <int D>
void Solver<D>::destroy_graphs() {
#if defined(SCREE_HAVE_CUDA)
  for (auto& g : graphs_)
    if (g) {
      cudaGraphExecDestroy(static_cast<cudaGraphExec_t>(g));
      g = nullptr;
    }
#endif
}

template <int D>
void Solver<D>::launch_steps(std::int64_t n) {
#if defined(SCREE_HAVE_CUDA)
  if (exec_.device == Device::cuda && opt_.use_graphs && !opt_.profile) {
    // The first step after a flush differs (no pending gather): launch it directly.
    while (n > 0 && !pending_) {
      step();
      --n;
    }
    auto stream = static_cast<cudaStream_t>(stream_);
    while (n >= 2) {
      const int p = static_cast<int>(step_ % 2);
      if (!graphs_[p]) {
        const std::int64_t saved = step_;
        cudaGraph_t graph;
        cuda_check(cudaStreamBeginCapture(stream, cudaStreamCaptureModeThreadLocal), "cudaStreamBeginCapture");
        step();
        step();
        cuda_check(cudaStreamEndCapture(stream, &graph), "cudaStreamEndCapture");
        cudaGraphExec_t exec;
        cuda_check(cudaGraphInstantiate(&exec, graph, 0), "cudaGraphInstantiate");
        cudaGraphDestroy(graph);
        graphs_[p] = exec;
        step_ = saved;  // capturing ran nothing
      }
      cuda_check(cudaGraphLaunch(static_cast<cudaGraphExec_t>(graphs_[p]), stream), "cudaGraphLaunch");
      step_ += 2;
      n -= 2;
    }
    while (n-- > 0) step();
    return;
  }
#endif
  for (std::int64_t i = 0; i < n; ++i) step();
}

template <int D>
void Solver<D>::sync_control_from_device() {
  mem::synchronize(exec_.device);
  ctl_.copy_to_host(&host_ctl_);
}

template <int D>
void Solver<D>::sync_control_to_device() {
  mem::synchronize(exec_.device);
  ctl_.copy_from_host(&host_ctl_, 1);
}

// ------------------------------------------------------------------ time loop

template <int D>
void Solver<D>::advance_chunked(double target, std::int64_t step_limit, bool with_output) {
  // step_limit: stop after this many more steps (-1: none).
  std::int64_t budget = step_limit;
  for (;;) {
    const int p = static_cast<int>(step_ % 2);
    const double t = host_ctl_.t[p];
    if (t >= target - 1e-12 * std::max(1.0, std::fabs(target)) || budget == 0) break;
    // Next event: the earliest of target, output times and function-object times.
    double t_event = target;
    std::int64_t step_event = -1;
    auto consider = [&](const Scheduled& s) {
      if (s.control == Scheduled::Control::timeStep) {
        const std::int64_t due = s.next_step - step_;
        if (due > 0 && (step_event < 0 || due < step_event)) step_event = due;
      } else if (s.control == Scheduled::Control::runTime && s.next_time > t) {
        t_event = std::min(t_event, s.next_time);
      }
    };
    if (with_output && !writers_.empty()) consider(write_schedule_);
    if (with_output)
      for (auto& s : function_schedule_) consider(s);
    if (with_output && (!writers_.empty() || !functions_.empty())) {
      // Function objects on writeTime follow the write schedule.
      if (write_schedule_.control == Scheduled::Control::timeStep) {
        const std::int64_t due = write_schedule_.next_step - step_;
        if (due > 0 && (step_event < 0 || due < step_event)) step_event = due;
      } else if (write_schedule_.next_time > t) {
        t_event = std::min(t_event, write_schedule_.next_time);
      }
    }

    // Steps in this chunk: enough to reach t_event, capped by events, budget and a
    // progress-report interval (about 0.5 s of wall time, or progressInterval steps).
    const Real dt = std::max<Real>(host_ctl_.dt[p], 1e-300);
    std::int64_t n = static_cast<std::int64_t>(std::ceil((t_event - t) / dt - 1e-9));
    if (adaptive_) n += 1;
    n = std::max<std::int64_t>(n, 1);
    if (step_event > 0) n = std::min(n, step_event);
    if (budget > 0) n = std::min(n, budget);
    std::int64_t report = progress_interval_ > 0
                              ? progress_interval_
                              : static_cast<std::int64_t>(std::max(2.0, chunk_rate_ * 0.5));
    if (sort_interval_ > 0) report = std::min(report, sort_interval_ - step_ % sort_interval_);
    n = std::min(n, std::max<std::int64_t>(report, 1));

    if (host_ctl_.t_target != t_event) {
      host_ctl_.t_target = t_event;
      // Re-derive this step's dt against the new target (it may have been clamped to 0).
      Real dt_next = adaptive_ ? host_ctl_.dt_max : delta_t_;
      if (adaptive_ && host_ctl_.dt[p] > 0) dt_next = std::min<Real>(dt_next, host_ctl_.dt[p]);
      if (adaptive_ && host_ctl_.dt[p] == 0 && host_ctl_.max_speed[1 - p] > 0)
        dt_next = std::min<Real>(dt_next, host_ctl_.cfl * grid_.h / host_ctl_.max_speed[1 - p]);
      const Real rem = t_event - t;
      if (rem < dt_next * (1 + 1e-6)) dt_next = rem;
      host_ctl_.dt[p] = dt_next;
      sync_control_to_device();
    }
    const auto t0 = std::chrono::steady_clock::now();
    launch_steps(n);
    sync_control_from_device();
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (sec > 0) chunk_rate_ = 0.7 * chunk_rate_ + 0.3 * (n / sec);
    wall_ += sec;
    if (split_) split_steps_ += n;
    if (tuner_.active) tune_split(n, sec);
    if (opt_.split_elastic == StressSplit::alternate && can_split_) set_split(!split_);
    if (budget > 0) budget -= n;
    if (sort_interval_ > 0 && step_ % sort_interval_ == 0) {
      // Queued on the stream; a pending G2P applies to the particles in their new order.
      for (auto& b : bodies_) b->sort_by_cell(grid_);
    }
    if (with_output) output_due(false);
    if (opt_.progress) report_progress(false);
    watch_time_step();
    if (host_ctl_.lost > 0 && !lost_warned_) {
      log_ << "\nwarning: " << host_ctl_.lost
           << " particle(s) left the grid and are frozen: enlarge the domain in system/gridDict, or, if "
              "the run blew up, reduce deltaT\n";
      lost_warned_ = true;
    }
  }
}

/// The split's tuner (RunOptions::split_elastic = automatic): after a chunk of steps run one
/// way, record its rate; every kTrialSeconds of run time run one chunk the other way, then
/// keep whichever was faster (by 3%, so that noise does not flip it back and forth). The
/// flow changes what is faster (the share of plastic points, and so the second kernel's
/// work), hence the repeated trials; a trial costs at most a chunk (~0.5 s) in ~10 s.
template <int D>
void Solver<D>::tune_split(std::int64_t n, double seconds) {
  constexpr double kTrialSeconds = 10;
  // Chunks of a few steps (the first ones, or cut short by an event) time the host, not
  // the kernels.
  if (n < 50 || seconds <= 0) return;
  const int now = split_ ? 1 : 0;
  tuner_.rate[now] = static_cast<double>(n) / seconds;
  bool want = split_;
  if (tuner_.trial) {
    tuner_.trial = false;
    // keep the trial's way only if it beat the other clearly
    if (tuner_.rate[now] < 1.03 * tuner_.rate[1 - now]) want = !split_;
    tuner_.next_trial_wall = wall_ + kTrialSeconds;
  } else if (wall_ >= tuner_.next_trial_wall) {
    tuner_.trial = true;
    want = !split_;
  }
  set_split(want);
}

template <int D>
void Solver<D>::set_split(bool on) {
  if (on == split_) return;
  split_ = on;
  // The split's kernels clear the counter of the step after theirs: when they stop, the
  // last step's count stays behind, and a later split step of that parity would re-run
  // the points it lists (a 2.5 mm column collapse on the GPU took 50% more steps so).
  for (auto& b : bodies_) b->reset_split();
  destroy_graphs();  // captured with the other way's kernels
}

template <int D>
void Solver<D>::output_due(bool force_all) {
  const double t = host_ctl_.t[step_ % 2];
  const double eps = 1e-9 * std::max(1.0, std::fabs(t)) + 1e-12;
  auto due = [&](Scheduled& s, bool is_write) -> bool {
    typename Scheduled::Control c = s.control;
    if (!is_write && c == Scheduled::Control::writeTime) c = write_schedule_.control;
    const Scheduled& clock = (!is_write && s.control == Scheduled::Control::writeTime) ? write_schedule_ : s;
    if (c == Scheduled::Control::timeStep) return step_ >= clock.next_step;
    return t >= clock.next_time - eps;
  };
  const bool write = !writers_.empty() && (force_all || due(write_schedule_, true));
  std::vector<std::size_t> run;
  for (std::size_t i = 0; i < functions_.size(); ++i)
    if (force_all || due(function_schedule_[i], false)) run.push_back(i);
  if (!write && run.empty()) return;

  const auto t0 = std::chrono::steady_clock::now();
  const bool with_grid = writers_want_grid_ && write;
  std::shared_ptr<Snapshot> snap;
  std::vector<std::function<void(BodySnapshot&)>> finish;
  if (exec_.device == Device::cuda && !with_grid) {
    // Asynchronous: the particle data are copied on the device and sent to the host on
    // their own stream while the next steps run; the output thread waits for the copy,
    // builds the fields and writes. The run stops only for the flush's pass.
    flush();
    snap = std::make_shared<Snapshot>(snapshot_header());
    for (auto& b : bodies_) finish.push_back(b->snapshot_async(copy_stream_));
  } else {
    snap = std::make_shared<Snapshot>(snapshot(with_grid));
  }
  std::vector<Writer*> ws;
  if (write)
    for (auto& w : writers_) ws.push_back(w.get());
  std::vector<FunctionObject*> fs;
  for (auto i : run) fs.push_back(functions_[i].get());
  output_thread_->submit([snap, finish, ws, fs] {
    for (std::size_t i = 0; i < finish.size(); ++i) {
      const std::string material = snap->bodies[i].material;
      finish[i](snap->bodies[i]);
      snap->bodies[i].material = material;
    }
    for (auto* w : ws) w->write(*snap);
    for (auto* f : fs) f->execute(*snap);
  });
  output_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  auto bump = [&](Scheduled& s) {
    if (s.control == Scheduled::Control::timeStep) {
      const auto iv = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::llround(s.interval)));
      while (s.next_step <= step_) s.next_step += iv;
    } else {
      while (s.next_time <= t + eps) s.next_time += s.interval;
    }
  };
  if (write) bump(write_schedule_);
  for (auto i : run)
    if (function_schedule_[i].control != Scheduled::Control::writeTime) bump(function_schedule_[i]);
}

template <int D>
void Solver<D>::report_progress(bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_report_).count();
  if (!final && !tty_ && since < 10.0) return;  // logs: a line every 10 s
  if (!final && tty_ && since < 0.2) return;
  last_report_ = now;
  const double t = host_ctl_.t[step_ % 2];
  const double elapsed = std::chrono::duration<double>(now - run_start_).count();
  const double done = (t - start_time_) / std::max(1e-300, end_time_ - start_time_);
  const double eta = done > 0 ? elapsed * (1 - done) / done : -1;
  std::ostringstream os;
  os << "t = " << std::setprecision(6) << std::setw(10) << t << " s  step " << std::setw(9) << step_ << "  "
     << std::setprecision(4) << (elapsed > 0 ? step_ / elapsed : 0.0) << " steps/s  " << std::fixed
     << std::setprecision(1) << 100 * done << "%  elapsed " << fmt_time(elapsed) << "  ETA " << fmt_time(eta);
  if (tty_)
    log_ << "\r" << os.str() << "   " << (final ? "\n" : "") << std::flush;
  else
    log_ << os.str() << "\n" << std::flush;
}

template <int D>
RunStats Solver<D>::run() {
  run_start_ = last_report_ = std::chrono::steady_clock::now();
  log_ << "Running " << case_.dir().string() << ": " << D << "D, " << bodies_.size() << " bod"
       << (bodies_.size() == 1 ? "y" : "ies") << ", " << stats().particles << " particles, "
       << grid_.num_nodes() << " grid nodes, backend " << to_string(exec_.device)
       << (exec_.device == Device::cpu ? " (" + std::to_string(exec_.threads) + " threads)" : "") << "\n";
  if (opt_.output) output_due(false);  // the initial state
  advance_chunked(end_time_, opt_.max_steps, opt_.output);
  if (opt_.output) {
    output_due(true);  // the final state (also when endTime is not on the write grid)
    output_thread_->drain();
    for (auto& w : writers_) w->finish();
    for (auto& f : functions_) f->finish();
  }
  if (opt_.progress) report_progress(true);
  report_profile();
  return stats();
}

template <int D>
void Solver<D>::advance_to(double t, bool with_output) {
  advance_chunked(t, -1, with_output);
  if (with_output && output_thread_) output_thread_->drain();
}

template <int D>
void Solver<D>::run_steps(std::int64_t n) {
  const double t0 = host_ctl_.t[step_ % 2];
  (void)t0;
  advance_chunked(end_time_, n, false);
}

template <int D>
Snapshot Solver<D>::snapshot_header() const {
  Snapshot s;
  s.time = host_ctl_.t[step_ % 2];
  s.step = step_;
  s.dimension = D;
  s.bodies.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    s.bodies[i].material = case_.bodies().sub(bodies_[i]->name()).get_word("material");
  return s;
}

template <int D>
Snapshot Solver<D>::snapshot(bool with_grid) {
  flush();
  mem::synchronize(exec_.device);
  Snapshot s = snapshot_header();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const std::string material = s.bodies[i].material;
    bodies_[i]->snapshot(s.bodies[i]);
    s.bodies[i].material = material;
  }
  if (with_grid) {
    s.has_grid = true;
    const Index nn = grid_.num_nodes();
    for (int d = 0; d < D; ++d) {
      s.grid.n[d] = grid_.n[d];
      s.grid.origin[d] = grid_.origin[d];
    }
    s.grid.h = grid_.h;
    const int last = static_cast<int>((step_ + 1) % 2);
    auto copy = [&](const Real* p) {
      std::vector<Real> v(nn);
      mem::copy(v.data(), Device::cpu, p, exec_.device, nn * sizeof(Real));
      return v;
    };
    FieldData mass{"mass", 1, "kg", "nodal mass", copy(sets_[last].mass)};
    FieldData vel{"velocity", 3, "m/s", "nodal velocity v^{k+1}", std::vector<Real>(3 * nn, 0.0)};
    for (int d = 0; d < D; ++d) {
      const auto c = copy(sets_[last].velocity_new[d]);
      for (Index i = 0; i < nn; ++i) vel.values[3 * i + d] = c[i];
    }
    s.grid.fields.push_back(std::move(mass));
    s.grid.fields.push_back(std::move(vel));
  }
  return s;
}

template <int D>
void Solver<D>::set_velocities(std::size_t body, const std::vector<Real>& v) {
  if (step_ > 0) throw std::logic_error("set_velocities: only before the first step");
  bodies_.at(body)->set_velocities(v);
  check_time_step();
}

template <int D>
RunStats Solver<D>::stats() const {
  RunStats r;
  r.steps = step_;
  r.simulated_time = host_ctl_.t[step_ % 2] - start_time_;
  r.wall_seconds = wall_;
  r.output_seconds = output_wall_;
  for (auto& b : bodies_) {
    r.particles += b->size();
    r.bytes_per_particle = std::max(r.bytes_per_particle, b->bytes_per_particle());
  }
  r.nodes = grid_.num_nodes();
  r.peak_device_bytes = mem::peak_bytes(exec_.device);
  r.lost_particles = host_ctl_.lost;
  r.split_steps = split_steps_;
  return r;
}

template class Solver<2>;
template class Solver<3>;

}  // namespace scree

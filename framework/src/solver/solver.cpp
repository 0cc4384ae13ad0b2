// Solver<D>: the time loop (see solver.hpp; construction in solver_setup.cpp).
#include "solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>

namespace scree {

// ------------------------------------------------------------------ one step

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
void Solver<D>::step() {
  if (porous_) {
    step_two_phase();
    return;
  }
  const int p = parity();
  const int A = 1 - p, B = p;
  const UpdateScheme scheme = settings_.schemes.update_scheme;
  const unsigned pend = pending_ ? pending_flags(scheme) : 0u;
  auto passes = [&](const char* name, unsigned flags, int g, int s, int gp) {
    phase(name, [&] {
      for (auto& b : bodies_) b->pass(pass_params(flags, g, s, gp));
    });
  };
  auto grid = [&](const char* name, unsigned modes) {
    phase(name, [&] {
      grid_update<D>(exec_, grid_params(modes, B));
      apply_node_laws(modes, B);
    });
  };
  switch (scheme) {
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

/// The two-phase step (porous/two_phase.hpp), USL: the liquid's gather at the points'
/// positions x^k (the last step's G2P of v_l and the pore pressure), the solid's pass (its
/// G2P and stress; a single-phase body's P2G too), both phases' P2G of the two-phase bodies
/// at x^{k+1} (MixtureScatter), then both phases' grid update.
template <int D>
void Solver<D>::step_two_phase() {
  const int p = parity();
  const int A = 1 - p, B = p;
  const unsigned pend = pending_ ? pending_flags(UpdateScheme::USL) : 0u;
  PassParams<D> pp = pass_params(pend | kScatterMassMomentum | kScatterForce, A, B, A);
  pp.tile_stamps = nullptr;  // the two-phase grid update visits every node
  PassParams<D> gather_only = pp;
  gather_only.flags &= ~kAnyScatter;
  phase("pore liquid: G2P v_l, pore pressure", [&] {
    if (pending_) porous_->gather(pp, A, B);
  });
  phase("particles: G2P + stress (+ P2G of single-phase bodies)", [&] {
    for (auto& b : bodies_) b->pass(porous_->holds(b.get()) ? gather_only : pp);
  });
  phase("both phases: P2G", [&] { porous_->scatter(pp, A, B); });
  phase("grid: both phases, implicit drag", [&] {
    const DampingSettings& damping = settings_.schemes.damping;
    porous_->grid_update(B, ctl_.data(), p, mass_eps_, damping.coefficient, damping.start_time, damping.end_time,
                         sets_);
    apply_node_laws(kNormalize | kIntegrate, B);
  });
  pending_ = true;
  ++step_;
}

template <int D>
void Solver<D>::flush() {
  if (!pending_) return;
  const int last = 1 - parity();  // set and parity of the last step
  const unsigned flags = pending_flags(settings_.schemes.update_scheme);
  if (porous_) porous_->gather(pass_params(flags, last, last, last), last, last);
  for (auto& b : bodies_) b->pass(pass_params(flags, last, last, last));
  if (porous_) porous_->finish_columns(last, last);
  pending_ = false;
  // The gather may have updated the clock: USL's stress update of the last step records
  // its signal speed (for the next step's dt), the position update counts lost points.
  // The host's copy, which the next chunk's retarget writes back, must hold them: without
  // them, the step after every write of an adaptive USL run was maxDeltaT (14 times the
  // CFL step in tests/verification/restart), and lost points found here were forgotten.
  sync_control_from_device();
}

template <int D>
PassParams<D> Solver<D>::pass_params(unsigned flags, int gather_set, int scatter_set, int gather_parity) const {
  PassParams<D> pp;
  pp.flags = flags;
  pp.parity = parity();
  pp.gather_parity = gather_parity;
  pp.grid = grid_;
  pp.gather = sets_[gather_set];
  pp.scatter = sets_[scatter_set];
  pp.control = ctl_.data();
  pp.gravity = gravity_;
  pp.pic_fraction = settings_.schemes.pic_fraction;
  pp.pic_rate = settings_.schemes.pic_rate;
  pp.max_volume_ratio = settings_.schemes.max_volume_ratio;
  pp.transfer = settings_.schemes.transfer;
  pp.serial = exec_.device == Device::cpu && exec_.threads == 1;
  pp.reference = policy_.reference;
  // The signal speed: for the adaptive step, and for the health check of a fixed one (stopCo).
  pp.need_speed = time_.adaptive() || policy_.reference || (host_ctl_.stop_co > 0 && policy_.health_checks);
  // A fixed step wants the speed for the stopCo check alone: sampled (PassParams::speed_mask).
  pp.speed_mask = time_.adaptive() || policy_.reference ? 0u : static_cast<unsigned>(policy_.speed_every - 1);
  pp.tile_stamps = policy_.sparse() ? tile_stamps_[scatter_set].data() : nullptr;
  pp.stress_blocks_per_sm = policy_.stress_blocks_per_sm;
  pp.split_elastic = split_;
  pp.elastic_blocks_per_sm = policy_.elastic_blocks_per_sm;
  pp.energy = energy_ledger_;
  pp.ledger_light_transfer = policy_.ledger_light_transfer;
  // The walls' share on the points where the gather still sees the step's force (USF, USL;
  // MUSL re-maps momentum into the force array first): PassParams::wall_ledger.
  pp.wall_ledger = energy_ledger_ && settings_.schemes.update_scheme != UpdateScheme::MUSL && !porous_;
  pp.mass_eps = mass_eps_;
  const DampingSettings& damping = settings_.schemes.damping;
  pp.damping = damping.coefficient;
  pp.damping_start = damping.start_time;
  pp.damping_end = damping.end_time;
  return pp;
}

template <int D>
GridUpdateParams<D> Solver<D>::grid_params(unsigned modes, int set) const {
  GridUpdateParams<D> gp;
  gp.modes = modes;
  gp.parity = parity();
  gp.grid = grid_;
  gp.cur = sets_[set];
  gp.other = sets_[1 - set];
  gp.control = ctl_.data();
  gp.walls = has_walls_ ? walls_.data() : nullptr;
  gp.masks = has_walls_ ? masks_.data() : nullptr;
  gp.mass_eps = mass_eps_;
  const DampingSettings& damping = settings_.schemes.damping;
  gp.damping = damping.coefficient;
  gp.damping_start = damping.start_time;
  gp.damping_end = damping.end_time;
  gp.energy = energy_ledger_;
  gp.energy_walls = energy_ledger_ && (settings_.schemes.update_scheme == UpdateScheme::MUSL || porous_);
  gp.health = policy_.health_checks;
  if (policy_.sparse()) {
    gp.cur_stamps = tile_stamps_[set].data();
    gp.other_stamps = tile_stamps_[1 - set].data();
  }
  return gp;
}

/// Boundary conditions with node laws of their own act after the grid update (and its
/// walls) on the velocities it produced (boundary/boundary_condition.hpp).
template <int D>
void Solver<D>::apply_node_laws(unsigned modes, int set) const {
  if (node_laws_.empty()) return;
  GridNodes<D> g;
  g.grid = grid_;
  g.fields = sets_[set];
  g.control = ctl_.data();
  g.parity = parity();
  g.velocity = (modes & (kNormalize | kRemap)) != 0;
  g.velocity_new = (modes & kIntegrate) != 0;
  for (const BoundaryCondition* bc : node_laws_) bc->apply(exec_, g);
}

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
  profile_.add(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

template <int D>
void Solver<D>::launch_steps(std::int64_t n) {
  if (graphs_) {
    // The first step after a flush differs (no pending gather): launch it directly.
    for (; n > 0 && !pending_; --n) step();
    for (; n >= 2; n -= 2) {
      graphs_->replay(parity(), [&] {  // capturing queues the steps but runs nothing
        const std::int64_t saved = step_;
        step();
        step();
        step_ = saved;
      });
      step_ += 2;
    }
  }
  for (; n > 0; --n) step();
}

// ------------------------------------------------------------------ the loop

template <int D>
void Solver<D>::advance_chunked(double target, std::int64_t step_limit, bool with_output) {
  std::int64_t budget = step_limit;  // steps left (-1: no limit)
  for (;;) {
    const int p = parity();
    const double t = host_ctl_.t[p];
    if (TimeControl::reached(t, target) || budget == 0) break;
    // A chunk of steps ends at the next event: the target, an output or function-object
    // time, the step budget, a particle sort, or a progress report (about 0.5 s of wall
    // time, or progressInterval steps).
    double t_event = target;
    std::int64_t step_event = -1;
    if (with_output && output_) output_->next_event(t, step_, t_event, step_event);
    std::int64_t n = time_.steps_to(host_ctl_, p, t_event);
    if (step_event > 0) n = std::min(n, step_event);
    if (budget > 0) n = std::min(n, budget);
    const std::int64_t every = settings_.control.progress_interval;
    std::int64_t report = every > 0 ? every : static_cast<std::int64_t>(std::max(2.0, chunk_rate_ * 0.5));
    if (sort_interval_ > 0) report = std::min(report, sort_interval_ - steps_done() % sort_interval_);
    n = std::min(n, std::max<std::int64_t>(report, 1));

    if (time_.retarget(host_ctl_, p, t_event)) sync_control_to_device();
    run_chunk(n);
    if (budget > 0) budget -= n;
    after_chunk(with_output);
    if (const int sig = stop_requested(); sig != 0) {  // SIGINT/SIGTERM (scree's handler)
      std::ostringstream m;
      m << "stopped by signal " << sig << " at t = " << time() << " s (step " << step_ << ", " << steps_done()
        << " steps advanced the clock)";
      throw RunInterrupted(m.str(), sig);
    }
  }
}

template <int D>
void Solver<D>::run_chunk(std::int64_t n) {
  const auto t0 = std::chrono::steady_clock::now();
  launch_steps(n);
  sync_control_from_device();
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (sec > 0) chunk_rate_ = 0.7 * chunk_rate_ + 0.3 * (n / sec);
  wall_ += sec;
  if (split_) split_steps_ += n;
  if (tuner_) set_split(tuner_->next(split_, n, sec, wall_));
  if (policy_.split == StressSplit::alternate && can_split_) set_split(!split_);
}

template <int D>
void Solver<D>::after_chunk(bool with_output) {
  check_health();  // before any output: the regular schedule does not write a failed state
  // Sorts happen after every sortInterval steps that advanced the clock: the steps that
  // idle on a target time (dt = 0, their number set by where a chunk of steps ended, which
  // depends on the wall time) do not count, so that a run reproduces itself bit for bit.
  if (sort_interval_ > 0 && steps_done() % sort_interval_ == 0 && steps_done() != sorted_at_) {
    sorted_at_ = steps_done();
    // Queued on the stream; a pending G2P applies to the particles in their new order.
    for (auto& b : bodies_) b->sort_by_cell(grid_);
  }
  if (with_output) output_due(false);
  if (opt_.progress) progress_.report(time(), step_, false);
  time_.watch(wall_, time(), step_, [this] { return max_signal_speed(); }, log_);
  if (host_ctl_.lost > 0 && !lost_warned_) {
    log_ << "\nwarning: " << host_ctl_.lost
         << " particle(s) left the grid and are frozen: enlarge the domain in system/gridDict, or, if "
            "the run blew up, reduce deltaT\n";
    lost_warned_ = true;
  }
}

template <int D>
void Solver<D>::check_health() {
  if (host_ctl_.failure == 0 && time_.adaptive()) {
    // The adaptive step collapsed (a material whose signal speed exploded): it cannot add
    // to the clock, or the run would need more steps than any run can take. A step that
    // lands on a target may be a sliver legitimately: only a step short of it counts.
    const int p = parity();
    const double t = host_ctl_.t[p], dt = host_ctl_.dt[p];
    if (dt > 0 && !TimeControl::reached(t + dt, host_ctl_.t_target) &&
        (t + dt == t || (time_.end_time() - t) / dt > TimeControl::kMaxSteps)) {
      host_ctl_.failure = kFailStalled;
      host_ctl_.failed_step = host_ctl_.step[p];
    }
  }
  if (host_ctl_.failure == 0) return;
  throw RunFailure(diagnosis());
}

namespace {
std::string vec_str(const Real* v, int n) {
  std::ostringstream o;
  o << "(";
  for (int i = 0; i < n; ++i) o << (i ? " " : "") << v[i];
  o << ")";
  return o.str();
}
std::string where(const Dictionary& d, const char* key) {
  const Entry* e = d.find(key);
  if (e) return e->where().str() + ": " + key;
  const auto& file = d.where().file;
  return (file ? *file + ": " : std::string()) + key + " (not set: the default)";
}
}  // namespace

template <int D>
std::string Solver<D>::diagnosis() {
  const StepControl c = host_ctl_;
  const Snapshot s = snapshot(false);  // the state the clock stopped in (a host copy)
  std::ostringstream m;
  m.precision(6);
  m << "the run went wrong and was stopped in step " << c.failed_step << " (t = " << time() << " s):";
  // Body, material and particle of a point the kernels recorded.
  auto point = [&](const StepControl::BadPoint& b, std::size_t& body, Index& i) -> std::string {
    body = s.bodies.size();
    for (std::size_t k = 0; k < s.bodies.size(); ++k)
      if (s.bodies[k].body_id == b.body) body = k;
    if (body == s.bodies.size() || b.index < 0 || b.index >= s.bodies[body].n) return "a particle";
    i = b.index;
    const BodySnapshot& bs = s.bodies[body];
    const Entry* mat = case_.materials().find(bs.material);
    return "particle " + std::to_string(bs.id[i]) + " of body '" + bs.name + "' (material '" + bs.material + "', " +
           bs.material_type + (mat ? ", " + mat->where().str() : std::string()) + ")";
  };
  if (c.failure & kFailNonFinite) {
    static const char* fields[] = {"position", "velocity", "stress"};
    static const char* axes[] = {"x", "y", "z"};
    static const char* stress[] = {"xx", "yy", "zz", "xy", "yz", "zx"};
    // Found by the grid update (report_nonfinite_node): the point is the first one of the
    // frozen state with a non-finite position, velocity or stress.
    StepControl::BadPoint bad = c.bad;
    if (bad.index < 0) {
      bad.index = -1;
      for (std::size_t k = 0; k < s.bodies.size() && bad.index < 0; ++k) {
        const BodySnapshot& bs = s.bodies[k];
        const FieldData* vel = bs.find("velocity");
        const FieldData* sig = bs.find("stress");
        for (Index q = 0; q < bs.n && bad.index < 0; ++q) {
          const struct { int field, n, stride; const Real* v; } probes[] = {
              {kBadPosition, D, 3, &bs.position[3 * q]},
              {kBadVelocity, D, 3, vel ? &vel->values[3 * q] : nullptr},
              {kBadStress, 6, 6, sig ? &sig->values[6 * q] : nullptr}};
          for (const auto& pr : probes) {
            for (int j = 0; pr.v && j < pr.n && bad.index < 0; ++j)
              if (!std::isfinite(pr.v[j])) {
                bad.body = bs.body_id;
                bad.field = pr.field;
                bad.component = j;
                bad.index = q;
                bad.value = pr.v[j];
              }
          }
        }
      }
    }
    const int f = bad.field;
    const char* comp = f == kBadStress ? stress[bad.component % 6] : axes[bad.component % 3];
    std::size_t b = 0;
    Index i = -1;
    if (bad.index < 0) {
      m << "\n  a nodal velocity or force of the grid update is not finite (step " << bad.step
        << "), and no particle's position, velocity or stress is";
    } else {
      const std::string who = point(bad, b, i);
      m << "\n  " << fields[f % 3] << " " << comp << " = " << bad.value << " (not finite) of " << who
        << ", found in step " << bad.step << "; " << bad.count << " non-finite value(s) in that step";
    }
    if (i >= 0) m << "\n  its position " << vec_str(&s.bodies[b].position[3 * i], D);
    m << "\n  the material's parameters, the time step (" << where(case_.control(), "deltaT")
      << ") or the loads (constant/g, boundary conditions) drove it there";
  }
  if (c.failure & kFailLost) {
    std::size_t b = 0;
    Index i = -1;
    const std::string who = point(c.first_lost, b, i);
    m << "\n  " << c.lost << " of " << stats().particles << " particles have left the grid, more than "
      << where(case_.control(), "maxLostFraction") << " = " << settings_.control.max_lost_fraction << " allows";
    m << "\n  the first, in step " << c.first_lost.step << ": " << who;
    if (i >= 0) {
      const FieldData* v = s.bodies[b].find("velocity");
      m << ", last inside at " << vec_str(&s.bodies[b].position[3 * i], D);
      if (v) m << " with velocity " << vec_str(&v->values[3 * i], D) << " m/s";
    }
    m << "\n  the grid: " << where(case_.grid(), "lower") << " and " << where(case_.grid(), "upper")
      << "; if the particles were flung out, look at the loads (constant/g) and the time step";
  }
  // The body with the largest signal speed c + |v| now (a host copy of each body).
  auto fastest = [&] {
    Real cmax = -1;
    std::string who;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const Real ck = bodies_[k]->max_signal_speed(grid_.h);
      if (!(ck <= cmax)) {
        cmax = ck;
        const BodySnapshot& bs = s.bodies[k];
        const Entry* mat = case_.materials().find(bs.material);
        who = "body '" + bs.name + "' (material '" + bs.material + "', " + bs.material_type +
              (mat ? ", " + mat->where().str() : std::string()) + ")";
      }
    }
    std::ostringstream o;
    o.precision(6);
    o << "the largest signal speed c + |v| = " << cmax << " m/s is in " << who;
    return o.str();
  };
  if (c.failure & kFailStalled) {
    const int p = parity();
    m << "\n  the adaptive step has collapsed to dt = " << c.dt[p] << " s: reaching endTime " << time_.end_time()
      << " s would take " << (time_.end_time() - c.t[p]) / c.dt[p] << " steps\n  " << fastest()
      << "\n  the adaptive step follows it (" << where(case_.control(), "maxCo")
      << "): a material's parameters out of range, or a blown-up state";
  }
  if (c.failure & kFailUnstable) {
    m << "\n  the step's Courant number dt (c + |v|)_max / h = " << c.failed_co << " is above stopCo "
      << host_ctl_.stop_co << " (" << where(case_.control(), "stopCo") << "): the step is unstable";
    m << "\n  " << fastest();
    m << "\n  the fixed step " << where(case_.control(), "deltaT") << " " << settings_.control.time.delta_t
        << " s exceeds the stable step h / (c + |v|) = " << settings_.control.time.delta_t / c.failed_co
        << " s: reduce it, or use adjustTimeStep yes";
  }
  return m.str();
}

template <int D>
void Solver<D>::set_split(bool on) {
  if (on == split_) return;
  split_ = on;
  // The split's kernels clear the counter of the step after theirs: when they stop, the
  // last step's count stays behind, and a later split step of that parity would re-run
  // the points it lists (a 2.5 mm column collapse on the GPU took 50% more steps so).
  for (auto& b : bodies_) b->reset_split();
  if (graphs_) graphs_->clear();  // captured with the other way's kernels
}

template <int D>
void Solver<D>::output_due(bool force_all, CheckpointWhen when) {
  if (!output_) return;
  const double t = time();
  const OutputSchedule::Due due = output_->due(t, step_, force_all);
  // Checkpoints at every checkpointInterval-th write time after the run's first output
  // (the initial state, or the restart's own), and when asked (endTime, a signal).
  const std::int64_t every = settings_.control.checkpoint_interval;
  if (due.write_time && !first_output_) ++writes_;
  const bool checkpoint = when != CheckpointWhen::never && every > 0 && !first_output_ && t != checkpoint_time_ &&
                          (when == CheckpointWhen::always || (due.write_time && writes_ % every == 0));
  first_output_ = false;
  std::vector<double> schedule;  // before done(): a restart runs what is due now
  if (checkpoint) schedule = output_->state();
  if (!due.any()) {
    if (checkpoint) write_checkpoint(schedule);
    output_->done(due, t, step_);
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::shared_ptr<Snapshot> snap;
  std::vector<std::function<void(BodySnapshot&)>> finish;
  if (exec_.device == Device::cuda && !due.with_grid) {
    // Asynchronous: the particle data are copied on the device and sent to the host on
    // their own stream while the next steps run; the output thread waits for the copy,
    // builds the fields and writes. The run stops only for the flush's pass.
    flush();
    snap = std::make_shared<Snapshot>(snapshot_header());
    for (auto& b : bodies_) {
      std::vector<BodySnapshot::Scalar> scalars;  // taken now, at this time
      if (porous_) porous_->scalars(b.get(), scalars);
      finish.push_back([fill = b->snapshot_async(copy_stream_), scalars](BodySnapshot& out) {
        fill(out);
        out.scalars = scalars;
      });
    }
  } else {
    snap = std::make_shared<Snapshot>(snapshot(due.with_grid));
  }
  output_->submit(due, std::move(snap), std::move(finish));
  if (checkpoint) write_checkpoint(schedule);
  output_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  output_->done(due, t, step_);
}

template <int D>
void Solver<D>::write_checkpoint(const std::vector<double>& schedule) {
  // The particles as of now (the set the next step scatters into is then all zeros); the
  // host's clock is the device's after a flush (flush reads it back).
  flush();
  mem::synchronize(exec_.device);
  auto ck = std::make_shared<Checkpoint>();
  ck->dimension = D;
  ck->time = time();
  ck->step = step_;
  ck->sorted_at = sorted_at_;
  ck->writes = writes_;
  ck->clock.resize(sizeof host_ctl_);
  std::memcpy(ck->clock.data(), &host_ctl_, sizeof host_ctl_);
  ck->schedule = schedule;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Checkpoint::Body b;
    b.name = ctx_.body_names[i];
    b.material_type = bodies_[i]->material_type();
    b.particles = static_cast<std::uint64_t>(bodies_[i]->size());
    b.data = bodies_[i]->save_state();
    b.columns = bodies_[i]->bytes_per_particle() / sizeof(Real);
    ck->bodies.push_back(std::move(b));
  }
  if (porous_) ck->liquid = porous_->save_state();
  checkpoint_time_ = ck->time;
  // Written after the frames of this time (the output thread runs its jobs in order).
  const std::filesystem::path file = checkpoint_file(case_.dir(), ck->time), dir = case_.dir();
  const std::size_t keep = static_cast<std::size_t>(settings_.control.checkpoint_keep);
  output_->submit_job([ck, file, dir, keep] {
    ck->write(file);
    purge_checkpoints(dir, keep);
  });
}

template <int D>
Real Solver<D>::max_signal_speed() const {
  Real cmax = 0;
  for (auto& b : bodies_) cmax = std::max(cmax, b->max_signal_speed(grid_.h));
  if (porous_) cmax = std::max(cmax, porous_->max_signal_speed());
  return cmax;
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

// ------------------------------------------------------------------ the public face

template <int D>
RunStats Solver<D>::run() {
  progress_.start();
  log_ << "Running " << case_.dir().string() << ": " << D << "D, " << bodies_.size() << " bod"
       << (bodies_.size() == 1 ? "y" : "ies") << ", " << stats().particles << " particles, " << grid_.num_nodes()
       << " grid nodes, backend " << to_string(exec_.device)
       << (exec_.device == Device::cpu
               ? " (" + std::to_string(exec_.threads) + (exec_.threads == 1 ? " thread)" : " threads)")
               : "")
       << std::endl;  // flushed: a run killed early still leaves its header in the log
  if (opt_.output) output_due(false);  // the initial state
  try {
    advance_chunked(time_.end_time(), opt_.max_steps, opt_.output);
  } catch (const RunFailure&) {
    // The state the run stopped in, written for the diagnosis (frozen on the device since
    // the failing step: step_control.hpp), then the failure goes to the caller. No
    // checkpoint of it: the newest is the last healthy write time, to restart from.
    finish_output(CheckpointWhen::never);
    throw;
  } catch (const RunInterrupted&) {
    finish_output(CheckpointWhen::always);  // the state at the stop, and a checkpoint to continue from
    throw;
  }
  if (opt_.output) {
    // The final state (also when endTime is not on the write grid) and its checkpoint,
    // from which a later endTime continues.
    output_due(true, CheckpointWhen::always);
    const auto t0 = std::chrono::steady_clock::now();
    output_->finish();  // waits for the output thread: output time too
    output_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (opt_.progress) progress_.report(time(), step_, true);
  profile_.report(log_, step_);
  return stats();
}

template <int D>
void Solver<D>::finish_output(CheckpointWhen checkpoint) {
  if (!opt_.output) return;
  output_due(true, checkpoint);
  output_->finish();
}

template <int D>
void Solver<D>::advance_to(double t, bool with_output) {
  advance_chunked(t, -1, with_output);
  if (with_output && output_) output_->drain();
}

template <int D>
void Solver<D>::run_steps(std::int64_t n) {
  advance_chunked(time_.end_time(), n, false);
}

template <int D>
Snapshot Solver<D>::snapshot_header() const {
  Snapshot s;
  s.time = time();
  s.step = steps_done();  // the steps that advanced the clock: the same in every run
  s.dimension = D;
  // The ledger as of the last sync with the device: flush() has just read the clock back.
  s.energy.kept = energy_ledger_;
  if (energy_ledger_) {
    const Real* e = host_ctl_.energy;
    s.energy.stress_work = e[kEnergyStressWork];
    s.energy.collisional = e[kEnergyCollisional];
    s.energy.pic = e[kEnergyPic];
    s.energy.damping = e[kEnergyDamping];
    s.energy.walls = e[kEnergyWalls];
  }
  s.bodies.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    s.bodies[i].material = material_names_[i];
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
    if (porous_) porous_->scalars(bodies_[i].get(), s.bodies[i].scalars);
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
  if (time_.start(host_ctl_, max_signal_speed(), log_)) sync_control_to_device();
}

template <int D>
RunStats Solver<D>::stats() const {
  RunStats r;
  r.steps = step_;
  r.simulated_time = time() - run_start_;
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

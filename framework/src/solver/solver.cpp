// Solver<D>: the step and the time loop (see solver.hpp; its other units are listed there).
#include "solver.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>

namespace scree {

// ------------------------------------------------------------------ one step

namespace {
/// P2G (eqs. 5-6 and the nodal force): mass, momentum, internal and external force.
constexpr unsigned kP2G = kScatterMassMomentum | kScatterForce;
}  // namespace

/// One step, its stages in the order of its update scheme (solver.hpp): particle passes,
/// the first one fused with the last step's G2P (fused_pass), the others on this step's
/// grid set (this_step_pass), and grid updates of this step's set.
template <int D>
void Solver<D>::step() {
  if (porous_) {
    step_two_phase();
    return;
  }
  auto particles = [&](const char* name, const PassParams<D>& pp) {
    phase(name, [&] {
      for (auto& b : bodies_) b->pass(pp);
    });
    scattered_ |= pp.flags & kAnyScatter;
  };
  auto grid = [&](const char* name, unsigned modes) {
    if (decomposed()) exchange_before_grid(parity(), modes);
    phase(name, [&] {
      grid_update<D>(exec_, grid_params(modes, parity()));
      apply_node_laws(modes, parity());
    });
  };
  switch (settings_.schemes.update_scheme) {
    case UpdateScheme::USL:
      particles("particles: G2P + stress + P2G (fused)", fused_pass(kP2G));
      grid("grid: velocity, integration, clear", kNormalize | kIntegrate | kZeroOther | kAdvance);
      break;
    case UpdateScheme::USF:
      particles("particles: G2P + P2G mass, momentum", fused_pass(kScatterMassMomentum));
      grid("grid: velocity, clear", kNormalize | kZeroOther);
      particles("particles: stress + P2G force", this_step_pass(kStressFromVelocity | kScatterForce));
      grid("grid: integration", kIntegrate | kAdvance);
      break;
    case UpdateScheme::MUSL:
      particles("particles: stress, x + P2G m, p, f", fused_pass(kP2G));
      grid("grid: velocity, integration, clear", kNormalize | kIntegrate | kZeroForce | kZeroOther);
      particles("particles: G2P velocity + P2G momentum", this_step_pass(kGatherVelocity | kScatterMomentum));
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
  PassParams<D> pp = fused_pass(kP2G);
  pp.tile_stamps = nullptr;  // the two-phase grid update visits every node
  PassParams<D> gather_only = pp;
  gather_only.flags &= ~kAnyScatter;
  phase("pore liquid: G2P v_l, pore pressure", [&] {
    if (pending_) porous_->gather(pp, A, B);
  });
  phase("particles: G2P + stress (+ P2G of single-phase bodies)", [&] {
    for (auto& b : bodies_) b->pass(porous_->holds(b.get()) ? gather_only : pp);
  });
  phase("both phases: P2G", [&] { porous_->scatter(pp, A, B); });  // with its halo sums (PorousMedia::set_halo)
  if (decomposed()) exchange_before_grid(B, kAdvance);  // the clock's reduction
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
  const PassParams<D> g2p = pass_params(g2p_of(settings_.schemes.update_scheme), last, last, last);
  if (porous_) porous_->gather(g2p, last, last);
  for (auto& b : bodies_) b->pass(g2p);
  if (porous_) porous_->finish_columns(last, last);
  pending_ = false;
  // The gather may have updated the clock: USL's stress update of the last step records
  // its signal speed (for the next step's dt), the position update counts lost points.
  // The host's copy, which the next chunk's retarget writes back, must hold them, or the
  // next step would start from a cleared speed (next_cfl_step, time/step_control.hpp) and
  // lost points found here would be forgotten.
  sync_control_from_device();
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
    const std::int64_t every = settings_.control.progress_interval;
    std::int64_t report = every > 0 ? every : static_cast<std::int64_t>(std::max(2.0, chunk_rate_ * 0.5));
    if (sort_interval_ > 0) report = std::min(report, sort_interval_ - steps_done() % sort_interval_);
    std::int64_t n = time_.chunk_length(host_ctl_, p, t_event, step_event, budget, report);
    if (decomposed()) phase("ranks: chunk agreement", [&] { agree_chunk(n, t_event); });

    if (time_.retarget(host_ctl_, p, t_event)) sync_control_to_device();
    run_chunk(n);
    if (budget > 0) budget -= n;
    after_chunk(with_output);
    if (const int sig = decomposed() ? agree_signal() : stop_requested(); sig != 0) {  // SIGINT/SIGTERM (scree's handler)
      std::ostringstream m;
      m << "stopped by signal " << sig << " at t = " << time() << " s (step " << step_ << ")";
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
  if (refill_) refill_steps_ += n;
  if (tuner_) set_stress_way(tuner_->next(stress_way(), n, sec, wall_));
  if (policy_.split == StressSplit::alternate && can_split_) set_stress_way(split_ ? 0 : 2);
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
  if (with_output) output_due(false);  // a decomposed run's migrates after the flush of its output
  if (decomposed() && !migrated_ && steps_done() >= next_migration_) phase("ranks: migration of points", [&] { migrate(); });
  migrated_ = false;
  if (opt_.progress) progress_.report(time(), step_, false);
  if (root()) time_.watch(wall_, time(), step_, [this] { return max_signal_speed(); }, log_);
  if (host_ctl_.lost > 0 && !lost_warned_) {
    log_ << "\nwarning: " << host_ctl_.lost
         << " particle(s) left the grid and are frozen: enlarge the domain in system/gridDict, or, if "
            "the run blew up, reduce deltaT\n";
    lost_warned_ = true;
  }
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
  progress_.start(time(), step_);
  first_step_ = step_;
  log_ << "Running " << case_.dir().string() << ": " << D << "D, " << bodies_.size() << " bod"
       << (bodies_.size() == 1 ? "y" : "ies") << ", " << stats().particles << " particles, " << global_.num_nodes()
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
    report_bounded_updates();
    throw;
  }
  if (opt_.output) {
    // The final state (also when endTime is not on the write grid) and its checkpoint,
    // from which a later endTime continues.
    output_due(true, CheckpointWhen::always);
    const auto t0 = std::chrono::steady_clock::now();
    if (output_) output_->finish();  // waits for the output thread: output time too
    output_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (opt_.progress) progress_.report(time(), step_, true);
  report_bounded_updates();
  profile_.report(log_, step_ - first_step_, *comm_);
  return stats();
}

template <int D>
void Solver<D>::report_bounded_updates() {
  std::vector<std::uint64_t> n(bodies_.size(), 0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) n[i] = bodies_[i]->bounded_updates();
  comm_->sum(n.data(), static_cast<int>(n.size()));
  const double steps = static_cast<double>(step_ - first_step_);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const std::string bound = bodies_[i]->work_bound();
    if (bound.empty()) continue;
    const double updates = steps * static_cast<double>(body_totals_[i]);
    std::ostringstream m;
    m << "scree: body '" << bodies_[i]->name() << "': " << n[i] << " stress update" << (n[i] == 1 ? "" : "s")
      << " reached the bound on their work (" << bound << ")";
    if (n[i] > 0 && updates > 0) m << ", " << std::setprecision(3) << static_cast<double>(n[i]) / updates
                                   << " of its " << updates << " point-updates";
    log_ << m.str() << "\n";
  }
}

template <int D>
void Solver<D>::advance_to(double t, bool with_output) {
  advance_chunked(t, -1, with_output);
  if (with_output && output_) output_->drain();
  if (decomposed() && with_output) comm_->barrier();  // the root's files are written when every rank returns
}

template <int D>
void Solver<D>::run_steps(std::int64_t n) {
  advance_chunked(time_.end_time(), n, false);
}

template class Solver<2>;
template class Solver<3>;

}  // namespace scree

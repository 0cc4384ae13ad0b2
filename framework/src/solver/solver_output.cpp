// Solver<D>: output, checkpoints and the run's statistics. What is due at a write time goes to the output
// thread (output/output_schedule.hpp) as a snapshot of the particles (and the grid when a
// writer asks for it), with a checkpoint (case/checkpoint.hpp) queued after the frames of
// its time.
#include <chrono>
#include <cstring>

#include "solver.hpp"

namespace scree {

template <int D>
void Solver<D>::output_due(bool force_all, CheckpointWhen when) {
  if (!output_ && !decomposed()) return;
  const double t = time();
  // A decomposed run: the root's schedule decides, and every rank takes part in the gathers.
  OutputSchedule::Due due;
  bool checkpoint = false;
  std::vector<double> schedule;  // before done(): a restart runs what is due now
  if (output_) {
    due = output_->due(t, step_, force_all);
    // Checkpoints at every checkpointInterval-th write time after the run's first output
    // (the initial state, or the restart's own), and when asked (endTime, a signal).
    const std::int64_t every = settings_.control.checkpoint_interval;
    if (due.write_time && !first_output_) ++writes_;
    checkpoint = when != CheckpointWhen::never && every > 0 && !first_output_ && t != checkpoint_time_ &&
                 (when == CheckpointWhen::always || (due.write_time && writes_ % every == 0));
    if (!force_all) {
      due_schedule_ = output_->state();
      due_step_ = step_;
    }
    // Forced after this step's scheduled output, the checkpoint keeps the schedule from
    // before it: the restart writes again what was due at its time, as an uninterrupted
    // run has it, and drops what only the forced output wrote.
    if (checkpoint) schedule = force_all && step_ == due_step_ ? due_schedule_ : output_->state();
  }
  first_output_ = false;
  if (decomposed()) {
    output_ranks(due, checkpoint, schedule);
    return;
  }
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
    const std::vector<Real> liquid = porous_ ? liquid_totals() : std::vector<Real>{};
    for (auto& b : bodies_) {
      std::vector<BodySnapshot::Scalar> scalars;  // taken now, at this time
      if (porous_) porous_->scalars(b.get(), liquid, scalars);
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
void Solver<D>::output_ranks(const OutputSchedule::Due& due, bool checkpoint, const std::vector<double>& schedule) {
  // What the root's schedule found due: the writers of pieces write on every rank, and so
  // do the function objects that reduce over ranks; the other function objects and any
  // other writer get the whole case gathered on the root.
  struct {
    bool write, pieces, gather, grid, checkpoint;
  } agreed{due.any(), due.write && !piece_writers_.empty(), output_ && output_->gathers(due), due.with_grid,
           checkpoint};
  comm_->broadcast(&agreed, sizeof agreed, 0);
  std::vector<std::uint64_t> reducing;  // the due function objects that run on every rank
  if (root())
    for (std::size_t i : due.functions)
      if (rank_functions_[i]) reducing.push_back(i);
  std::uint64_t count = reducing.size();
  comm_->broadcast(&count, sizeof count, 0);
  reducing.resize(count);
  comm_->broadcast(reducing.data(), count * sizeof(std::uint64_t), 0);
  if (agreed.write || agreed.checkpoint) {  // the state written, every point in its owner's box
    flush();
    migrate(false);
    migrated_ = true;
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (agreed.write) {
    auto snap = std::make_shared<Snapshot>(local_snapshot(agreed.grid));
    std::vector<std::string> frames;
    if (agreed.pieces) frames = write_pieces(*snap);
    for (std::uint64_t i : reducing) {
      std::string error;
      try {
        rank_functions_[i]->execute(*snap);
      } catch (const std::exception& e) {
        error = e.what();
      }
      agree_error(error);
    }
    if (agreed.gather)
      gather_snapshot(*snap);
    else if (agreed.grid)
      gather_grid(*snap);
    if (root())
      for (std::size_t i = 0; i < frames.size(); ++i) piece_writers_[i]->end_frame(*snap, frames[i], comm_->size());
    if (agreed.gather && output_) output_->submit(due, std::move(snap), {});
  }
  if (agreed.checkpoint) write_checkpoint(schedule);
  output_wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (output_) output_->done(due, time(), step_);
}

template <int D>
std::vector<std::string> Solver<D>::write_pieces(const Snapshot& local) {
  std::vector<std::string> frames(piece_writers_.size());
  std::string error;
  if (root()) try {
      for (std::size_t i = 0; i < frames.size(); ++i) frames[i] = piece_writers_[i]->begin_frame(local);
    } catch (const std::exception& e) {
      error = e.what();
    }
  agree_error(error);
  for (std::string& f : frames) {  // each frame's name from the root
    std::uint64_t len = f.size();
    comm_->broadcast(&len, sizeof len, 0);
    f.resize(len);
    comm_->broadcast(f.data(), len, 0);
  }
  try {
    for (std::size_t i = 0; i < frames.size(); ++i) piece_writers_[i]->write_piece(local, frames[i], comm_->rank());
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree_error(error);  // every rank's piece is in place
  return frames;
}

template <int D>
void Solver<D>::agree_error(const std::string& error) {
  const int R = comm_->size();
  std::vector<std::uint64_t> failed(static_cast<std::size_t>(R), 0);
  failed[static_cast<std::size_t>(comm_->rank())] = error.empty() ? 0 : 1;
  comm_->sum(failed.data(), R);
  int who = -1;
  for (int r = 0; r < R && who < 0; ++r)
    if (failed[static_cast<std::size_t>(r)] != 0) who = r;
  if (who < 0) return;
  std::string msg = comm_->rank() == who ? error : std::string();
  std::uint64_t len = msg.size();
  comm_->broadcast(&len, sizeof len, who);
  msg.resize(len);
  comm_->broadcast(msg.data(), len, who);
  throw std::runtime_error("rank " + std::to_string(who) + " of " + std::to_string(R) + ": " + msg);
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
  ck->physics = case_physics(case_);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Checkpoint::Body b;
    b.name = ctx_.body_names[i];
    b.material_type = bodies_[i]->material_type();
    b.particles = static_cast<std::uint64_t>(bodies_[i]->size());
    b.data = bodies_[i]->save_state();
    b.columns = bodies_[i]->bytes_per_particle() / sizeof(Real);
    ck->bodies.push_back(std::move(b));
  }
  if (porous_) ck->liquid = liquid_totals();  // over the ranks: the root's share on a restart
  checkpoint_time_ = ck->time;
  const std::filesystem::path file = checkpoint_file(case_.dir(), ck->time), dir = case_.dir();
  if (decomposed()) {
    ck->decomposition = decomp_.tree_code();
    reduce_checkpoint_clock(*ck);
    // Every rank writes the points it holds now; the root writes the manifest once every
    // piece is on disk (agree_error waits for all), so a killed run leaves either the
    // whole new checkpoint or none of it.
    const std::filesystem::path piece = checkpoint_piece(file, comm_->rank());
    std::string error;
    try {
      std::filesystem::create_directories(piece.parent_path());
      ck->write(piece);
    } catch (const std::exception& e) {
      error = e.what();
    }
    agree_error(error);
    std::vector<std::uint64_t> totals;
    for (const Checkpoint::Body& b : ck->bodies) totals.push_back(b.particles);
    comm_->sum(totals.data(), static_cast<int>(totals.size()));
    if (!output_) return;
    for (std::size_t i = 0; i < ck->bodies.size(); ++i) {
      ck->bodies[i].particles = totals[i];
      ck->bodies[i].data.clear();
    }
    for (int r = 0; r < comm_->size(); ++r) ck->pieces.push_back(checkpoint_piece_relative(file, r));
  }
  // Written after the frames of this time (the output thread runs its jobs in order).
  const std::size_t keep = static_cast<std::size_t>(settings_.control.checkpoint_keep);
  output_->submit_job([ck, file, dir, keep] {
    ck->write(file);
    purge_checkpoints(dir, keep);
  });
}

template <int D>
void Solver<D>::finish_output(CheckpointWhen checkpoint) {
  if (!opt_.output) return;
  output_due(true, checkpoint);
  if (output_) output_->finish();
  for (auto& w : own_piece_writers_) w->finish();
  for (auto& f : own_functions_) f->finish();
}

template <int D>
Snapshot Solver<D>::snapshot_header() const {
  Snapshot s;
  s.time = time();
  s.step = steps_done();  // the steps that advanced the clock: the same in every run
  s.dimension = D;
  // The ledger as of the last sync with the device: flush() has just read the clock back.
  s.energy.kept = energy_ledger_;
  if (energy_ledger_)
    for (int t = 0; t < kEnergyTerms; ++t) s.energy.term[t] = host_ctl_.energy.total(t);
  s.bodies.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    s.bodies[i].material = material_names_[i];
  return s;
}

template <int D>
Snapshot Solver<D>::snapshot(bool with_grid) {
  Snapshot s = local_snapshot(with_grid);
  if (decomposed()) gather_snapshot(s);
  return s;
}

template <int D>
Snapshot Solver<D>::local_snapshot(bool with_grid, bool alone) {
  flush();
  mem::synchronize(exec_.device);
  Snapshot s = snapshot_header();
  if (energy_ledger_ && decomposed() && !alone) comm_->sum(s.energy.term, kEnergyTerms);  // the case's
  const std::vector<Real> liquid =
      !porous_ ? std::vector<Real>{} : (alone ? porous_->totals() : liquid_totals());  // over the ranks
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const std::string material = s.bodies[i].material;
    bodies_[i]->snapshot(s.bodies[i]);
    if (porous_) porous_->scalars(bodies_[i].get(), liquid, s.bodies[i].scalars);
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
RunStats Solver<D>::stats() const {
  RunStats r;
  r.steps = step_ - first_step_;
  r.last_step = step_;
  r.simulated_time = time() - run_start_;
  r.wall_seconds = wall_;
  r.output_seconds = output_wall_;
  for (auto& b : bodies_) r.bytes_per_particle = std::max(r.bytes_per_particle, b->bytes_per_particle());
  for (std::uint64_t n : body_totals_) r.particles += static_cast<std::int64_t>(n);  // over every rank
  r.nodes = global_.num_nodes();
  r.peak_device_bytes = mem::peak_bytes(exec_.device);
  r.lost_particles = host_ctl_.lost;
  r.split_steps = split_steps_;
  r.refill_steps = refill_steps_;
  r.rebalances = rebalances_;
  return r;
}

template RunStats Solver<2>::stats() const;
template RunStats Solver<3>::stats() const;
template void Solver<2>::output_due(bool, CheckpointWhen);
template void Solver<3>::output_due(bool, CheckpointWhen);
template void Solver<2>::output_ranks(const OutputSchedule::Due&, bool, const std::vector<double>&);
template void Solver<3>::output_ranks(const OutputSchedule::Due&, bool, const std::vector<double>&);
template std::vector<std::string> Solver<2>::write_pieces(const Snapshot&);
template std::vector<std::string> Solver<3>::write_pieces(const Snapshot&);
template void Solver<2>::agree_error(const std::string&);
template void Solver<3>::agree_error(const std::string&);
template void Solver<2>::write_checkpoint(const std::vector<double>&);
template void Solver<3>::write_checkpoint(const std::vector<double>&);
template void Solver<2>::finish_output(CheckpointWhen);
template void Solver<3>::finish_output(CheckpointWhen);
template Snapshot Solver<2>::snapshot_header() const;
template Snapshot Solver<3>::snapshot_header() const;
template Snapshot Solver<2>::local_snapshot(bool, bool);
template Snapshot Solver<3>::local_snapshot(bool, bool);
template Snapshot Solver<2>::snapshot(bool);
template Snapshot Solver<3>::snapshot(bool);

}  // namespace scree

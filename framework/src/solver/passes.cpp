// Solver<D>: the parameters of the particle passes and grid updates. What every pass of
// the run shares is built once, at setup (setup_passes): the physics of the case (gravity,
// the FLIP/PIC blend, the volume cap, the damping, the light-node mass: PassPhysics) and
// the kernel policy (PassPolicy). A launch adds its per-step state: its phases, the grid
// sets it reads and writes, the parity of the step it gathers from, and the split tuner's
// current choice.
#include "solver.hpp"

namespace scree {

template <int D>
void Solver<D>::setup_passes() {
  const SchemeSettings& sch = settings_.schemes;
  const DampingSettings& damping = sch.damping;
  PassPhysics<D>& ph = pass_physics_;
  ph.gravity = gravity_;
  ph.pic_fraction = sch.pic_fraction;
  ph.pic_rate = sch.pic_rate;
  ph.max_volume_ratio = sch.max_volume_ratio;
  ph.transfer = sch.transfer;
  ph.mass_eps = mass_eps_;
  ph.damping = damping.coefficient;
  ph.damping_start = damping.start_time;
  ph.damping_end = damping.end_time;

  PassPolicy& po = pass_policy_;
  po.serial = exec_.device == Device::cpu && exec_.threads == 1;
  po.reference = policy_.reference;
  // The signal speed: for the adaptive step, and for the health check of a fixed one (stopCo).
  po.need_speed = time_.adaptive() || policy_.reference || (host_ctl_.stop_co > 0 && policy_.health_checks);
  // A fixed step wants the speed for the stopCo check alone: sampled (PassPolicy::speed_mask).
  po.speed_mask = time_.adaptive() || policy_.reference ? 0u : static_cast<unsigned>(policy_.speed_every - 1);
  po.stress_blocks_per_sm = policy_.stress_blocks_per_sm;
  po.elastic_blocks_per_sm = policy_.elastic_blocks_per_sm;
  po.refill_lanes = policy_.refill_lanes;
  po.energy = energy_ledger_;
  po.ledger_light_transfer = policy_.ledger_light_transfer;
  // The walls' share on the points where the gather still sees the step's force (USF, USL;
  // MUSL re-maps momentum into the force array first): PassPolicy::wall_ledger.
  po.wall_ledger = energy_ledger_ && sch.update_scheme != UpdateScheme::MUSL && !porous_;

  GridUpdateParams<D>& gp = grid_base_;
  gp.grid = grid_;
  gp.control = ctl_.data();
  gp.walls = has_walls_ ? walls_.data() : nullptr;
  gp.masks = has_walls_ ? masks_.data() : nullptr;
  gp.mass_eps = mass_eps_;
  gp.damping = damping.coefficient;
  gp.damping_start = damping.start_time;
  gp.damping_end = damping.end_time;
  gp.energy = energy_ledger_;
  gp.energy_walls = energy_ledger_ && (sch.update_scheme == UpdateScheme::MUSL || porous_);
  gp.health = policy_.health_checks;
  gp.ledger_nodes = owned_nodes();  // the halo's nodes are updated as their owner's are, and counted by it
}

template <int D>
PassParams<D> Solver<D>::fused_pass(unsigned p2g) const {
  // Step k's first pass runs the G2P that finishes step k - 1 (from its grid set, at its
  // parity: its dt drives the gather) fused with step k's P2G into the other set, so that
  // the particles are read and written once per step. The first step after a flush has no
  // G2P pending: the pass is then the P2G alone.
  const int k = parity(), last = 1 - k;
  return pass_params((pending_ ? g2p_of(settings_.schemes.update_scheme) : 0u) | p2g, last, k, last);
}

template <int D>
PassParams<D> Solver<D>::this_step_pass(unsigned phases) const {
  return pass_params(phases, parity(), parity(), parity());
}

template <int D>
PassParams<D> Solver<D>::pass_params(unsigned flags, int gather_set, int scatter_set, int gather_parity) const {
  PassParams<D> pp;
  pp.physics = pass_physics_;
  pp.policy = pass_policy_;
  pp.flags = flags;
  pp.parity = parity();
  pp.gather_parity = gather_parity;
  pp.gather = sets_[gather_set];
  pp.scatter = sets_[scatter_set];
  pp.grid = grid_;
  pp.control = ctl_.data();
  pp.tile_stamps = policy_.sparse() ? tile_stamps_[scatter_set].data() : nullptr;
  pp.policy.split_elastic = split_;
  pp.policy.refill = refill_;
  return pp;
}

template <int D>
GridUpdateParams<D> Solver<D>::grid_params(unsigned modes, int set) const {
  GridUpdateParams<D> gp = grid_base_;
  gp.modes = modes;
  gp.parity = parity();
  gp.cur = sets_[set];
  gp.other = sets_[1 - set];
  if (policy_.sparse()) {
    gp.cur_stamps = tile_stamps_[set].data();
    gp.other_stamps = tile_stamps_[1 - set].data();
  }
  return gp;
}

template <int D>
void Solver<D>::set_stress_way(int way) {
  const bool split = way > 0 && can_split_, refill = way == 2 && can_refill_;
  if (split == split_ && refill == refill_) return;
  split_ = split;
  refill_ = refill;
  // The split's kernels clear the counters of the step after theirs (the list's length, and
  // with the updates in turns the queue's head): when they stop or change, the last step's
  // stay behind, and a later split step of that parity would re-run the points it lists
  // (their stress updated twice in one step) or start its queue past them.
  for (auto& b : bodies_) b->reset_split();
  if (graphs_) graphs_->clear();  // captured with the other way's kernels
}

template void Solver<2>::set_stress_way(int);
template void Solver<3>::set_stress_way(int);
template void Solver<2>::setup_passes();
template void Solver<3>::setup_passes();
template PassParams<2> Solver<2>::fused_pass(unsigned) const;
template PassParams<3> Solver<3>::fused_pass(unsigned) const;
template PassParams<2> Solver<2>::this_step_pass(unsigned) const;
template PassParams<3> Solver<3>::this_step_pass(unsigned) const;
template PassParams<2> Solver<2>::pass_params(unsigned, int, int, int) const;
template PassParams<3> Solver<3>::pass_params(unsigned, int, int, int) const;
template GridUpdateParams<2> Solver<2>::grid_params(unsigned, int) const;
template GridUpdateParams<3> Solver<3>::grid_params(unsigned, int) const;

}  // namespace scree

// The grid-update kernel (compiled as CUDA when the CUDA backend is on).
#include "scree/mpm/grid_update.hpp"
#include "scree/mpm/schemes.hpp"

#include <algorithm>
#include <cmath>

namespace scree {
namespace {

/// A thread's shares of the energy ledger (GridUpdateParams::energy) over the nodes it
/// updated: added to StepControl::energy once per warp (the sparse CUDA kernel) or once per
/// loop (the CPU), not once per node: every node adds to the same few addresses, and atomics
/// on one address serialise (the local damping books every node with mass).
struct LedgerShares {
  Real damping = 0, walls = 0;
};

template <int D>
struct GridUpdate {
  GridUpdateParams<D> p;

  /// The dense update: every node (tests, the reference kernels): one atomic per share.
  SCREE_HD void operator()(Index I) const {
    if ((p.modes & kAdvance) && I == 0) advance_clock(p.control, p.parity);
    LedgerShares e;
    node(I, true, (p.modes & kZeroOther) != 0, e);
    book(e);
  }

  /// Add shares to the ledger.
  SCREE_INLINE void book(const LedgerShares& e) const {
    Real* to = p.control->energy.at(warp_index());
    if (e.damping != 0) atomic_add(to + kEnergyDamping, e.damping, false);
    if (e.walls != 0) atomic_add(to + kEnergyWalls, e.walls, false);
  }

  /// The update of node I: `update` the set cur, `clear` the set other; its ledger shares
  /// added to e.
  SCREE_INLINE void node(Index I, bool update, bool clear, LedgerShares& e) const {
    if (clear) {
      // Sparse: every field, so that the set is zero outside its stamped tiles; dense:
      // what the next P2G adds to (velocities are overwritten before they are read).
      p.other.mass[I] = 0;
      for (int d = 0; d < D; ++d) {
        p.other.momentum[d][I] = 0;
        p.other.force[d][I] = 0;
        if (p.cur_stamps) {
          p.other.velocity[d][I] = 0;
          p.other.velocity_new[d][I] = 0;
        }
      }
    }
    if (!update) return;
    const StepControl* ctl = p.control;
    const int par = p.parity;
    const Real t = ctl->t[par], dt = ctl->dt[par];
    const GridFields<D>& g = p.cur;
    const Real m = g.mass[I];
    // Any node with mass gets a velocity p/m (a ratio of weighted sums, well defined);
    // only nodes heavier than mass_eps are accelerated by f/m: a node at the far edge of
    // a particle's stencil has a tiny mass but an O(1/h) share of its internal force.
    const bool has_mass = m > 0;
    const bool accelerate = m > p.mass_eps;
    const Real rm = has_mass ? 1 / m : Real(0);  // one division per node, not one per component
    const WallMask mask = p.masks ? p.masks[I] : 0;
    Real x[D] = {};
    if (mask) {
      const Vec<D> xn = p.grid.node_position(I);
      for (int d = 0; d < D; ++d) x[d] = xn[d];
    }

    if (p.modes & (kNormalize | kRemap)) {
      Real* const* src = (p.modes & kRemap) ? g.force : g.momentum;
      Real v[D];
      for (int d = 0; d < D; ++d) v[d] = has_mass ? src[d][I] * rm : Real(0);
      if (mask) {
        const bool count = p.energy_walls && (p.modes & kNormalize);
        const Real e0 = count ? kinetic(m, v) : Real(0);
        apply_walls<D>(p.walls, mask, v, x, t);
        if (count) share(I, e.walls, e0 - kinetic(m, v));
      }
      for (int d = 0; d < D; ++d) g.velocity[d][I] = v[d];
    }
    if (p.modes & kIntegrate) {
      Real v[D], v_free[D];
      const bool damp = damping_active(p.damping, t, p.damping_start, p.damping_end);
      Real probe = 0;  // health: the nodal velocity and force (report_nonfinite_node)
      for (int d = 0; d < D; ++d) {
        const Real vk = g.velocity[d][I];
        Real f = g.force[d][I];
        if (p.health) probe += vk + f;
        v_free[d] = accelerate ? vk + dt * f * rm : vk;  // without damping (the ledger's reference)
        if (damp) f = damped_force(f, vk, p.damping);
        v[d] = accelerate ? vk + dt * f * rm : vk;
      }
      if (!(probe - probe == 0)) [[unlikely]]
        report_nonfinite_node(p.control, par);
      Real v_damped[D];
      for (int d = 0; d < D; ++d) v_damped[d] = v[d];
      if (mask) apply_walls<D>(p.walls, mask, v, x, t);
      if (p.energy && (damp || mask)) {
        // The work of the damping force and of the walls' reaction over the step: impulse
        // times the step's mean velocity (v^k + v^{k+1})/2, so that with the internal force
        // they add up to the node's 1/2 m (|v^{k+1}|^2 - |v^k|^2) exactly. (The kinetic
        // energy a wall takes from v^k + dt f/m instead counted 1/2 m (dt f/m)^2 at every
        // step at the nodes a resting body stands on: a loss that never happened.)
        Real w_damp = 0, w_wall = 0;
        for (int d = 0; d < D; ++d) {
          const Real vm = Real(0.5) * (g.velocity[d][I] + v[d]);
          w_damp += m * (v_damped[d] - v_free[d]) * vm;
          w_wall += m * (v[d] - v_damped[d]) * vm;
        }
        share(I, e.damping, -w_damp);
        if (p.energy_walls) share(I, e.walls, -w_wall);
      }
      for (int d = 0; d < D; ++d) g.velocity_new[d][I] = v[d];
    }
    if (p.modes & kZeroForce)
      for (int d = 0; d < D; ++d) g.force[d][I] = 0;
  }

  /// 1/2 m |v|^2 of a node.
  SCREE_INLINE static Real kinetic(Real m, const Real* v) {
    Real v2 = 0;
    for (int d = 0; d < D; ++d) v2 += v[d] * v[d];
    return Real(0.5) * m * v2;
  }
  /// Node I's share of a term of the energy ledger (GridUpdateParams::energy), added to
  /// `to`; the shares of nodes another rank owns (ledger_nodes) are not counted.
  SCREE_INLINE void share(Index I, Real& to, Real value) const {
    if (value != 0 && p.ledger_nodes.holds(p.grid, I)) to += value;
  }

  /// The sparse update of lane `lane` of tile `t` (Tiles<D>): the node it stands for,
  /// if the tile was stamped (cur: this step; other: the previous one).
  SCREE_INLINE void tile(Index t, int lane, bool act, bool clr, LedgerShares& e) const {
    const GridGeometry<D>& g = p.grid;
    int idx[D];
    Index r = t;
    int l = lane;
    for (int d = 0; d < D; ++d) {
      const int nt = Tiles<D>::count(g.n[d], d), e = Tiles<D>::extent(d);
      idx[d] = static_cast<int>(r % nt) * e + l % e;
      r /= nt;
      l /= e;
      if (idx[d] >= g.n[d]) return;
    }
    node(g.flat(idx), act, clr, e);
  }
  /// Whether tile t is updated (act) and/or cleared in `other` (clr) in this step.
  SCREE_INLINE void tile_flags(Index t, bool& act, bool& clr) const {
    const unsigned long long k = p.control->step[p.parity];
    act = p.cur_stamps[t] == tile_stamp(k);
    clr = (p.modes & kZeroOther) && p.other_stamps && k > 0 && p.other_stamps[t] == tile_stamp(k - 1);
  }
};

#if defined(__CUDACC__)
/// Sparse update on CUDA: one block of Tiles<D>::kNodes threads per tile, the blocks
/// striding over the tiles; a tile nobody stamped costs one load.
/// Every thread of a block walks the same tiles, so the warps reach the ledger's warp sums
/// whole.
template <int D>
__global__ void __launch_bounds__(Tiles<D>::kNodes) sparse_kernel(Index tiles, GridUpdate<D> u) {
  if ((u.p.modes & kAdvance) && blockIdx.x == 0 && threadIdx.x == 0) advance_clock(u.p.control, u.p.parity);
  LedgerShares e;
  for (Index t = blockIdx.x; t < tiles; t += gridDim.x) {
    bool act, clr;
    u.tile_flags(t, act, clr);
    if (act || clr) u.tile(t, static_cast<int>(threadIdx.x), act, clr, e);
  }
  if (u.p.energy) {
    e.damping = warp_sum(e.damping);
    e.walls = warp_sum(e.walls);
    if (first_lane_of_warp()) u.book(e);
  }
}
#endif

}  // namespace

template <int D>
void grid_update(const Exec& ex, const GridUpdateParams<D>& p) {
  const GridUpdate<D> u{p};
  if (!p.cur_stamps) {
    parallel_for(ex, p.grid.num_nodes(), u);
    return;
  }
  const Index tiles = Tiles<D>::total(p.grid);
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    const unsigned blocks = static_cast<unsigned>(std::min<Index>(tiles, 2048));
    sparse_kernel<D><<<blocks, Tiles<D>::kNodes, 0, static_cast<cudaStream_t>(ex.stream)>>>(tiles, u);
    check_cuda_launch("grid_update (sparse)");
#endif
    return;
  }
  if (p.modes & kAdvance) advance_clock(p.control, p.parity);
  Real damping = 0, walls = 0;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (tiles * Tiles<D>::kNodes >= kCpuParallelMinItems) \
    num_threads(ex.threads > 0 ? ex.threads : 1) reduction(+ : damping, walls)
#endif
  for (Index t = 0; t < tiles; ++t) {
    bool act, clr;
    u.tile_flags(t, act, clr);
    if (!(act || clr)) continue;
    LedgerShares e;
    for (int lane = 0; lane < Tiles<D>::kNodes; ++lane) u.tile(t, lane, act, clr, e);
    damping += e.damping;
    walls += e.walls;
  }
  u.book({damping, walls});
}

template void grid_update<2>(const Exec&, const GridUpdateParams<2>&);
template void grid_update<3>(const Exec&, const GridUpdateParams<3>&);

}  // namespace scree

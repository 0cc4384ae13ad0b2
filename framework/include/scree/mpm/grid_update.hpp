// The grid update of the explicit MPM (Feng et al. 2025, section 2.2, step d), one kernel over
// the nodes of one grid set, for both backends:
//
//   kNormalize:  v_I^k = p_I / m_I, then the walls (wall_law.hpp)         (eq. 6)
//   kIntegrate:  a_I = (f_I + f_damp) / m_I, v_I^{k+1} = v_I^k + a_I dt, walls
//                (f_damp = -alpha |f_I| sign(v_I^k) per component: local damping)
//   kRemap:      v_I = f_I / m_I, walls (MUSL: the velocity of the updated
//                particles, whose momentum was re-mapped into the force array)
//   kZeroForce:  f_I = 0 after the integration (MUSL re-maps momentum into it)
//   kZeroOther:  clear mass, momentum and force of the other set (the next step's P2G)
//   kAdvance:    (node 0) t <- t + dt and the next dt (fixed, or CFL-adaptive), clamped
//                so that t lands on the target time
// Nodes without mass have zero velocity; nodes lighter than mass_eps keep v^{k+1} = v^k
// (no acceleration from an O(1/h) force share divided by a vanishing mass).
//
// Sparse update (cur_stamps set): only the tiles of `cur` that this step's particle passes
// stamped (Tiles<D>, grid.hpp) are updated, and kZeroOther clears every field of `other`
// on the tiles stamped in the previous step, so that a set is zero outside its stamped
// tiles. The launch has a fixed size (a CUDA graph replays it), and its work follows the
// particles. Without stamps every node is visited (tests, the reference kernels).
#pragma once

#include <cstdint>

#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/owned_nodes.hpp"
#include "scree/mpm/wall_law.hpp"

namespace scree {

enum GridModes : unsigned {
  kNormalize = 1u << 0,
  kIntegrate = 1u << 1,
  kRemap = 1u << 2,
  kZeroForce = 1u << 3,
  kZeroOther = 1u << 4,
  kAdvance = 1u << 5,
};

template <int D>
struct GridUpdateParams {
  unsigned modes = 0;
  int parity = 0;
  GridGeometry<D> grid;
  GridFields<D> cur;    ///< the set being updated
  GridFields<D> other;  ///< the set cleared by kZeroOther
  StepControl* control = nullptr;
  const Wall* walls = nullptr;     ///< the case's walls
  const WallMask* masks = nullptr;  ///< per node: the walls acting on it
  Real mass_eps = 0;
  Real damping = 0;  ///< local damping coefficient alpha
  Real damping_start = 0, damping_end = 0;
  const std::uint32_t* cur_stamps = nullptr;    ///< tile stamps of `cur` (sparse update); null: all nodes
  const std::uint32_t* other_stamps = nullptr;  ///< tile stamps of `other` (sparse kZeroOther)
  /// Keep the energy ledger (StepControl::energy): the energy the local damping and the
  /// walls take from the nodes: at kNormalize the kinetic energy a wall removes from v^k,
  /// 1/2 m (|v_after|^2 - |v_before|^2); at kIntegrate the work of the damping force and of
  /// the walls' reaction, impulse times (v^k + v^{k+1})/2 (kRemap's walls act on a velocity
  /// that carries no kinetic energy of its own); one atomic add per node where not zero.
  bool energy = false;
  /// With `energy`: whether the walls' share is measured here (MUSL) or on the points
  /// (USF, USL: PassPolicy::wall_ledger).
  bool energy_walls = false;
  /// With `energy`: the nodes the ledger counts (a decomposed run: those this rank owns; its
  /// halo nodes hold the same sums as their owner's and are updated alike).
  OwnedNodes<D> ledger_nodes;
  /// Probe the nodal velocity and force for non-finite values (report_nonfinite_node):
  /// KernelPolicy::health_checks; off only to measure the probe's cost.
  bool health = true;
};

/// Run the grid update on `ex`'s backend (defined in the core, instantiated for D = 2, 3).
template <int D>
SCREE_API void grid_update(const Exec& ex, const GridUpdateParams<D>& p);

}  // namespace scree

// The rigid-wall law that the grid update applies to nodal velocities, fused into its
// kernel (no launch of its own, no host round trip: a gate opens at its time even inside
// a CUDA graph).
//
// A wall moves rigidly, v_w(x) = velocity + omega x (x - centre), and acts on the nodes
// its boundary condition selects, over a time window. Relative to the wall, the node's
// velocity v_r = v - v_w is
//   stick:    set to zero (no-slip; a prescribed velocity; a rotating drum)
//   contact:  stripped of its normal part v_r.n n (always, or only while the node
//             approaches the wall, v_r.n < 0, when `separable`), and its tangential part
//             reduced by mu |v_r.n|, not past zero: Coulomb friction against a rigid wall
//             (Bardenhagen, Brackbill & Sulsky 2000); mu = 0 is a frictionless roller.
// The boundary plugins fixed, slip, friction and rotatingWall are walls of this one law
// with their own parameters; a plugin may add a wall of any motion and friction without
// touching the core. A node law outside this family is a plugin's own kernel
// (boundary/node_law.hpp).
//
// A case has at most kMaxWalls walls; a bit mask per node says which act on it.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"

namespace scree {

inline constexpr int kMaxWalls = 32;
using WallMask = std::uint32_t;

/// Contact of a node moving at v (D components, relative to the surface) with a rigid
/// surface of unit normal n pointing into the material: the normal part v.n n is removed
/// (always, or only while the node approaches, v.n < 0, when `separable`), and the
/// tangential part reduced by mu |v.n|, not past zero (Coulomb friction; Bardenhagen,
/// Brackbill & Sulsky 2000). mu = 0 is a frictionless roller.
template <int D>
SCREE_INLINE void coulomb_contact(Real* v, const Real* n, Real mu, bool separable) {
  Real vn = 0;
  for (int d = 0; d < D; ++d) vn += v[d] * n[d];
  if (separable && vn >= 0) return;  // moving away from a separable surface: free
  if (mu == 0) {
    for (int d = 0; d < D; ++d) v[d] -= vn * n[d];
    return;
  }
  Real vt[3], vt2 = 0;
  for (int d = 0; d < D; ++d) {
    vt[d] = v[d] - vn * n[d];
    vt2 += vt[d] * vt[d];
  }
  const Real vtn = sqrt(vt2);
  const Real scale = vtn > 0 ? fmax(Real(0), vtn - mu * fabs(vn)) / vtn : Real(0);
  for (int d = 0; d < D; ++d) v[d] = vt[d] * scale;
}

struct Wall {
  enum class Mode : int { stick = 0, contact = 1 };
  Mode mode = Mode::stick;
  Real normal[3] = {0, 0, 0};    ///< contact: unit normal pointing into the material
  Real mu = 0;                   ///< contact: Coulomb friction coefficient (0: frictionless)
  int separable = 0;             ///< contact: the material may leave the wall
  Real velocity[3] = {0, 0, 0};  ///< translation of the wall [m/s]
  int rotating = 0;              ///< the wall also rotates with omega about centre
  Real omega[3] = {0, 0, 0};     ///< angular velocity (2D uses omega[2]) [rad/s]
  Real centre[3] = {0, 0, 0};    ///< centre of rotation [m]
  Real t_start = -1e300;         ///< active for t_start <= t < t_end [s]
  Real t_end = 1e300;
  int drained = 0;               ///< two-phase: the pore liquid crosses the wall (else it obeys it too)

  /// The wall's velocity w (D components) at the node position x.
  template <int D>
  SCREE_INLINE void wall_velocity(Real* w, const Real* x) const {
    if (!rotating) {
      for (int d = 0; d < D; ++d) w[d] = velocity[d];
      return;
    }
    Real r[3] = {0, 0, 0};
    for (int d = 0; d < D; ++d) r[d] = x[d] - centre[d];
    const Real c[3] = {omega[1] * r[2] - omega[2] * r[1], omega[2] * r[0] - omega[0] * r[2],
                       omega[0] * r[1] - omega[1] * r[0]};
    for (int d = 0; d < D; ++d) w[d] = velocity[d] == 0 ? c[d] : c[d] + velocity[d];
  }

  /// Apply to the velocity v (D components) of the node at position x, at time t.
  template <int D>
  SCREE_INLINE void apply(Real* v, const Real* x, Real t) const {
    if (t < t_start || t >= t_end) return;
    if (mode == Mode::stick) {
      wall_velocity<D>(v, x);
      return;
    }
    // Contact with a wall at rest works on v itself; a moving wall on v - v_w.
    const bool moves = rotating || velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0;
    Real w[3] = {0, 0, 0};
    if (moves) {
      wall_velocity<D>(w, x);
      for (int d = 0; d < D; ++d) v[d] -= w[d];
    }
    coulomb_contact<D>(v, normal, mu, separable != 0);
    if (moves)
      for (int d = 0; d < D; ++d) v[d] += w[d];
  }
};

/// The index of the lowest set bit of a non-zero mask (walls, open surfaces per node).
SCREE_INLINE int lowest_bit(std::uint32_t mask) {
#if defined(__CUDA_ARCH__)
  return __ffs(static_cast<int>(mask)) - 1;
#else
  return __builtin_ctz(mask);
#endif
}

/// Apply every wall whose bit is set in `mask`, in index order.
template <int D>
SCREE_INLINE void apply_walls(const Wall* table, WallMask mask, Real* v, const Real* x, Real t) {
  for (; mask; mask &= mask - 1) table[lowest_bit(mask)].template apply<D>(v, x, t);
}

}  // namespace scree

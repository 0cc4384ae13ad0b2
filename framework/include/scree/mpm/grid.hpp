// The background grid: a uniform box of nodes, and views of its fields for kernels.
//
// Node (i, j[, k]) sits at origin + h (i, j[, k]). The user's domain box [lower, upper]
// is padded by `ghost` layers of nodes on every side so that the widest stencil
// (3 nodes: B-spline, GIMP) of a particle inside the domain stays on the grid; walls
// are boundary conditions on the domain faces, applied to the face nodes and the ghost
// nodes beyond them. The box may later be a sub-box of a larger one (domain
// decomposition): `offset` is its first node's index in the global lattice.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/time/step_control.hpp"
#include "scree/core/tensor.hpp"

namespace scree {

template <int D>
struct GridGeometry {
  Vec<D> origin;  ///< position of node 0 [m]
  Real h;         ///< cell size [m]
  int n[D];       ///< nodes per axis (ghosts included)
  int ghost;      ///< ghost node layers outside the domain on each side
  Vec<D> lower;   ///< the domain box the user gave [m]
  Vec<D> upper;
  int offset[D];  ///< index of node 0 in the global lattice (0 for a single box)

  SCREE_INLINE Index num_nodes() const {
    Index s = 1;
    for (int d = 0; d < D; ++d) s *= n[d];
    return s;
  }
  SCREE_INLINE Index stride(int d) const {
    Index s = 1;
    for (int e = 0; e < d; ++e) s *= n[e];
    return s;
  }
  /// Flat index of node (idx[0], idx[1], ...), x fastest.
  SCREE_INLINE Index flat(const int* idx) const {
    Index f = 0, s = 1;
    for (int d = 0; d < D; ++d) {
      f += idx[d] * s;
      s *= n[d];
    }
    return f;
  }
  SCREE_INLINE void unflat(Index f, int* idx) const {
    for (int d = 0; d < D; ++d) {
      idx[d] = static_cast<int>(f % n[d]);
      f /= n[d];
    }
  }
  SCREE_INLINE Vec<D> node_position(Index f) const {
    int idx[D];
    unflat(f, idx);
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + h * idx[d];
    return x;
  }
  SCREE_INLINE Real cell_volume() const {
    Real v = 1;
    for (int d = 0; d < D; ++d) v *= h;
    return v;
  }
};

/// One set of grid fields (device pointers). Two sets alternate between steps so that
/// the G2P of one step and the P2G of the next run in one particle pass.
template <int D>
struct GridFields {
  Real* mass;             ///< nodal mass m_I [kg]
  Real* momentum[D];      ///< sum N m_p v_p [kg m/s] (P2G); reused for MUSL's second P2G
  Real* force[D];         ///< internal + external force [N]
  Real* velocity[D];      ///< v^k = momentum/mass after boundary conditions [m/s]
                          ///< (MUSL: the velocity re-mapped from updated particle velocities)
  Real* velocity_new[D];  ///< v^{k+1} = v^k + dt f/m after boundary conditions [m/s]
};

/// Sparse grid updates: the nodes are grouped in tiles of kTileNodes (32 along x, a warp's
/// coalesced row of doubles, by 4 along y in 2D, by 2 x 2 in 3D). A particle pass that
/// scatters into a grid set stamps the tiles its stencils touch with the step's stamp
/// (tile_stamp), and the grid update visits only tiles stamped in this step (and clears
/// those of the other set stamped in the last step), so its work follows the particles
/// rather than the size of the box (a flume's grid is mostly empty). Outside its stamped
/// tiles every field of a set is zero.
template <int D>
struct Tiles {
  static constexpr int kX = 32;
  static constexpr int kY = D == 2 ? 4 : 2;
  static constexpr int kZ = D == 3 ? 2 : 1;
  static constexpr int kNodes = kX * kY * kZ;
  static constexpr int extent(int d) { return d == 0 ? kX : (d == 1 ? kY : kZ); }
  /// Tiles along axis d of a grid with n nodes along it.
  SCREE_INLINE static int count(int n, int d) { return (n + extent(d) - 1) / extent(d); }
  SCREE_INLINE static Index total(const GridGeometry<D>& g) {
    Index t = 1;
    for (int d = 0; d < D; ++d) t *= count(g.n[d], d);
    return t;
  }
  /// Tile of node (idx[0], idx[1], ...).
  SCREE_INLINE static Index of(const GridGeometry<D>& g, const int* idx) {
    Index t = 0, s = 1;
    for (int d = 0; d < D; ++d) {
      t += (idx[d] / extent(d)) * s;
      s *= count(g.n[d], d);
    }
    return t;
  }
};

/// The stamp a grid set's tiles get in step k (0: never touched).
SCREE_INLINE std::uint32_t tile_stamp(unsigned long long step) { return static_cast<std::uint32_t>(step) + 1u; }

}  // namespace scree

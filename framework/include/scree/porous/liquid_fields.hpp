// The pore liquid's state of a two-phase body (porous/two_phase.hpp): its columns on the
// points, its constants, and its nodal fields on the grid.
//
// Per point (extra columns, PoreColumn): p_w (compression positive) [Pa], S_l, n, suction,
// v_l, seepage velocity w = n S_l (v_l - v_s), and where rain falls, the rain the surface in
// the point's reach does not take and for how long it has not, the ponded water the point
// carries and the pond's depth over the surface in its reach.
// Per node (LiquidFields): M_l = sum N rho_l V, M_lm = sum N n S_l rho_l V (the liquid's
// mass in the mixture), liquid momentum sum N rho_l V v_l, liquid force F_l, drag
// coefficient Q, liquid velocities, the surface's share sum V grad N (its normal), the rain
// a surface node does not take, the pond it holds, and the points per cell.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/porous/hydraulic_model.hpp"

namespace scree {

/// The extra columns of a two-phase body's points, in order (BodySetup::extra).
enum PoreColumn : int { kPorePressure = 0, kSaturation = 1, kPorosity = 2, kSuction = 3, kLiquidVelocity = 4 };
/// Column of the seepage velocity's first component.
template <int D>
inline constexpr int kSeepage = kLiquidVelocity + D;
/// Column of the rain not taken at the surface nodes in the point's reach [m/s], and of
/// how long they have not taken all of it [s] (PoreRate).
template <int D>
inline constexpr int kRainNotTaken = kLiquidVelocity + 2 * D;
template <int D>
inline constexpr int kPondingDuration = kRainNotTaken<D> + 1;
/// Column of the ponded water the point carries [kg; kg/m in 2D]: the points near the surface
/// carry the surface's pond between steps (boundary/rainfall: scattered onto the surface
/// nodes, gathered back after the rain's node law), and of the pond's depth over the surface
/// in the point's reach [m].
template <int D>
inline constexpr int kPond = kPondingDuration<D> + 1;
template <int D>
inline constexpr int kPondDepth = kPond<D> + 1;
template <int D>
inline constexpr int kPoreColumns = kPondDepth<D> + 1;

/// The constants of a two-phase body.
struct PoreParams {
  Real n0 = 0.3;          ///< initial porosity [-]
  Real rho_l = 1000;      ///< liquid density [kg/m^3]
  Real bulk_l = 2e9;      ///< liquid bulk modulus K_l [Pa]
  Real viscosity = 1e-3;  ///< dynamic viscosity mu_l [Pa s]
  Real kappa = 1e-12;     ///< intrinsic permeability [m^2]
  HydraulicTable table;

  /// The liquid's storage C = n S_l / K_l + n dS_l/dp [1/Pa] at porosity n, saturation S
  /// and pore pressure p: (C) dp/dt = -(S_l div v_s + div q) (the mass balance,
  /// porous/two_phase.hpp).
  SCREE_INLINE Real storage(Real n, Real S, Real p) const { return n * S / bulk_l + n * table.dsaturation_dp(p); }
};

/// One set of the liquid's nodal fields (two sets alternate, as the solid's).
template <int D>
struct LiquidFields {
  Real* mass;             ///< M_l = sum N rho_l V [kg]
  Real* mass_mix;         ///< M_lm = sum N n S_l rho_l V [kg]
  Real* momentum[D];      ///< sum N rho_l V v_l [kg m/s]
  Real* force[D];         ///< F_l [N]
  Real* drag;             ///< sum N V n S_l mu_l / kappa [kg/s]: Q at k_rel = 1 (see drag_per_mass)
  Real* conductance;      ///< sum N V k_rel [m^3]; over `volume`: the node's mean k_rel
  Real* velocity_new[D];  ///< v_l^{k+1} [m/s]
  Real* area[D];          ///< sum V grad N [m^2 per unit thickness], at every node: at a surface node its
                          ///< share of the surface, int N n dGamma; elsewhere the quadrature's error (PoreRate)
  Real* pressure;         ///< sum N V p_w [Pa m^3]; over `volume`: the nodal pore pressure
  Real* volume;           ///< sum N V [m^3] (see drag_per_mass)
  Real* not_taken;        ///< rain a surface node does not take, per unit horizontal area [m/s]:
                          ///< written by the rainfall condition where the surface ponds, else 0
  Real* pond;             ///< ponded water on a surface node [kg; kg/m in 2D]: scattered from the
                          ///< points (SurfaceScatter), updated by the rain's node law, gathered back
                          ///< (PoreRate)
};

/// A node's sum N V [m^3] and drag at k_rel = 1 [kg/s] (LiquidFields::volume, drag), from
/// the scattered sums or, with PorePassParams::drag_per_mass > 0, from M_l and M_lm.
template <int D>
SCREE_INLINE Real nodal_volume(const LiquidFields<D>& f, Index I, Real drag_per_mass, Real rho_l) {
  return drag_per_mass > 0 ? f.mass[I] / rho_l : f.volume[I];
}
template <int D>
SCREE_INLINE Real nodal_drag(const LiquidFields<D>& f, Index I, Real drag_per_mass) {
  return drag_per_mass > 0 ? f.mass_mix[I] * drag_per_mass : f.drag[I];
}
template <int D>
inline constexpr int kLiquidFieldCount = 8 + 4 * D;

/// Node I's share of the surface seen from above, a_I . up [m per unit thickness in 2D; m^2
/// in 3D], `up` the unit vector against gravity: the level area a pond on the node covers
/// (its depth is P_I / (rho_l a_I . up)); 0 or less where the surface does not face up.
template <int D>
SCREE_INLINE Real level_share(const LiquidFields<D>& f, Index I, const Real* up) {
  Real l = 0;
  for (int d = 0; d < D; ++d) l += f.area[d][I] * up[d];
  return l;
}

/// The cell of the grid that holds x (cell (i, j) indexed as node (i, j), strides of the
/// node counts): the points-per-cell counts and the liquid mass balance use it.
/// With `ci`, also the cell's integer coordinates (its lower corner is origin + ci h).
template <int D>
SCREE_INLINE Index cell_of(const GridGeometry<D>& grid, const Vec<D>& x, int* ci = nullptr) {
  Index cell = 0, stride = 1;
  for (int d = 0; d < D; ++d) {
    const int c = static_cast<int>(floor((x[d] - grid.origin[d]) / grid.h));
    if (ci) ci[d] = c;
    cell += static_cast<Index>(c) * stride;
    stride *= grid.n[d];
  }
  return cell;
}

}  // namespace scree

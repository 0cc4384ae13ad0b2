// What the pore liquid's passes over a two-phase body's points share (porous/pore_gather.hpp,
// porous/pore_scatter.hpp): their parameters beyond the solid pass's, and their base.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/mpm/particle_pass.hpp"
#include "scree/porous/hydraulic_condition.hpp"
#include "scree/porous/liquid_fields.hpp"

namespace scree {

/// What the pore passes need beyond the solid pass's parameters.
template <int D>
struct PorePassParams {
  PoreParams pore;
  LiquidFields<D> gather;   ///< the liquid set read (the last step's)
  LiquidFields<D> scatter;  ///< the liquid set written (this step's)
  Real* cells = nullptr;    ///< points per cell (this step's), for the surface nodes
  std::uint8_t* surface = nullptr;  ///< per node: 1 on a surface of the points (SurfaceMask)
  Real* extra = nullptr;    ///< the body's extra columns (PoreColumn order)
  int n_laws = 0;
  PorePressureLaw laws[kMaxPorePressureLaws];
  int vertical = 1;         ///< the axis opposite to gravity
  Real g = 0;               ///< |g| [m/s^2]
  /// The liquid mass balance per cell (PoreRate, PorePressure): sum V r_p [m^3/s] and
  /// sum V C_p [m^3/Pa] over the cell's points; not alternating: the grid update clears them.
  Real* inflow = nullptr;
  Real* capacity = nullptr;
  /// Per cell, sum V C p [m^3] then sum V C x_d [m^4/Pa] for each axis d, n_cells apart.
  Real* moments = nullptr;
  /// Per cell after CellPressure: the new mean pressure P_c [Pa], then the centroid x_c
  /// [m] and the slope g_c [Pa/m] per axis, n_cells apart (1 + 2 D of them).
  Real* cell_pressure = nullptr;
  Index n_cells = 0;
  /// Every two-phase body of the case has the same rho_l and mu_l / kappa (the common case,
  /// one soil and water): the nodal drag at k_rel = 1 is then Q_I = M_lm,I mu_l / (kappa
  /// rho_l) and sum N V = M_l,I / rho_l, so neither is scattered (two of the eleven nodal sums
  /// per node in 2D). This factor mu_l / (kappa rho_l) [1/s], or 0 when the bodies differ:
  /// both are then scattered (LiquidFields::drag, volume).
  Real drag_per_mass = 0;
  /// Cumulative liquid mass [kg] since t = 0: [0] through the surfaces (SurfaceInflow),
  /// [1] added by the prescribed pore pressures. Null: not counted.
  Real* totals = nullptr;
  /// A condition keeps a pond (HydraulicCondition::keeps_a_pond): the points carry it
  /// (SurfaceScatter, PoreRate); the water that leaves it is added to totals[4].
  bool ponds = false;
  /// Per node, the open surfaces selecting it (TwoPhaseGridUpdate::open_masks), and those of
  /// the conditions that keep a pond: a pond stands only on their nodes.
  const std::uint32_t* open_masks = nullptr;
  std::uint32_t pond_bits = 0;
  Real up[3] = {};  ///< the unit vector against gravity (0 without gravity): a pond lies level
};

/// What every pass over a two-phase body's points holds: the solid pass's parameters (grid,
/// sets, control, PIC fraction), the liquid's, the body's arrays and the shape functions.
template <int D, class Shape>
struct PorePass {
  PassParams<D> pp;
  PorePassParams<D> lp;
  ParticleArrays<D> pa;
  Shape shape;
  /// Column c (PoreColumn order) of point p.
  SCREE_INLINE Real& col(int c, Index p) const { return lp.extra[static_cast<std::size_t>(c) * pa.n + p]; }
  /// The volume of point p at x^k from the porosity n the last scatter wrote:
  /// J = (1 - n0) / (1 - n).
  SCREE_INLINE Real volume_at(Index p, Real n) const { return pa.volume0[p] * (1 - lp.pore.n0) / (1 - n); }
};

}  // namespace scree

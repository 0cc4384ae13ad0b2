// Hydraulic conditions: what acts on the pore liquid of the two-phase bodies
// (porous/two_phase.hpp), at its points of the step:
//
//   pore pressures  constrain_pores(): a prescribed p_w on the points of a region, after each
//                   step's pore-pressure update (a water table, a drained layer: porePressure);
//   open surfaces   open_surfaces(): stretches of the surface where the liquid has the weak
//                   form's natural condition p_w = 0 (ponding, rain, a seepage face); a
//                   two-phase body's surface is closed elsewhere;
//   node laws       apply_hydraulic(): a kernel on both phases' nodal velocities after the
//                   two-phase grid update (rainfall).
//
// A boundary-condition plugin that acts on the liquid implements HydraulicCondition beside
// BoundaryCondition (boundary/boundary_condition.hpp), whose walls and node laws are the
// solid's:
//
//   class MyDrain final : public BoundaryCondition, public HydraulicCondition { ... };
//
// The solver finds these conditions among the case's boundary conditions by dynamic_cast
// and hands them to the porous media; in a case without a two-phase body it rejects them.
#pragma once

#include <functional>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/owned_nodes.hpp"
#include "scree/mpm/wall_law.hpp"
#include "scree/porous/liquid_fields.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

/// A prescribed pore pressure on the points inside a box (porePressure condition):
/// p_w = value, or hydrostatic below the level z_w along -g, p_w = rho_l |g| (z_w - z)
/// (negative above it: the suction of a hydrostatic profile).
struct PorePressureLaw {
  Real lo[3] = {-kUnbounded, -kUnbounded, -kUnbounded}, hi[3] = {kUnbounded, kUnbounded, kUnbounded};
  Real value = 0;
  int hydrostatic = 0;
  Real level = 0;  ///< z_w along the vertical (the axis opposite to g) [m]
  Real t_start = -kUnbounded, t_end = kUnbounded;
};
inline constexpr int kMaxPorePressureLaws = 8;

/// A stretch of a two-phase body's surface that a hydraulic condition opens (ponding, rain).
struct OpenSurface {
  std::function<bool(const Real* x)> select;  ///< the surface nodes it opens, by position
  Real t_start = -kUnbounded, t_end = kUnbounded;
  /// A seepage face: open only where the soil behind it is not in suction (nodal p_w >= 0),
  /// so that the liquid may leave but not enter; closed elsewhere.
  bool outflow_only = false;
};

/// What a hydraulic node law (the rainfall condition) sees after the two-phase grid
/// update: both phases' fields of the set just updated, and the points per cell.
template <int D>
struct TwoPhaseNodes {
  GridGeometry<D> grid;
  GridFields<D> solid;
  LiquidFields<D> liquid;
  const Real* cells = nullptr;  ///< points per cell (cell (i, j) at i + j n_x, n the node counts)
  const Wall* walls = nullptr;   ///< the case's walls and, per node, which act on the solid
  const WallMask* masks = nullptr;
  const StepControl* control = nullptr;
  int parity = 0;
  Real mass_eps = 0;
  /// The case's liquid totals [kg] (per metre in 2D), summed with atomic_add(.., serial):
  /// [2] the rain offered to the surface nodes under rain, rho_l |w . a_I| dt where the rain
  /// falls onto the node's share of the surface a_I; [3] of it, what the surface did not take
  /// (ponded or run off): offered less the node's inflow, as SurfaceInflow counts it (less
  /// than 0 where the surface takes a pond's water); [4] the ponded water that ran off
  /// (beyond the pond's depth, or where the surface it stood on went away): the pond holds
  /// [3] - [4].
  Real* totals = nullptr;
  /// The nodes whose shares the totals count (a decomposed run: this rank's own).
  OwnedNodes<D> owned;
  bool serial = false;
  Real drag_per_mass = 0, rho_l = 0;  ///< as TwoPhaseGridUpdate's (nodal_volume)
  Real up[D] = {};  ///< the unit vector against gravity (0 without gravity): a pond lies level
};

class SCREE_API HydraulicCondition {
 public:
  virtual ~HydraulicCondition();
  /// Prescribed pore pressures on points (the water table, ponding, a drained layer):
  /// applied after each step's pore-pressure update.
  virtual void constrain_pores(std::vector<PorePressureLaw>& laws) const { (void)laws; }
  /// Stretches of surface the condition opens (the liquid's natural condition p_w = 0 there:
  /// ponding, rain); a two-phase body's surface is closed elsewhere.
  virtual void open_surfaces(std::vector<OpenSurface>& out) const { (void)out; }
  /// Whether the node law keeps water on the surface from step to step (a pond: the points
  /// near the surface then carry it, LiquidFields::pond); a case's pond is scattered and
  /// gathered only when one of its conditions keeps one (on the nodes of its open surfaces).
  virtual bool keeps_a_pond() const { return false; }
  /// Whether apply_hydraulic() runs a law on both phases' nodal velocities after the
  /// two-phase grid update (rainfall).
  virtual bool has_hydraulic_law() const { return false; }
  /// The law: queue a kernel on `ex` (its stream) over the nodes it acts on.
  virtual void apply_hydraulic(const Exec& ex, const TwoPhaseNodes<2>& g) const {
    (void)ex;
    (void)g;
  }
  virtual void apply_hydraulic(const Exec& ex, const TwoPhaseNodes<3>& g) const {
    (void)ex;
    (void)g;
  }
};

}  // namespace scree

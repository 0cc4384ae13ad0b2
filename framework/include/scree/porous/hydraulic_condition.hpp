// What the hydraulic conditions (rainfall, ponding, seepageFace, porePressure) hand the
// two-phase formulation (porous/two_phase.hpp): prescribed pore pressures, and what a node
// law on the liquid sees after the two-phase grid update.
#pragma once

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
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
};

}  // namespace scree

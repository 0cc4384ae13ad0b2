// The two-phase formulation's grid update (porous/two_phase.hpp): both phases' nodal
// velocities with the drag integrated implicitly, the walls and the surface's condition,
// then the liquid that entered through the surface.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/owned_nodes.hpp"
#include "scree/mpm/schemes.hpp"
#include "scree/mpm/wall_law.hpp"
#include "scree/porous/free_surface.hpp"
#include "scree/porous/liquid_fields.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

/// The grid update of the two-phase formulation, per node, for the USL scheme: nodal
/// velocities of both phases with the walls, then both phases' v^{k+1} with the drag
/// implicit (a closed-form 2 x 2 solve per component), the walls again, and the other
/// sets cleared; node 0 advances the clock.
template <int D>
struct TwoPhaseGridUpdate {
  GridGeometry<D> grid;
  GridFields<D> solid, solid_other;
  LiquidFields<D> liquid, liquid_other;
  Real* cells_other = nullptr;  ///< the other parity's cell counts (cleared)
  Real* inflow = nullptr;       ///< the liquid mass balance per cell (PorePassParams; cleared)
  Real* capacity = nullptr;
  Real* moments = nullptr;      ///< (1 + D) n_cells of them
  Index n_cells = 0;
  StepControl* control = nullptr;
  int parity = 0;
  const Wall* walls = nullptr;
  const WallMask* masks = nullptr;
  const WallMask* liquid_masks = nullptr;  ///< the walls the liquid cannot cross
  const Real* cells = nullptr;             ///< this step's points per cell (surface nodes)
  /// This step's SurfaceMask: a superset of the surface nodes below (the same test without
  /// the walls), so that surface_node's cells are read only where the mask says so.
  const std::uint8_t* surface = nullptr;
  const std::uint32_t* open_masks = nullptr;  ///< per node: the open surfaces selecting it
  OpenSurfaceWindow open[kMaxOpenSurfaces];   ///< their time windows
  Real mass_eps = 0;
  Real damping = 0, damping_start = 0, damping_end = 0;
  Real drag_per_mass = 0, rho_l = 0;  ///< PorePassParams::drag_per_mass and the bodies' rho_l
  bool ponds = false;  ///< PorePassParams::ponds: the pond's surface is open, its weight a load
  Real g = 0;          ///< |g| [m/s^2]
  Real up[D] = {};     ///< the unit vector against gravity

  SCREE_HD void operator()(Index I) const {
    if (I == 0) advance_clock(control, parity);
    if (I < n_cells && cells_other) cells_other[I] = 0;
    if (inflow && I < n_cells) {
      inflow[I] = 0;
      capacity[I] = 0;
      for (int d = 0; d <= D; ++d) moments[d * n_cells + I] = 0;
    }
    const Real t = control->t[parity], dt = control->dt[parity];
    const Real ms = solid.mass[I], ml = liquid.mass[I], mlm = liquid.mass_mix[I];
    Real x[D] = {};
    const WallMask mask = masks ? masks[I] : 0, lmask = liquid_masks ? liquid_masks[I] : 0;
    if (mask | lmask) {
      const Vec<D> xn = grid.node_position(I);
      for (int d = 0; d < D; ++d) x[d] = xn[d];
    }
    Real vs[D], vl[D];
    for (int d = 0; d < D; ++d) {
      vs[d] = ms > 0 ? solid.momentum[d][I] / ms : Real(0);
      vl[d] = ml > 0 ? liquid.momentum[d][I] / ml : Real(0);
    }
    if (mask) apply_walls<D>(walls, mask, vs, x, t);
    if (lmask) apply_walls<D>(walls, lmask, vl, x, t);
    for (int d = 0; d < D; ++d) {
      solid.velocity[d][I] = vs[d];  // the solid pass's FLIP increment reads it (PoreRate: M_l v_l / M_l)
    }
    Real ws[D], wl[D], fls[D];
    const bool damp = damping_active(damping, t, damping_start, damping_end);
    // The liquid's boundary term. The weak form of -grad p_w on the points' domain carries
    // -int N p_b n dGamma; left out, it makes every surface p_b = 0: open, the liquid enters
    // or leaves as the pore pressure drives it (ponding, a drained face). A surface is closed
    // unless a condition opens it: there p_b is the nodal pore pressure itself, with
    // int N n dGamma = sum V grad N (the divergence theorem), so that no flow is driven
    // through it (the rainfall and ponding conditions open theirs). A closed node's seepage
    // along the normal is then also set to zero after the integration.
    Real boundary[D] = {};
    bool closed = false;  // a closed surface node: no seepage through it (below)
    bool inflow_face = false;  // an open surface node where the liquid flows in
    bool outflow_only = false; // open as a seepage face only: closed again if the liquid would enter
    Real exposed[D] = {};  // a node on the surface by its exposure alone: the exposure (surface_node)
    Real load[D] = {};     // a pond's weight on the surface: on both phases (below)
    if (cells && ml > 0 && surface[I] && surface_node<D>(grid, cells, I, walls, mask, t, true, kSurfaceExposure, exposed)) {
      bool is_open = (mask & ~lmask) != 0;  // on a drained wall
      bool seepage = false;                 // open as a seepage face
      bool by_exposure = false;
      for (int d = 0; d < D; ++d) by_exposure = by_exposure || exposed[d] != 0;
      // A node on the surface by its exposure alone has the open surfaces of its neighbours
      // towards the surface (exposed_open_masks).
      const std::uint32_t opened = by_exposure ? exposed_open_masks<D>(grid, open_masks, I, exposed)
                                               : (open_masks ? open_masks[I] : 0u);
      // Water standing on the node (a pond the rain left, boundary/rainfall) keeps the surface
      // of the conditions that select it open after their time window: the pond drains into
      // the soil as the soil takes it. Its weight is the surface's load, p_b = rho_l g d with
      // d = P_I / (rho_l a_I . up) the pond's depth, on the liquid and on the mixture alike:
      // -p_b a_I (the boundary term int N p_b n dGamma of both momentum equations).
      const Real pond = ponds ? liquid.pond[I] : Real(0);
      if (pond > 0) {
        const Real level = level_share<D>(liquid, I, up);
        if (level > 0)
          for (int d = 0; d < D; ++d) load[d] = -g * pond / level * liquid.area[d][I];
      }
      for (std::uint32_t m = opened; m; m &= m - 1) {
        const int b = lowest_bit(m);
        if ((t < open[b].t_start || t >= open[b].t_end) && !(pond > 0 && !open[b].outflow_only)) continue;
        if (!open[b].outflow_only)
          is_open = true;
        else
          seepage = seepage || liquid.pressure[I] >= 0;
      }
      outflow_only = seepage && !is_open;
      is_open = is_open || seepage;
      const Real vol = nodal_volume<D>(liquid, I, drag_per_mass, rho_l);
      closed = !is_open;
      if (!is_open && vol > 0) {
        const Real pb = liquid.pressure[I] / vol;
        for (int d = 0; d < D; ++d) boundary[d] = -pb * liquid.area[d][I];
      }
      // Upstream weighting at an open surface: where the soil is in suction (nodal p_w < 0)
      // the liquid flows in from the boundary, at p_b = 0, S_l = S_max and k_rel = 1, and the
      // node's conductivity is the boundary's (as a finite-volume Richards solver weights its
      // boundary face upstream; Forsyth, Wu & Pruess 1995 show that dry soil needs it). The
      // points' mean alone would be the dry soil's: a dry surface under rain or a pond would
      // take in K_sat k_rel(S_dry) grad p, orders below what it takes (the water would wait
      // for the top cell's points to wet through that small conductance first).
      inflow_face = is_open && !outflow_only && vol > 0 && liquid.pressure[I] < 0;
    }
    // The drag coefficient with the node's mean relative permeability (the liquid momentum,
    // porous/two_phase.hpp).
    const Real volI = nodal_volume<D>(liquid, I, drag_per_mass, rho_l);
    const Real kI = inflow_face ? Real(1) : (volI > 0 ? liquid.conductance[I] / volI : Real(1));
    const Real Q = nodal_drag<D>(liquid, I, drag_per_mass) / (kI > Real(1e-300) ? kI : Real(1e-300));
    Real probe = 0;  // health: both phases' nodal velocities and forces (report_nonfinite_node)
    for (int d = 0; d < D; ++d) {
      Real fm = solid.force[d][I] + load[d], fl = liquid.force[d][I] + boundary[d] + load[d];
      probe += vs[d] + vl[d] + fm + fl;
      fls[d] = 0;
      if (damp) {
        fm = damped_force(fm, vs[d], damping);
        fl = damped_force(fl, vl[d], damping);
      }
      ws[d] = vs[d];
      wl[d] = vl[d];
      fls[d] = fl;
      if (!(ms > mass_eps)) continue;
      if (ml > 0) {
        // M_l dl = dt [F_l - Q (v_l + dl - v_s - ds)],  M_s ds = dt F_mix - M_lm dl
        const Real dl = dt * (fl - Q * (vl[d] - vs[d]) + dt * Q * fm / ms) / (ml + dt * Q * (1 + mlm / ms));
        wl[d] = vl[d] + dl;
        ws[d] = vs[d] + (dt * fm - mlm * dl) / ms;
      } else {
        ws[d] = vs[d] + dt * fm / ms;
      }
    }
    if (!(probe - probe == 0)) [[unlikely]]
      report_nonfinite_node(control, parity);
    if (mask) {
      apply_walls<D>(walls, mask, ws, x, t);
      // A wall held the solid: its reaction is not in F_mix, so the coupled solve dragged the
      // liquid along with a solid motion that did not happen. The liquid again, against the
      // solid velocity the wall left: M_l dl = dt [F_l - Q (v_l + dl - v_s^{k+1})].
      if (ms > mass_eps && ml > 0)
        for (int d = 0; d < D; ++d) wl[d] = vl[d] + dt * (fls[d] - Q * (vl[d] - ws[d])) / (ml + dt * Q);
    }
    if (lmask) apply_walls<D>(walls, lmask, wl, x, t);
    if ((closed || outflow_only) && ms > mass_eps) {
      // A closed surface node: no flow through it: the seepage along the outward normal set to zero,
      // the mixture's momentum kept (seepage_correction with w = 0, unconditionally). A seepage
      // face's node the same where the liquid would enter (w = 0 and eq. B: only inflow is
      // cut): open, the liquid leaves at p_w = 0; never does it enter.
      Real grad[D];
      const Real w0[D] = {};
      for (int d = 0; d < D; ++d) grad[d] = liquid.area[d][I];  // the surface's share: its normal
      if (mask) project_on_walls<D>(walls, mask, t, grad);
      if (seepage_correction<D>(grad, ms, ml, mlm, w0, ws, wl, outflow_only)) {
        if (mask) apply_walls<D>(walls, mask, ws, x, t);  // the walls have the last word
        if (lmask) apply_walls<D>(walls, lmask, wl, x, t);
      }
    }
    for (int d = 0; d < D; ++d) {
      solid.velocity_new[d][I] = ws[d];
      liquid.velocity_new[d][I] = wl[d];
    }
    // The next step's P2G adds into the other sets. The fields only SurfaceScatter adds
    // (pressure: at surface nodes) are cleared where they were added, after their
    // last reader (SurfaceInflow).
    solid_other.mass[I] = 0;
    liquid_other.mass[I] = 0;
    liquid_other.mass_mix[I] = 0;
    liquid_other.conductance[I] = 0;
    liquid_other.not_taken[I] = 0;  // after its last reader, this step's PoreRate
    if (ponds) liquid_other.pond[I] = 0;  // the same
    if (!(drag_per_mass > 0)) {
      liquid_other.drag[I] = 0;
      liquid_other.volume[I] = 0;
    }
    for (int d = 0; d < D; ++d) {
      solid_other.momentum[d][I] = 0;
      solid_other.force[d][I] = 0;
      liquid_other.momentum[d][I] = 0;
      liquid_other.force[d][I] = 0;
      liquid_other.area[d][I] = 0;  // after its last reader, this step's PoreRate
    }
  }
};

/// The liquid mass that entered through the surfaces in the step just integrated (after the
/// hydraulic node laws), added to totals[0]: at a surface node I, -dt rho_l q_I . a_I with
/// q_I = (M_lm / M_l)(v_l - v_s) the nodal seepage and a_I = sum V grad N = int N n dGamma
/// (outward n, the divergence theorem), rho_l = M_l / sum N V. Interior nodes carry no
/// boundary: the points' divergence leaves them none (PoreRate), so that the points' storage
/// gains this sum and no more (the water-balance function object checks it).
/// The last reader of the fields SurfaceScatter adds at the surface nodes: it clears them
/// there, so that the set is zero everywhere when its turn comes again (the grid update would
/// clear them at every node, for the few surface nodes that hold them).
template <int D>
struct SurfaceInflow {
  GridGeometry<D> grid;
  GridFields<D> solid;
  LiquidFields<D> liquid;
  /// This step's SurfaceMask: where a node has mass it is surface_node without the walls
  const std::uint8_t* surface = nullptr;
  const StepControl* control = nullptr;
  int parity = 0;
  Real* totals = nullptr;
  OwnedNodes<D> owned;  ///< the nodes whose inflow this rank counts
  bool serial = false;
  Real drag_per_mass = 0, rho_l = 0;  ///< as TwoPhaseGridUpdate's

  SCREE_HD void operator()(Index I) const {
    if (!surface[I]) return;
    const Real ml = liquid.mass[I], vol = nodal_volume<D>(liquid, I, drag_per_mass, rho_l);
    if (ml > 0 && vol > 0 && solid.mass[I] > 0 && owned.holds(grid, I)) {
      const Real nS = liquid.mass_mix[I] / ml;
      Real qa = 0;
      for (int d = 0; d < D; ++d)
        qa += nS * (liquid.velocity_new[d][I] - solid.velocity_new[d][I]) * liquid.area[d][I];
      const Real dt = control->dt[parity];
      if (qa != 0) atomic_add(totals, -dt * (ml / vol) * qa, serial);
    }
    liquid.pressure[I] = 0;
  }
};

}  // namespace scree

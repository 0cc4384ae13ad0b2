// The pore liquid's gather (porous/two_phase.hpp): the liquid velocity's G2P and the pore
// pressure from the liquid mass balance per cell, at the points' positions x^k, before the
// solid pass moves them.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/stencil.hpp"
#include "scree/porous/pore_pass.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

/// The pore pressure. The liquid mass balance (porous/two_phase.hpp) holds per cell c of the
/// grid, a finite volume of the points it holds, for the storage-weighted mean pressure P_c:
///   C_c dP_c/dt = sum_{p in c} V_p r_p,   C_c = sum_{p in c} V_p C_p,
///   P_c = sum V_p C_p p_p / C_c,   r_p = -(S_l div v_s + div q) at the point
/// (the divergences from the nodal velocities). The points then take the cell's pressure
/// reconstructed linearly (van Leer 1979): p_p = P_c + g_c . (x_p - x_c), x_c the
/// storage-weighted centroid of the cell's points (so sum V C p_p = C_c P_c: the liquid's
/// volume is kept), g_c per axis the minmod of the differences to the two face neighbours
/// (one-sided where there is one neighbour, none where there is none), so that no new
/// extremum appears at a sharp wetting front. A hydrostatic or a uniform profile is
/// reproduced exactly inside the cells.
/// The pressure per cell and the velocities at the nodes pair like a staggered grid (Q1-P0;
/// Anura3D also takes the pore pressure per element): the force on the node between two
/// cells sees their difference, and no pattern of p hides from it. Three other pairings were
/// tried, each with a defect measured:
/// - per point (each point integrating its own r_p): equal and opposite p_w between the rows
///   of points of a cell give no nodal force (V p grad N cancels); where the soil was
///   saturated (C smallest) they grew into an odd-even pattern of the seepage;
/// - per node (C_I dp_I/dt = sum_p N_Ip V_p r_p, dp_p = sum_I N_Ip dp_I): the force
///   sum V p grad N and the divergence sum N V r pair like central differences, blind to p
///   alternating from node to node; a saturated column with an artesian head at its base and
///   a seepage face on top carried seepage alternating between -9e-5 and +4.6e-4 m/s from one
///   row of points to the next around the steady 2.1e-4 m/s;
/// - per cell, the increment only (each point keeping its own p plus the cell's rate, with
///   or without a reconstructed slope of the rate): the differences between a cell's points
///   never relax; behind a wetting front, where the pressure is uniform, the two rows of a
///   cell stayed rho g h/2 apart from the initial hydrostatic profile (0.02 in S_l), more
///   with the slope of the rate accumulated across the front.
///
/// The seepage's divergence keeps the divergence theorem. Summed over the points,
/// sum_p V_p div q(x_p) = sum_I q_I . a_I with a_I = sum_p V_p grad N_I(x_p): at a node on
/// the surface its share of the surface, int N_I n dGamma (what SurfaceInflow counts), and
/// elsewhere the quadrature of int grad N_I dV, which is 0 when the node's support lies in
/// the soil but which the points give as 0 only while they sit regularly. In a disordered
/// mass (the debris of a failed slope) the uncorrected sum makes liquid out of nothing, as
/// much as the rain brings in (cases/rainfallSlope/README.md, "The water balance closes,
/// after the failure too"). So off the surface the seepage's test gradient carries the correction of
/// variationally consistent integration (Chen, Hillman & Rueter 2013, IJNME 95:387, the
/// first-order integration constraint), grad N_I - N_I a_I / sum_q N_Iq V_q: its sum over the
/// points is then exactly 0 at such a node, where the points sit regularly the correction is
/// the round-off of a_I = 0, and the liquid the points gain is what crossed the surface. The
/// skeleton's share, S_l div v_s, is left as it is: it is each point's own change of volume
/// (its J follows the same nodal velocities), which moves no liquid between points.
///
/// The pond (PorePassParams::ponds): the water standing on the surface nodes after the rain's
/// node law, P_I, returns to the points in their reach in proportion to their share of the
/// node's liquid mass, pond_p = sum_I N_Ip rho_l V_p P_I / M_l,I with V_p = V0 det F the
/// volume the scatter weighed M_l,I with: the shares add up to P_I, so the pond is kept whole
/// from step to step (SurfaceScatter returns it to the surface).
///
/// Three passes at the points' positions x^k, before the solid pass moves them: PoreRate (the
/// liquid velocity's G2P, r_p and the cell's moments), CellPressure (per cell: P_c, x_c,
/// g_c), then PorePressure (p_w, the prescribed pore pressures, S_l(p_w)).
template <int D, class Shape>
struct PoreRate : PorePass<D, Shape> {
  using Base = PorePass<D, Shape>;
  using Base::col, Base::lp, Base::pa, Base::pp, Base::shape;

  SCREE_HD void operator()(Index p) const {
    if (!(pa.volume0[p] >= 0)) return;  // frozen
    const Real dt = pp.control->dt[pp.gather_parity];
    if (!(dt > 0)) return;
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = pa.x[d][p];
    const detail::Stencil<D, Shape> st(shape, pp.grid, x);
    if (!st.inside) return;
    Vec<D> vl = Vec<D>::zero(), vpic = Vec<D>::zero(), dv = Vec<D>::zero();
    for (int d = 0; d < D; ++d) vl[d] = col(kLiquidVelocity + d, p);
    Real div_s = 0, div_q = 0, not_taken = 0, pond = 0, depth = 0;
    for_each_stencil_node(st, pp.grid, x, true, [&](Index I, Real N, const Vec<D>& gradN, const Vec<D>&) {
      const Real ml = lp.gather.mass[I];
      if (!(ml > 0)) return;
      if (N > 0) not_taken = fmax(not_taken, lp.gather.not_taken[I]);
      const Real rm = 1 / ml;
      if (lp.ponds && N > 0) {
        const Real P = lp.gather.pond[I];
        if (P != 0) {
          pond += N * P * rm;
          const Real level = level_share<D>(lp.gather, I, lp.up);
          if (level > 0) depth = fmax(depth, P / (lp.pore.rho_l * level));
        }
      }
      const Real nS = lp.gather.mass_mix[I] * rm;  // nodal n S_l = M_lm / M_l
      // The seepage's test gradient: grad N_I, less N_I a_I / sum N V off the surface (above).
      const Real k = lp.surface[I] ? Real(0) : N / nodal_volume<D>(lp.gather, I, lp.drag_per_mass, lp.pore.rho_l);
      for (int d = 0; d < D; ++d) {
        const Real vln = lp.gather.velocity_new[d][I];
        const Real vsn = pp.gather.velocity_new[d][I];
        vpic[d] += N * vln;
        dv[d] += N * (vln - lp.gather.momentum[d][I] * rm);
        div_s += vsn * gradN[d];
        div_q += nS * (vln - vsn) * (gradN[d] - k * lp.gather.area[d][I]);
      }
    });
    const Real a = pic_share(pp.physics, dt);
    for (int d = 0; d < D; ++d) col(kLiquidVelocity + d, p) = a * vpic[d] + (1 - a) * (vl[d] + dv[d]);
    // Ponding seen from the point: the most rain left by a surface node in its reach, and
    // for how many seconds without a break.
    col(kRainNotTaken<D>, p) = not_taken;
    col(kPondingDuration<D>, p) = not_taken > 0 ? col(kPondingDuration<D>, p) + dt : Real(0);
    if (lp.ponds) {
      if (pond != 0) {
        Mat<D> F;
        for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
        pond *= lp.pore.rho_l * pa.volume0[p] * det(F);
      }
      col(kPond<D>, p) = pond;
      col(kPondDepth<D>, p) = depth;
    }
    const Real n = col(kPorosity, p), S = col(kSaturation, p), pw = col(kPorePressure, p);
    const Real V = Base::volume_at(p, n);
    const Real r = -(S * div_s + div_q) * V, c = lp.pore.storage(n, S, pw) * V;
    const Index cell = cell_of<D>(pp.grid, x);
    atomic_add(lp.inflow + cell, r, pp.policy.serial);
    atomic_add(lp.capacity + cell, c, pp.policy.serial);
    atomic_add(lp.moments + cell, c * pw, pp.policy.serial);
    for (int d = 0; d < D; ++d) atomic_add(lp.moments + (d + 1) * lp.n_cells + cell, c * x[d], pp.policy.serial);
  }
};

/// The cells' new pressures and their reconstruction (PoreRate above), once per cell, for
/// PorePressure: P_c = (sum V C p + dt sum V r) / C_c, the storage-weighted centroid x_c
/// and per axis the slope g_c, the minmod of the differences to the two face neighbours
/// (one-sided where there is one, 0 where there is none). A cell without points (C_c = 0)
/// is left as it is: no point reads it. (Per point, the same sums read 25 cell values of
/// a 2D point's neighbourhood for each of the cell's points.)
template <int D>
struct CellPressure {
  GridGeometry<D> grid;
  const Real* inflow = nullptr;    ///< PorePassParams's, n_cells each
  const Real* capacity = nullptr;
  const Real* moments = nullptr;
  Real* out = nullptr;             ///< PorePassParams::cell_pressure
  Index n_cells = 0;
  const StepControl* control = nullptr;
  int gather_parity = 0;

  SCREE_HD void operator()(Index cell) const {
    const Real dt = control->dt[gather_parity];
    const Real c0 = capacity[cell];
    if (!(dt > 0) || !(c0 > 0)) return;
    // One reciprocal per cell read (a double division is a chain of about ten dependent
    // instructions on a GPU), and the cell's coordinates in 32-bit arithmetic (a 64-bit
    // division is emulated on a GPU). A grid has far fewer than 2^32 nodes (a node's fields
    // alone are over 200 B).
    const Real r0 = 1 / c0;
    const Real P0 = (moments[cell] + dt * inflow[cell]) * r0;
    out[cell] = P0;
    std::uint32_t rest = static_cast<std::uint32_t>(cell);
    Index stride = 1;
    for (int d = 0; d < D; ++d) {
      const std::uint32_t nd = static_cast<std::uint32_t>(grid.n[d]);
      const int cd = static_cast<int>(rest % nd);
      rest /= nd;
      const Real* xm = moments + (d + 1) * n_cells;  // sum V C x_d per cell
      const Real xc = xm[cell] * r0;
      Real lo = 0, hi = 0;
      bool has_lo = false, has_hi = false;
      const Index a = cell - stride, b = cell + stride;
      if (cd > 0 && capacity[a] > 0) {
        const Real ra = 1 / capacity[a];
        lo = (P0 - (moments[a] + dt * inflow[a]) * ra) / (xc - xm[a] * ra);
        has_lo = true;
      }
      if (cd + 2 < grid.n[d] && capacity[b] > 0) {
        const Real rb = 1 / capacity[b];
        hi = ((moments[b] + dt * inflow[b]) * rb - P0) / (xm[b] * rb - xc);
        has_hi = true;
      }
      Real slope = 0;
      if (has_lo && has_hi)
        slope = lo * hi > 0 ? (fabs(lo) < fabs(hi) ? lo : hi) : Real(0);
      else if (has_lo || has_hi)
        slope = has_lo ? lo : hi;
      out[(1 + d) * n_cells + cell] = xc;
      out[(1 + D + d) * n_cells + cell] = slope;
      stride *= grid.n[d];
    }
  }
};

/// The pore pressure from its cell's reconstruction (CellPressure), then the prescribed
/// pore pressures, and S_l(p_w).
template <int D, class Shape>
struct PorePressure : PorePass<D, Shape> {
  using Base = PorePass<D, Shape>;
  using Base::col, Base::lp, Base::pa, Base::pp, Base::shape;

  SCREE_HD void operator()(Index p) const {
    if (!(pa.volume0[p] >= 0)) return;  // frozen
    const Real dt = pp.control->dt[pp.gather_parity];
    const Real t = pp.control->t[pp.gather_parity];
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = pa.x[d][p];
    const Real p_old = col(kPorePressure, p), S_old = col(kSaturation, p);  // the last step's
    Real pw = p_old;
    if (dt > 0) {
      const detail::Stencil<D, Shape> st(shape, pp.grid, x);
      const Index cell = st.inside ? cell_of<D>(pp.grid, x) : Index(0);
      if (st.inside && lp.capacity[cell] > 0) {  // p_p = P_c + g_c . (x_p - x_c)
        const Index nc = lp.n_cells;
        pw = lp.cell_pressure[cell];
        for (int d = 0; d < D; ++d)
          pw += lp.cell_pressure[(1 + D + d) * nc + cell] * (x[d] - lp.cell_pressure[(1 + d) * nc + cell]);
      }
    }
    // Prescribed pore pressures (a water table, an artesian head), on every point of a cell
    // the law's box overlaps: with linear shape functions the nodal force sees a cell's sum
    // of V p, and a prescribed point beside free ones in one cell would be undone by them
    // (measured: a base row held 2 kPa above hydrostatic, the free row of its cell fell 2 kPa
    // below, and no water moved).
    const Real p_free = pw;
    Real cell_lo[D];  // the lower corner of the point's cell
    for (int d = 0; d < D; ++d)
      cell_lo[d] = pp.grid.origin[d] + floor((x[d] - pp.grid.origin[d]) / pp.grid.h) * pp.grid.h;
    bool held = false;
    for (int i = 0; i < lp.n_laws; ++i) {
      const PorePressureLaw& L = lp.laws[i];
      if (t < L.t_start || t >= L.t_end) continue;
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && cell_lo[d] + pp.grid.h > L.lo[d] && cell_lo[d] < L.hi[d];
      if (!in) continue;
      pw = L.hydrostatic ? lp.pore.rho_l * lp.g * (L.level - x[lp.vertical]) : L.value;
      held = true;
    }
    const Real S = lp.pore.table.saturation(pw);
    if (lp.totals && held) {
      // The liquid mass the prescription added: the point's stored liquid after it,
      // rho_l (1 + p/K_l) n S_l V, minus the last step's, minus what the seepage and the
      // skeleton's deformation brought. The cell's balance above is linear in the storage,
      // C_c (P_c - P_c^old) = dt sum V r, so what they brought is rho_l V C (p_free - p_old),
      // C at the last step's state (PoreRate's); summed over the cell, all of whose points a
      // law holds, it is exactly rho_l dt sum V r. Not rho_l n V S_l(p_free) (1 + p_free/K_l):
      // p_free is a state the point never holds, and where the storage is small (near
      // saturation, C ~ n/K_l) a small imbalance of the fluxes puts it kPa from p_old, where
      // S_l(p_free) lies far below the linear balance's: the difference is no liquid that
      // moved, yet it would be counted as added at every step (cases/infiltration1D/README.md,
      // "The water balance").
      const Real n = col(kPorosity, p);
      const Real V = Base::volume_at(p, n);
      const Real K = lp.pore.bulk_l;
      const Real brought = V * lp.pore.storage(n, S_old, p_old) * (p_free - p_old);
      atomic_add(lp.totals + 1, lp.pore.rho_l * (n * V * (S * (1 + pw / K) - S_old * (1 + p_old / K)) - brought),
                 pp.policy.serial);
    }
    col(kPorePressure, p) = pw;
    col(kSaturation, p) = S;
    col(kSuction, p) = pw < 0 ? -pw : Real(0);
  }
};

}  // namespace scree

// The two-phase formulation: saturated or unsaturated soil as one set of material points
// carrying the solid skeleton and the pore liquid, with a velocity field for each phase
// (the single-point, two-velocity formulation of Anura3D and of the rainfall-infiltration
// MPM we implement: a_s, a_l, n, S_l, rho_s, rho_l). The pore air is at atmospheric
// pressure (p_a = 0).
//
// The solid skeleton is an ordinary body of the case's material: its kernels (mpm/
// particle_pass.hpp) move the points with the solid velocity v_s, update F and the
// effective stress sigma' (tension positive), and scatter the solid mass m_s = (1 - n0)
// rho_s V0, its momentum and the force -V sigma' grad N + N m_s g. The pore liquid adds two
// passes over the same points and its own grid fields; nothing of it runs in a
// single-phase case.
//
// Per point (extra columns, PoreColumn): p_w (compression positive) [Pa], S_l, n, suction,
// v_l, seepage velocity w = n S_l (v_l - v_s).
// Per node (LiquidFields): M_l = sum N rho_l V, M_lm = sum N n S_l rho_l V (the liquid's
// mass in the mixture), liquid momentum sum N rho_l V v_l, liquid force F_l, drag
// coefficient Q, liquid velocities, and for the rainfall condition the gradient of the
// mixture density sum (m_s + m_lm) grad N (its eq. A) and the points per cell.
//
// Equations (SI, p_w compression positive, sigma tension positive, chi = S_l):
//   effective stress (Bishop, chi = S_l):   sigma = sigma' - S_l p_w I
//   mixture momentum:   M_s a_s + M_lm a_l = F_mix
//       F_mix = -sum V (sigma' - S_l p_w I) grad N + sum N (m_s + m_lm) g
//   liquid momentum (per unit volume of liquid, Darcy drag):
//       M_l a_l = F_l - Q (v_l - v_s),  F_l = sum V p_w grad N + sum N rho_l V g,
//       Q = sum N V n S_l mu_l / (kappa k_I),  k_I = sum N V k_rel / sum N V
//     (k_I the arithmetic mean over the node's points, as a finite-volume Richards solver
//     takes between its cells, Celia et al. 1990; a sum of the points' resistances,
//     sum N V n S mu / (kappa k_rel), is their harmonic mean: one dry point behind a
//     wetting front then holds the water back, and a dry surface takes in almost no rain)
//     (steady state: n S_l (v_l - v_s) = -(kappa k_rel / mu_l)(grad p_w - rho_l g), Darcy)
//   liquid mass balance, incompressible grains, liquid bulk modulus K_l:
//       (n S_l / K_l + n dS_l/dp_w) dp_w/dt = -(S_l div v_s + div q),  q = n S_l (v_l - v_s)
//   porosity from the solid volumetric strain: n = 1 - (1 - n0) / J, J = det F.
// The drag is integrated implicitly per node (TwoPhaseGridUpdate): its explicit limit,
// dt < 2 k / (n g) with k the hydraulic conductivity (4e-8 s at k = 1e-7 m/s, and smaller
// as k_rel -> 0), no longer constrains the step, which the acoustic limit alone sets.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/particle_pass.hpp"
#include "scree/mpm/wall_law.hpp"
#include "scree/porous/hydraulic_model.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

/// The extra columns of a two-phase body's points, in order (BodySetup::extra).
enum PoreColumn : int { kPorePressure = 0, kSaturation = 1, kPorosity = 2, kSuction = 3, kLiquidVelocity = 4 };
/// Column of the seepage velocity's first component.
template <int D>
inline constexpr int kSeepage = kLiquidVelocity + D;
template <int D>
inline constexpr int kPoreColumns = kLiquidVelocity + 2 * D;

/// The constants of a two-phase body.
struct PoreParams {
  Real n0 = 0.3;          ///< initial porosity [-]
  Real rho_l = 1000;      ///< liquid density [kg/m^3]
  Real bulk_l = 2e9;      ///< liquid bulk modulus K_l [Pa]
  Real viscosity = 1e-3;  ///< dynamic viscosity mu_l [Pa s]
  Real kappa = 1e-12;     ///< intrinsic permeability [m^2]
  HydraulicTable table;

  /// The liquid's storage C = n S_l / K_l + n dS_l/dp [1/Pa] at porosity n, saturation S
  /// and pore pressure p: (C) dp/dt = -(S_l div v_s + div q) (the mass balance, top of file).
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
  Real* gradient[D];      ///< sum (m_s + m_lm) grad N [kg/m], the mixture density's (eq. A)
  Real* area[D];          ///< sum V grad N [m^2 per unit thickness]: the surface's share, int N n dGamma
  Real* pressure;         ///< sum N V p_w [Pa m^3]; over `volume`: the nodal pore pressure
  Real* volume;           ///< sum N V [m^3] (see drag_per_mass)
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
inline constexpr int kLiquidFieldCount = 6 + 5 * D;

/// Whether node I of a grid is on a surface of the points: among the cells around it, one
/// is empty and one holds points (`cells`: points per cell, cell (i, j) at i + j n_x), or,
/// with `has_mass` (the node has mass), one is empty and none holds points.
/// Cells beyond the grid are empty. With `walls`, the cells behind a contact wall acting at
/// the node (on the side its normal points away from) count as neither: the wall is a
/// plane of symmetry of the soil it holds, not a surface of it (the sides of a column
/// between slip walls are no surface; its top nodes at the walls are).
/// The second case: a node whose cells hold no point but which has mass takes it from points
/// of the cells beyond, through shape functions wider than a cell (a GIMP point's domain
/// reaching past the cell of its centre, a B-spline's kernel). The body's boundary, the edge
/// of those domains, then crosses the node's support: the node is on the surface as much as
/// the node below it, and its liquid needs the surface's condition (closed, or the rain's
/// seepage). Measured without it (cases/infiltration1D, K_sat 2e-4 m/s, rain, E = 5 MPa): the
/// soft column swells, the top points' uGIMP domains (edge at the node row y = 1.05 m at
/// t = 0) cross into the cell above, and the node row at 1.075 m takes a mass that grows
/// with the overlap d as d^2. Once it passes massTolerance it is accelerated, neither closed
/// nor corrected by the rain: an open surface at p_w = 0 a distance d from the top points
/// at -8 kPa, whose liquid ran at -7.5 m/s. Its share of div q at the top points, n S_l
/// (v_l - v_s) grad N, does not shrink with d (grad N^2 / N = 1 / (l_p h^2) for uGIMP): it
/// pumped liquid into the top cell, the two rows of a cell took opposite seepage (+0.003 and
/// -0.0065 m/s at 1.5 s, +-0.02 m/s at 2 s, against a rain of 5e-4) and the error against
/// the Richards reference went from 0.9% of rho g H at 1.25 s to 45% at 1.5 s. A rigid column
/// (E = 500 MPa) swells too little for its node to pass massTolerance; with massTolerance 0
/// it failed the same way (38% at 0.5 s). With this node on the surface both stay within 2%.
template <int D>
SCREE_INLINE bool surface_node(const GridGeometry<D>& grid, const Real* cells, Index I, const Wall* walls = nullptr,
                               WallMask mask = 0, Real t = 0, bool has_mass = false) {
  int idx[D];
  grid.unflat(I, idx);
  bool empty = false, full = false;
  for (int c = 0; c < (1 << D); ++c) {
    Index cell = 0, stride = 1;
    bool ok = true;
    for (int d = 0; d < D; ++d) {
      const int j = idx[d] - 1 + ((c >> d) & 1);
      ok = ok && j >= 0 && j < grid.n[d] - 1;
      cell += j * stride;
      stride *= grid.n[d];
    }
    bool behind = false;
    for (WallMask m = walls ? mask : 0u; m; m &= m - 1) {
      const Wall& w = walls[lowest_bit(m)];
      if (w.mode != Wall::Mode::contact || t < w.t_start || t >= w.t_end) continue;
      Real on = 0;  // the cell centre's offset from the node, along the wall's normal
      for (int d = 0; d < D; ++d) on += ((c >> d) & 1 ? Real(1) : Real(-1)) * w.normal[d];
      behind = behind || on < -Real(1e-6);
    }
    if (behind) continue;
    if (!ok) {
      empty = true;  // beyond the grid: nothing there
      continue;
    }
    (cells[cell] > 0 ? full : empty) = true;
  }
  return empty && (full || has_mass);
}

/// The seepage through a surface node set to w . n (w: a prescribed seepage velocity, e.g.
/// rain; n the outward normal from the mixture's density, eq. A of the rainfall paper's
/// supplement), keeping the mixture's momentum (its eqs. C-E; boundary/rainfall). With
/// `only_if_more` the correction applies only where the soil would take at least w (eq. B).
/// Returns whether it was applied.
template <int D>
SCREE_HD inline bool seepage_correction(const Real* grad, Real ms, Real ml, Real mlm, const Real* w, Real* vs,
                                        Real* vl, bool only_if_more) {
  Real g2 = 0;
  for (int d = 0; d < D; ++d) g2 += grad[d] * grad[d];
  if (!(g2 > 0) || !(ml > 0) || !(mlm > 0) || !(ms > 0)) return false;
  const Real inv = 1 / sqrt(g2);
  Real n[D];
  for (int d = 0; d < D; ++d) n[d] = grad[d] * inv;  // (A)
  const Real nS = mlm / ml;
  Real rel = 0, wn = 0;
  for (int d = 0; d < D; ++d) {
    rel += (vl[d] - vs[d]) * n[d];
    wn += w[d] * n[d];
  }
  if (only_if_more && nS * rel - wn > 0) return false;  // (B): the soil takes less than w
  const Real r = wn / nS - rel;                          // (C)
  const Real dl = r * ms / (ms + mlm), ds = -r * mlm / (ms + mlm);  // (D)
  for (int d = 0; d < D; ++d) {  // (E)
    vl[d] += dl * n[d];
    vs[d] += ds * n[d];
  }
  return true;
}

/// The surface normal at a node that walls hold lies in the walls' planes. A contact wall
/// (slip, friction) is a plane of symmetry of the soil it holds: mirrored across it, the
/// mixture's density has no gradient along the wall's normal. Without a mirror the points
/// stop at the wall, and eq. (A) tilts the normal towards it: at the top nodes of a
/// one-cell-wide column it points along the diagonal, and a correction along it (eq. C, or
/// a closed surface's) sets the seepage along the diagonal, which the wall then halves.
/// So the gradient loses its components along the normals of the contact walls acting at
/// the node (one after the other: exact for orthogonal walls). Stick walls set both
/// velocities outright and leave it as it is.
template <int D>
SCREE_INLINE void project_on_walls(const Wall* walls, WallMask mask, Real t, Real* grad) {
  for (; mask; mask &= mask - 1) {
    const Wall& w = walls[lowest_bit(mask)];
    if (w.mode != Wall::Mode::contact || t < w.t_start || t >= w.t_end) continue;
    Real gn = 0;
    for (int d = 0; d < D; ++d) gn += grad[d] * w.normal[d];
    for (int d = 0; d < D; ++d) grad[d] -= gn * w.normal[d];
  }
}

/// An open stretch of surface (ponding, rain): the pore liquid there has the natural
/// condition of the weak form, p_w = 0. Elsewhere a surface is closed (OpenSurfaces below).
inline constexpr int kMaxOpenSurfaces = 16;
struct OpenSurfaceWindow {
  Real t_start = -1e300, t_end = 1e300;
  int outflow_only = 0;  ///< a seepage face: open only where the nodal p_w >= 0
};

/// A prescribed pore pressure on the points inside a box (porePressure condition):
/// p_w = value, or hydrostatic below the level z_w along -g, p_w = rho_l |g| (z_w - z)
/// (negative above it: the suction of a hydrostatic profile).
struct PorePressureLaw {
  Real lo[3] = {-1e300, -1e300, -1e300}, hi[3] = {1e300, 1e300, 1e300};
  Real value = 0;
  int hydrostatic = 0;
  Real level = 0;  ///< z_w along the vertical (the axis opposite to g) [m]
  Real t_start = -1e300, t_end = 1e300;
};
inline constexpr int kMaxPorePressureLaws = 8;

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
  /// per node in 2D; performance log entry 28). This factor mu_l / (kappa rho_l) [1/s], or 0
  /// when the bodies differ: both are then scattered (LiquidFields::drag, volume).
  Real drag_per_mass = 0;
  /// Cumulative liquid mass [kg] since t = 0: [0] through the surfaces (SurfaceInflow),
  /// [1] added by the prescribed pore pressures. Null: not counted.
  Real* totals = nullptr;
};

namespace detail {
SCREE_INLINE Real clamp01(Real x, Real lo, Real hi) { return x < lo ? lo : (x > hi ? hi : x); }
}  // namespace detail

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
};

/// The pore pressure. The liquid mass balance (top of file) holds per cell c of the grid,
/// a finite volume of the points it holds, for the storage-weighted mean pressure P_c:
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
    Real div_s = 0, div_q = 0;
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I;
      Real N;
      Vec<D> gradN, dx;
      st.node(k, pp.grid, x, I, N, gradN, dx);
      const Real ml = lp.gather.mass[I];
      if (!(ml > 0)) continue;
      const Real rm = 1 / ml;
      const Real nS = lp.gather.mass_mix[I] * rm;  // nodal n S_l = M_lm / M_l
      for (int d = 0; d < D; ++d) {
        const Real vln = lp.gather.velocity_new[d][I];
        const Real vsn = pp.gather.velocity_new[d][I];
        vpic[d] += N * vln;
        dv[d] += N * (vln - lp.gather.momentum[d][I] * rm);
        div_s += vsn * gradN[d];
        div_q += nS * (vln - vsn) * gradN[d];
      }
    }
    const Real a = pic_share(pp, dt);
    for (int d = 0; d < D; ++d) col(kLiquidVelocity + d, p) = a * vpic[d] + (1 - a) * (vl[d] + dv[d]);
    const Real n = col(kPorosity, p), S = col(kSaturation, p), pw = col(kPorePressure, p);
    // The volume at x^k from the porosity the last scatter wrote: J = (1 - n0) / (1 - n).
    const Real V = pa.volume0[p] * (1 - lp.pore.n0) / (1 - n);
    const Real r = -(S * div_s + div_q) * V, c = lp.pore.storage(n, S, pw) * V;
    const Index cell = cell_of<D>(pp.grid, x);
    atomic_add(lp.inflow + cell, r, pp.serial);
    atomic_add(lp.capacity + cell, c, pp.serial);
    atomic_add(lp.moments + cell, c * pw, pp.serial);
    for (int d = 0; d < D; ++d) atomic_add(lp.moments + (d + 1) * lp.n_cells + cell, c * x[d], pp.serial);
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
    // division is emulated: with both, this pass took 21 us at 4.6e5 cells on an H100).
    // A grid has far fewer than 2^32 nodes (a node's fields alone are over 200 B).
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
    Real pw = col(kPorePressure, p);
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
    for (int i = 0; i < lp.n_laws; ++i) {
      const PorePressureLaw& L = lp.laws[i];
      if (t < L.t_start || t >= L.t_end) continue;
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && cell_lo[d] + pp.grid.h > L.lo[d] && cell_lo[d] < L.hi[d];
      if (!in) continue;
      pw = L.hydrostatic ? lp.pore.rho_l * lp.g * (L.level - x[lp.vertical]) : L.value;
    }
    const Real S = lp.pore.table.saturation(pw);
    if (lp.totals && pw != p_free) {
      // The liquid mass the prescription added: rho_l (1 + p/K_l) n S_l V after minus before.
      const Real n = col(kPorosity, p);
      const Real V = pa.volume0[p] * (1 - lp.pore.n0) / (1 - n);
      const Real K = lp.pore.bulk_l, S0 = lp.pore.table.saturation(p_free);
      atomic_add(lp.totals + 1, lp.pore.rho_l * n * V * (S * (1 + pw / K) - S0 * (1 + p_free / K)), pp.serial);
    }
    col(kPorePressure, p) = pw;
    col(kSaturation, p) = S;
    col(kSuction, p) = pw < 0 ? -pw : Real(0);
  }
};

/// The columns of point p that follow from the solid pass's state: the porosity from J,
/// n = 1 - (1 - n0) / J (clamped to [1e-3, 0.999]), and the seepage velocity
/// w = n S_l (v_l - v_s). Returns n.
template <int D>
SCREE_INLINE Real store_pore_columns(const PorePassParams<D>& lp, Index n_points, Index p, Real J, Real S,
                                     const Vec<D>& vl, const Vec<D>& vs) {
  auto col = [&](int c) -> Real& { return lp.extra[static_cast<std::size_t>(c) * n_points + p]; };
  const Real n = detail::clamp01(1 - (1 - lp.pore.n0) / J, Real(1e-3), Real(0.999));
  col(kPorosity) = n;
  for (int d = 0; d < D; ++d) col(kSeepage<D> + d) = n * S * (vl[d] - vs[d]);
  return n;
}

/// The pore columns of every point after a G2P with no P2G after it (Solver::flush, before a
/// snapshot): otherwise they would be the last scatter's, one step behind the positions,
/// and a run's output would depend on whether its last step was followed by an idle one
/// (a step on a target time, dt = 0, whose scatter writes them).
template <int D>
struct PoreColumns {
  PorePassParams<D> lp;
  ParticleArrays<D> pa;
  SCREE_HD void operator()(Index p) const {
    if (!(pa.volume0[p] >= 0)) return;  // frozen
    Vec<D> vl, vs;
    for (int d = 0; d < D; ++d) {
      vl[d] = lp.extra[static_cast<std::size_t>(kLiquidVelocity + d) * pa.n + p];
      vs[d] = pa.v[d][p];
    }
    Mat<D> F;
    for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
    store_pore_columns<D>(lp, pa.n, p, det(F), lp.extra[static_cast<std::size_t>(kSaturation) * pa.n + p], vl, vs);
  }
};

/// Both phases' P2G of a two-phase body, in one pass after the solid pass (weights at
/// x_p^{k+1}): the solid pass of a two-phase body gathers and updates only (its scatter
/// flags off; Solver::step_two_phase), and this pass scatters
///   the solid:  m_s N (eq. 5 of the solid pass), m_s N v_s (eq. 6; APIC: v_s + C dx),
///   the mixture force  F_mix = -V (sigma' - S_l p_w I) grad N + N (m_s + m_lm) g
///     (top of file), added as one value per node and axis,
///   the liquid: porosity from J, M_l, M_lm, the drag and conductance sums, the liquid
///     momentum, F_l = V p_w grad N + N m_l g, sum N V,
/// and counts the points per cell. The fields read only at surface nodes follow in
/// SurfaceScatter.
/// One pass for both phases builds the stencil and the warp's runs once, and the mixture
/// force takes one atomic per node and axis where the solid's scatter and a separate liquid
/// pass took two (performance log entry 28).
/// A point whose stencil at x^{k+1} leaves the grid adds nothing; the next step's gather
/// (or the run's last flush) freezes and reports it (ParticlePass::lost), one step later
/// than a single-phase pass would.
template <int D, class Shape>
struct MixtureScatter : PorePass<D, Shape> {
  using Base = PorePass<D, Shape>;
  using Base::col, Base::lp, Base::pa, Base::pp, Base::shape;

  /// Warp-collective (parallel_for_warps): points sorted by cell share their stencil's
  /// nodes, so the lanes of a warp with the same first node add their values per warp first
  /// and one lane makes the atomic add (WarpSegment, as the solid pass's scatter).
  SCREE_HD void operator()(Index p, bool valid) const {
    bool active = valid && pa.volume0[p] >= 0;
    Vec<D> x = Vec<D>::zero(), vs = Vec<D>::zero(), vl = Vec<D>::zero();
    Mat<D> C = Mat<D>::zero();
    Sym3 sig = Sym3::zero();
    Real V = 0, n = 0, S = 0, pw = 0;
    const bool apic = pp.transfer == Transfer::apic;
    if (active) {
      for (int d = 0; d < D; ++d) {
        x[d] = pa.x[d][p];
        vs[d] = pa.v[d][p];
        vl[d] = col(kLiquidVelocity + d, p);
      }
      if (apic)
        for (int i = 0; i < D * D; ++i) C.a[i / D][i % D] = pa.C[i][p];
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
      const Real J = det(F);
      V = pa.volume0[p] * J;
      sig = detail::load_stress<D>(pa.sigma, p);
      S = col(kSaturation, p);
      pw = col(kPorePressure, p);
      n = store_pore_columns<D>(lp, pa.n, p, J, S, vl, vs);
    }
    // The total stress's share in the mixture force: sigma = sigma' - S_l p_w I (Bishop).
    for (int d = 0; d < 3; ++d) sig[d] -= S * pw;
    const Real rho_l = lp.pore.rho_l;
    const Real m_lm = n * S * rho_l * V, m_l = rho_l * V, m_s = active ? pa.mass[p] : Real(0);
    const Real krel = active ? lp.pore.table.relative_permeability(S) : Real(0);
    const Real q = V * n * S * lp.pore.viscosity / lp.pore.kappa;

    const detail::Stencil<D, Shape> st(shape, pp.grid, x);
    active = active && st.inside;  // outside: frozen by the next gather (above)
    const bool serial = pp.serial;
#if defined(__CUDA_ARCH__)
    const WarpSegment seg(active ? static_cast<long long>(pp.grid.flat(st.base))
                                 : -1 - static_cast<long long>(threadIdx.x));
    if (lp.cells) {
      // The points per cell: the lanes of one cell (sorted points share it) add their count
      // in one atomic (one per point serialised on a few addresses per warp).
      const long long cell = active ? static_cast<long long>(cell_of<D>(pp.grid, x)) : -1;
      const unsigned peers = __match_any_sync(0xffffffffu, cell);
      if (active && __ffs(peers) - 1 == static_cast<int>(threadIdx.x & 31u))
        atomic_add(lp.cells + cell, Real(__popc(peers)), serial);
    }
#else
    const WarpSegment seg(0);
    if (active && lp.cells) atomic_add(lp.cells + cell_of<D>(pp.grid, x), Real(1), serial);
#endif
    auto add = [&](Real* field, Real value) {
#if defined(__CUDA_ARCH__)
      const Real sum = seg.sum(value);
      if (active && seg.head && sum != 0) atomic_add(field, sum, serial);
#else
      if (active && value != 0) atomic_add(field, value, serial);
#endif
    };
SCREE_UNROLL
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I = 0;
      Real N = 0;
      Vec<D> gradN = Vec<D>::zero(), dx = Vec<D>::zero();
      if (active) st.node(k, pp.grid, x, I, N, gradN, dx);
#if !defined(__CUDA_ARCH__)
      if (!active) continue;
#endif
      Vec<D> vI = vs;
      if (apic) vI += C * dx;
      add(pp.scatter.mass + I, N * m_s);
      add(lp.scatter.mass + I, N * m_l);
      add(lp.scatter.mass_mix + I, N * m_lm);
      if (!(lp.drag_per_mass > 0)) {  // uniform across the bodies (uniform in a launch)
        add(lp.scatter.drag + I, N * q);
        add(lp.scatter.volume + I, N * V);
      }
      add(lp.scatter.conductance + I, N * V * krel);
      for (int d = 0; d < D; ++d) {
        Real s = 0;
        for (int e = 0; e < D; ++e) s += sig(d, e) * gradN[e];
        add(pp.scatter.momentum[d] + I, N * m_s * vI[d]);
        add(pp.scatter.force[d] + I, -V * s + N * (m_s + m_lm) * pp.gravity[d]);
        add(lp.scatter.momentum[d] + I, N * m_l * vl[d]);
        add(lp.scatter.force[d] + I, V * pw * gradN[d] + N * m_l * pp.gravity[d]);
      }
    }
    // The pore liquid's signal speed (undrained, the mixture's inertia): c^2 = S_l^2 /
    // (C rho_mix) with the storage C = n S_l / K_l + n dS_l/dp (K_l / (n rho_mix) when
    // saturated), plus |v_l|. The step takes the larger of it and the skeleton's.
    if (active && speed_wanted(pp) && V > 0) {
      const Real Cs = lp.pore.storage(n, S, pw);
      const Real rho_mix = (m_s + m_lm) / V;
      const Real c = sqrt(S * S / (Cs * rho_mix)) + norm(vl);
      // One global address for every point: read it first, and only a larger speed takes
      // the atomic (after the first warps, almost none): unconditional, the 1e6 atomics on
      // one word serialised and made this pass 6x the solid pass (H100, 1e6 points).
      if (c > *static_cast<const volatile Real*>(&pp.control->max_speed[pp.parity]))
        atomic_max_nonneg(&pp.control->max_speed[pp.parity], c, serial);
    }
  }
};

/// Which nodes lie on a surface of the points (surface_node, without the walls and with the
/// node's mass of either phase: a superset of the nodes any hydraulic law treats as
/// surface), from this step's points per cell, for SurfaceScatter, the grid update and
/// SurfaceInflow.
template <int D>
struct SurfaceMask {
  GridGeometry<D> grid;
  const Real* cells = nullptr;
  const Real* solid_mass = nullptr;
  const Real* liquid_mass = nullptr;
  std::uint8_t* surface = nullptr;
  SCREE_HD void operator()(Index I) const {
    const bool has_mass = solid_mass[I] > 0 || liquid_mass[I] > 0;
    surface[I] = surface_node<D>(grid, cells, I, nullptr, 0, 0, has_mass) ? 1 : 0;
  }
};

/// The liquid's nodal fields read at surface nodes alone (the closed surface's p_b and
/// area, eq. A's mixture-density gradient, the surface inflow): sum (m_s + m_lm) grad N,
/// sum V grad N and sum N V p_w, added only into the nodes SurfaceMask marked, by the points
/// whose stencil reaches one. Every point adding them (PoreScatter) was a third of that
/// pass's atomics for nodes that are never read (performance log entry 27). Weights at
/// x^{k+1}, as PoreScatter's (whose porosity it reads).
template <int D, class Shape>
struct SurfaceScatter : PorePass<D, Shape> {
  using Base = PorePass<D, Shape>;
  using Base::col, Base::lp, Base::pa, Base::pp, Base::shape;

  SCREE_HD void operator()(Index p, bool valid) const {
    bool active = valid && pa.volume0[p] >= 0;
    Vec<D> x = Vec<D>::zero();
    if (active)
      for (int d = 0; d < D; ++d) x[d] = pa.x[d][p];
    const detail::Stencil<D, Shape> st(shape, pp.grid, x);
    active = active && st.inside;
    bool touches = false;
    for (int k = 0; active && k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I = 0;
      Real N = 0;
      Vec<D> gradN, dx;
      st.node(k, pp.grid, x, I, N, gradN, dx);
      touches = touches || lp.surface[I] != 0;
    }
#if defined(__CUDA_ARCH__)
    if (!__any_sync(0xffffffffu, touches)) return;  // the whole warp inside the soil (uniform)
#endif
    active = active && touches;
    Real V = 0, pw = 0, m = 0;
    if (active) {
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
      V = pa.volume0[p] * det(F);
      const Real n = col(kPorosity, p), S = col(kSaturation, p);
      pw = col(kPorePressure, p);
      m = pa.mass[p] + n * S * lp.pore.rho_l * V;  // m_s + m_lm
    }
    const bool serial = pp.serial;
#if defined(__CUDA_ARCH__)
    const WarpSegment seg(active ? static_cast<long long>(pp.grid.flat(st.base))
                                 : -1 - static_cast<long long>(threadIdx.x));
#else
    const WarpSegment seg(0);
#endif
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I = 0;
      Real N = 0;
      Vec<D> gradN = Vec<D>::zero(), dx = Vec<D>::zero();
      if (active) st.node(k, pp.grid, x, I, N, gradN, dx);
      const bool mine = active && lp.surface[I] != 0;  // the same node for a whole run of lanes
#if !defined(__CUDA_ARCH__)
      if (!mine || N == 0) continue;  // as PoreScatter's CPU path skipped them
#endif
      auto add = [&](Real* field, Real value) {
#if defined(__CUDA_ARCH__)
        const Real sum = seg.sum(mine ? value : Real(0));
        if (mine && seg.head && sum != 0) atomic_add(field, sum, serial);
#else
        if (mine && value != 0) atomic_add(field, value, serial);
#endif
      };
      for (int d = 0; d < D; ++d) {
        add(lp.scatter.gradient[d] + I, m * gradN[d]);
        add(lp.scatter.area[d] + I, V * gradN[d]);
      }
      add(lp.scatter.pressure + I, N * V * pw);
    }
  }
};

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
    if (cells && ml > 0 && surface[I] && surface_node<D>(grid, cells, I, walls, mask, t, true)) {
      bool is_open = (mask & ~lmask) != 0;  // on a drained wall
      bool seepage = false;                 // open as a seepage face
      for (std::uint32_t m = open_masks ? open_masks[I] : 0u; m; m &= m - 1) {
        const int b = lowest_bit(m);
        if (t < open[b].t_start || t >= open[b].t_end) continue;
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
    // The drag coefficient with the node's mean relative permeability (top of file).
    const Real volI = nodal_volume<D>(liquid, I, drag_per_mass, rho_l);
    const Real kI = inflow_face ? Real(1) : (volI > 0 ? liquid.conductance[I] / volI : Real(1));
    const Real Q = nodal_drag<D>(liquid, I, drag_per_mass) / (kI > Real(1e-300) ? kI : Real(1e-300));
    Real probe = 0;  // health: both phases' nodal velocities and forces (report_nonfinite_node)
    for (int d = 0; d < D; ++d) {
      Real fm = solid.force[d][I], fl = liquid.force[d][I] + boundary[d];
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
      for (int d = 0; d < D; ++d) grad[d] = liquid.gradient[d][I];
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
    // (gradient, area, pressure: at surface nodes) are cleared where they were added, after
    // their last reader (SurfaceInflow).
    solid_other.mass[I] = 0;
    liquid_other.mass[I] = 0;
    liquid_other.mass_mix[I] = 0;
    liquid_other.conductance[I] = 0;
    if (!(drag_per_mass > 0)) {
      liquid_other.drag[I] = 0;
      liquid_other.volume[I] = 0;
    }
    for (int d = 0; d < D; ++d) {
      solid_other.momentum[d][I] = 0;
      solid_other.force[d][I] = 0;
      liquid_other.momentum[d][I] = 0;
      liquid_other.force[d][I] = 0;
    }
  }
};

/// The liquid mass that entered through the surfaces in the step just integrated (after the
/// hydraulic node laws), added to totals[0]: at a surface node I, -dt rho_l q_I . a_I with
/// q_I = (M_lm / M_l)(v_l - v_s) the nodal seepage and a_I = sum V grad N = int N n dGamma
/// (outward n, the divergence theorem), rho_l = M_l / sum N V. Interior nodes carry no
/// boundary, so what the points' storage gains beyond this sum is the discretisation's
/// imbalance (the water-balance function object reports it).
/// The last reader of the fields SurfaceScatter adds at the surface nodes: it clears them
/// there, so that the set is zero everywhere when its turn comes again (cleared at every
/// node by the grid update, they were a seventh of its memory traffic).
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
  bool serial = false;
  Real drag_per_mass = 0, rho_l = 0;  ///< as TwoPhaseGridUpdate's

  SCREE_HD void operator()(Index I) const {
    if (!surface[I]) return;
    const Real ml = liquid.mass[I], vol = nodal_volume<D>(liquid, I, drag_per_mass, rho_l);
    if (ml > 0 && vol > 0 && solid.mass[I] > 0) {
      const Real nS = liquid.mass_mix[I] / ml;
      Real qa = 0;
      for (int d = 0; d < D; ++d)
        qa += nS * (liquid.velocity_new[d][I] - solid.velocity_new[d][I]) * liquid.area[d][I];
      const Real dt = control->dt[parity];
      if (qa != 0) atomic_add(totals, -dt * (ml / vol) * qa, serial);
    }
    for (int d = 0; d < D; ++d) {
      liquid.gradient[d][I] = 0;
      liquid.area[d][I] = 0;
    }
    liquid.pressure[I] = 0;
  }
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
};

}  // namespace scree

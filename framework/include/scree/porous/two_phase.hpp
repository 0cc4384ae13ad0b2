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
//       Q = sum N V n S_l mu_l / (kappa k_rel)
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
  Real* drag;             ///< Q [kg/s]
  Real* velocity[D];      ///< v_l^k [m/s]
  Real* velocity_new[D];  ///< v_l^{k+1} [m/s]
  Real* gradient[D];      ///< sum (m_s + m_lm) grad N [kg/m], the mixture density's (eq. A)
  Real* area[D];          ///< sum V grad N [m^2 per unit thickness]: the surface's share, int N n dGamma
  Real* pressure;         ///< sum N V p_w [Pa m^3]; over `volume`: the nodal pore pressure
  Real* volume;           ///< sum N V [m^3]
};
template <int D>
inline constexpr int kLiquidFieldCount = 5 + 6 * D;

/// Whether node I of a grid is on a surface of the points: among the cells around it, one
/// is empty and one holds points (`cells`: points per cell, cell (i, j) at i + j n_x).
/// Cells beyond the grid are empty. With `walls`, the cells behind a contact wall acting at
/// the node (on the side its normal points away from) count as neither: the wall is a
/// plane of symmetry of the soil it holds, not a surface of it (the sides of a column
/// between slip walls are no surface; its top nodes at the walls are).
template <int D>
SCREE_INLINE bool surface_node(const GridGeometry<D>& grid, const Real* cells, Index I, const Wall* walls = nullptr,
                               WallMask mask = 0, Real t = 0) {
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
#if defined(__CUDA_ARCH__)
      const Wall& w = walls[__ffs(static_cast<int>(m)) - 1];
#else
      const Wall& w = walls[__builtin_ctz(m)];
#endif
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
  return empty && full;
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
  while (mask) {
#if defined(__CUDA_ARCH__)
    const int b = __ffs(static_cast<int>(mask)) - 1;
#else
    const int b = __builtin_ctz(mask);
#endif
    mask &= mask - 1;
    const Wall& w = walls[b];
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
  Real* extra = nullptr;    ///< the body's extra columns (PoreColumn order)
  int n_laws = 0;
  PorePressureLaw laws[kMaxPorePressureLaws];
  int vertical = 1;         ///< the axis opposite to gravity
  Real g = 0;               ///< |g| [m/s^2]
  /// The nodal liquid mass balance (PoreRate, PorePressure): sum N V r_p [m^3/s] and
  /// sum N V C_p [m^3/Pa]; not alternating: the grid update clears them.
  Real* inflow = nullptr;
  Real* capacity = nullptr;
  /// Cumulative liquid mass [kg] since t = 0: [0] through the surfaces (SurfaceInflow),
  /// [1] added by the prescribed pore pressures. Null: not counted.
  Real* totals = nullptr;
};

namespace detail {
SCREE_INLINE Real clamp01(Real x, Real lo, Real hi) { return x < lo ? lo : (x > hi ? hi : x); }
}  // namespace detail

/// The pore pressure. The liquid mass balance (top of file) holds per node, not per point:
///   C_I dp_I/dt = sum_p N_Ip V_p r_p,   C_I = sum_p N_Ip V_p C_p,
///   r_p = -(S_l div v_s + div q) at the point,
/// and each point takes the nodal rate, dp_p = dt sum_I N_Ip dp_I/dt. Integrated per point,
/// the pressure has a null mode: equal and opposite values between the rows of points of a
/// cell give no nodal force (V p grad N cancels), so nothing resists them, and where the
/// soil is saturated (C smallest) they grow into an odd-even pattern of the seepage. The
/// nodal balance removes it: a point's pressure changes only by what the nodes carry. The
/// rate is projected, not p itself, so the answer does not depend on the number of steps,
/// and sum_p V_p C_p dp_p = dt sum_p V_p r_p: the liquid's volume is kept.
///
/// Two passes at the points' positions x^k, before the solid pass moves them: PoreRate (the
/// liquid velocity's G2P and r_p into the nodes), then PorePressure (p_w, the prescribed
/// pore pressures, S_l(p_w)).
template <int D, class Shape>
struct PoreRate {
  PassParams<D> pp;        ///< the solid pass's (grid, sets, control, PIC fraction)
  PorePassParams<D> lp;
  ParticleArrays<D> pa;
  Shape shape;

  SCREE_INLINE Real& col(int c, Index p) const { return lp.extra[static_cast<std::size_t>(c) * pa.n + p]; }

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
    const Real a = pp.pic_fraction;
    for (int d = 0; d < D; ++d) col(kLiquidVelocity + d, p) = a * vpic[d] + (1 - a) * (vl[d] + dv[d]);
    const Real n = col(kPorosity, p), S = col(kSaturation, p), pw = col(kPorePressure, p);
    // The volume at x^k from the porosity the last scatter wrote: J = (1 - n0) / (1 - n).
    const Real V = pa.volume0[p] * (1 - lp.pore.n0) / (1 - n);
    const Real r = -(S * div_s + div_q) * V, c = lp.pore.storage(n, S, pw) * V;
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I;
      Real N;
      Vec<D> gradN, dx;
      st.node(k, pp.grid, x, I, N, gradN, dx);
      if (N == 0) continue;
      atomic_add(lp.inflow + I, N * r, pp.serial);
      atomic_add(lp.capacity + I, N * c, pp.serial);
    }
  }
};

/// The pore pressure from the nodal rates (PoreRate), then the prescribed pore pressures,
/// and S_l(p_w).
template <int D, class Shape>
struct PorePressure {
  PassParams<D> pp;
  PorePassParams<D> lp;
  ParticleArrays<D> pa;
  Shape shape;

  SCREE_INLINE Real& col(int c, Index p) const { return lp.extra[static_cast<std::size_t>(c) * pa.n + p]; }

  SCREE_HD void operator()(Index p) const {
    if (!(pa.volume0[p] >= 0)) return;  // frozen
    const Real dt = pp.control->dt[pp.gather_parity];
    const Real t = pp.control->t[pp.gather_parity];
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = pa.x[d][p];
    Real pw = col(kPorePressure, p);
    if (dt > 0) {
      const detail::Stencil<D, Shape> st(shape, pp.grid, x);
      if (st.inside) {
        Real rate = 0;
        for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
          Index I;
          Real N;
          Vec<D> gradN, dx;
          st.node(k, pp.grid, x, I, N, gradN, dx);
          const Real c = lp.capacity[I];
          if (N != 0 && c > 0) rate += N * lp.inflow[I] / c;
        }
        pw += dt * rate;
      }
    }
    // Prescribed pore pressures (water table, ponding, drained boundaries).
    const Real p_free = pw;
    for (int i = 0; i < lp.n_laws; ++i) {
      const PorePressureLaw& L = lp.laws[i];
      if (t < L.t_start || t >= L.t_end) continue;
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && x[d] >= L.lo[d] && x[d] <= L.hi[d];
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

/// The liquid's scatter (after the solid pass; weights at x_p^{k+1}): porosity from J,
/// the liquid's nodal fields, and the pore pressure's share of the mixture force,
/// V S_l p_w grad N + N m_lm g, into the solid's force.
template <int D, class Shape>
struct PoreScatter {
  PassParams<D> pp;
  PorePassParams<D> lp;
  ParticleArrays<D> pa;
  Shape shape;

  SCREE_INLINE Real& col(int c, Index p) const { return lp.extra[static_cast<std::size_t>(c) * pa.n + p]; }

  SCREE_HD void operator()(Index p) const {
    if (!(pa.volume0[p] >= 0)) return;
    Vec<D> x, vs, vl;
    for (int d = 0; d < D; ++d) {
      x[d] = pa.x[d][p];
      vs[d] = pa.v[d][p];
      vl[d] = col(kLiquidVelocity + d, p);
    }
    Mat<D> F;
    for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
    const Real J = det(F);
    const Real V = pa.volume0[p] * J;
    const Real n = detail::clamp01(1 - (1 - lp.pore.n0) / J, Real(1e-3), Real(0.999));
    const Real S = col(kSaturation, p), pw = col(kPorePressure, p);
    col(kPorosity, p) = n;
    for (int d = 0; d < D; ++d) col(kSeepage<D> + d, p) = n * S * (vl[d] - vs[d]);
    const Real rho_l = lp.pore.rho_l;
    const Real m_lm = n * S * rho_l * V, m_l = rho_l * V, m_s = pa.mass[p];
    const Real krel = lp.pore.table.relative_permeability(S);
    const Real q = V * n * S * lp.pore.viscosity / (lp.pore.kappa * (krel > 1e-300 ? krel : Real(1e-300)));

    const detail::Stencil<D, Shape> st(shape, pp.grid, x);
    if (!st.inside) return;  // the solid pass froze it
    if (lp.cells) {
      int c[D];
      Index cell = 0, stride = 1;
      for (int d = 0; d < D; ++d) {
        c[d] = static_cast<int>(floor((x[d] - pp.grid.origin[d]) / pp.grid.h));
        cell += c[d] * stride;
        stride *= pp.grid.n[d];
      }
      atomic_add(lp.cells + cell, Real(1), pp.serial);
    }
    const bool serial = pp.serial;
    for (int k = 0; k < detail::Stencil<D, Shape>::kNodes; ++k) {
      Index I;
      Real N;
      Vec<D> gradN, dx;
      st.node(k, pp.grid, x, I, N, gradN, dx);
      if (N == 0) continue;
      atomic_add(lp.scatter.mass + I, N * m_l, serial);
      atomic_add(lp.scatter.mass_mix + I, N * m_lm, serial);
      atomic_add(lp.scatter.drag + I, N * q, serial);
      for (int d = 0; d < D; ++d) {
        atomic_add(lp.scatter.momentum[d] + I, N * m_l * vl[d], serial);
        atomic_add(lp.scatter.force[d] + I, V * pw * gradN[d] + N * m_l * pp.gravity[d], serial);
        atomic_add(pp.scatter.force[d] + I, V * S * pw * gradN[d] + N * m_lm * pp.gravity[d], serial);
        atomic_add(lp.scatter.gradient[d] + I, (m_s + m_lm) * gradN[d], serial);
        atomic_add(lp.scatter.area[d] + I, V * gradN[d], serial);
      }
      atomic_add(lp.scatter.pressure + I, N * V * pw, serial);
      atomic_add(lp.scatter.volume + I, N * V, serial);
    }
    // The pore liquid's signal speed (undrained, the mixture's inertia): c^2 = S_l^2 /
    // (C rho_mix) with the storage C = n S_l / K_l + n dS_l/dp (K_l / (n rho_mix) when
    // saturated), plus |v_l|. The step takes the larger of it and the skeleton's.
    if (pp.need_speed && V > 0) {
      const Real C = lp.pore.storage(n, S, pw);
      const Real rho_mix = (m_s + m_lm) / V;
      const Real c = sqrt(S * S / (C * rho_mix)) + norm(vl);
      atomic_max_nonneg(&pp.control->max_speed[pp.parity], c, serial);
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
  Real* inflow = nullptr;       ///< the nodal liquid mass balance (PorePassParams; cleared)
  Real* capacity = nullptr;
  Index n_cells = 0;
  StepControl* control = nullptr;
  int parity = 0;
  const Wall* walls = nullptr;
  const WallMask* masks = nullptr;
  const WallMask* liquid_masks = nullptr;  ///< the walls the liquid cannot cross
  const Real* cells = nullptr;             ///< this step's points per cell (surface nodes)
  const std::uint32_t* open_masks = nullptr;  ///< per node: the open surfaces selecting it
  OpenSurfaceWindow open[kMaxOpenSurfaces];   ///< their time windows
  Real mass_eps = 0;
  Real damping = 0, damping_start = 0, damping_end = 0;

  SCREE_HD void operator()(Index I) const {
    if (I == 0) advance_clock(control, parity);
    if (I < n_cells && cells_other) cells_other[I] = 0;
    if (inflow) {
      inflow[I] = 0;
      capacity[I] = 0;
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
      solid.velocity[d][I] = vs[d];
      liquid.velocity[d][I] = vl[d];
    }
    Real ws[D], wl[D], fls[D];
    const bool damp = damping > 0 && t >= damping_start && t < damping_end;
    const Real Q = liquid.drag[I];
    // The liquid's boundary term. The weak form of -grad p_w on the points' domain carries
    // -int N p_b n dGamma; left out, it makes every surface p_b = 0: open, the liquid enters
    // or leaves as the pore pressure drives it (ponding, a drained face). A surface is closed
    // unless a condition opens it: there p_b is the nodal pore pressure itself, with
    // int N n dGamma = sum V grad N (the divergence theorem), so that no flow is driven
    // through it (the rainfall and ponding conditions open theirs). A closed node's seepage
    // along the normal is then also set to zero after the integration.
    Real boundary[D] = {};
    bool closed = false;  // a closed surface node: no seepage through it (below)
    if (cells && ml > 0 && surface_node<D>(grid, cells, I, walls, mask, t)) {
      bool is_open = (mask & ~lmask) != 0;  // on a drained wall
      for (std::uint32_t m = open_masks ? open_masks[I] : 0u; m; m &= m - 1) {
#if defined(__CUDA_ARCH__)
        const int b = __ffs(static_cast<int>(m)) - 1;
#else
        const int b = __builtin_ctz(m);
#endif
        is_open = is_open || (t >= open[b].t_start && t < open[b].t_end);
      }
      const Real vol = liquid.volume[I];
      closed = !is_open;
      if (!is_open && vol > 0) {
        const Real pb = liquid.pressure[I] / vol;
        for (int d = 0; d < D; ++d) boundary[d] = -pb * liquid.area[d][I];
      }
    }
    for (int d = 0; d < D; ++d) {
      Real fm = solid.force[d][I], fl = liquid.force[d][I] + boundary[d];
      fls[d] = 0;
      if (damp) {
        if (vs[d] != 0) fm -= damping * fabs(fm) * (vs[d] > 0 ? Real(1) : Real(-1));
        if (vl[d] != 0) fl -= damping * fabs(fl) * (vl[d] > 0 ? Real(1) : Real(-1));
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
    if (mask) {
      apply_walls<D>(walls, mask, ws, x, t);
      // A wall held the solid: its reaction is not in F_mix, so the coupled solve dragged the
      // liquid along with a solid motion that did not happen. The liquid again, against the
      // solid velocity the wall left: M_l dl = dt [F_l - Q (v_l + dl - v_s^{k+1})].
      if (ms > mass_eps && ml > 0)
        for (int d = 0; d < D; ++d) wl[d] = vl[d] + dt * (fls[d] - Q * (vl[d] - ws[d])) / (ml + dt * Q);
    }
    if (lmask) apply_walls<D>(walls, lmask, wl, x, t);
    if (closed && ms > mass_eps) {
      // A closed surface node: no flow through it: the seepage along the outward normal set to zero,
      // the mixture's momentum kept (seepage_correction with w = 0, unconditionally).
      Real grad[D];
      const Real w0[D] = {};
      for (int d = 0; d < D; ++d) grad[d] = liquid.gradient[d][I];
      if (mask) project_on_walls<D>(walls, mask, t, grad);
      if (seepage_correction<D>(grad, ms, ml, mlm, w0, ws, wl, false)) {
        if (mask) apply_walls<D>(walls, mask, ws, x, t);  // the walls have the last word
        if (lmask) apply_walls<D>(walls, lmask, wl, x, t);
      }
    }
    for (int d = 0; d < D; ++d) {
      solid.velocity_new[d][I] = ws[d];
      liquid.velocity_new[d][I] = wl[d];
    }
    // The next step's P2G adds into the other sets.
    solid_other.mass[I] = 0;
    liquid_other.mass[I] = 0;
    liquid_other.mass_mix[I] = 0;
    liquid_other.drag[I] = 0;
    for (int d = 0; d < D; ++d) {
      solid_other.momentum[d][I] = 0;
      solid_other.force[d][I] = 0;
      liquid_other.momentum[d][I] = 0;
      liquid_other.force[d][I] = 0;
      liquid_other.gradient[d][I] = 0;
      liquid_other.area[d][I] = 0;
    }
    liquid_other.pressure[I] = 0;
    liquid_other.volume[I] = 0;
  }
};

/// The liquid mass that entered through the surfaces in the step just integrated (after the
/// hydraulic node laws), added to totals[0]: at a surface node I, -dt rho_l q_I . a_I with
/// q_I = (M_lm / M_l)(v_l - v_s) the nodal seepage and a_I = sum V grad N = int N n dGamma
/// (outward n, the divergence theorem), rho_l = M_l / sum N V. Interior nodes carry no
/// boundary, so what the points' storage gains beyond this sum is the discretisation's
/// imbalance (the water-balance function object reports it).
template <int D>
struct SurfaceInflow {
  GridGeometry<D> grid;
  GridFields<D> solid;
  LiquidFields<D> liquid;
  const Real* cells = nullptr;
  const StepControl* control = nullptr;
  int parity = 0;
  Real* totals = nullptr;
  bool serial = false;

  SCREE_HD void operator()(Index I) const {
    const Real ml = liquid.mass[I], vol = liquid.volume[I];
    if (!(ml > 0) || !(vol > 0) || !(solid.mass[I] > 0) || !surface_node<D>(grid, cells, I)) return;
    const Real nS = liquid.mass_mix[I] / ml;
    Real qa = 0;
    for (int d = 0; d < D; ++d)
      qa += nS * (liquid.velocity_new[d][I] - solid.velocity_new[d][I]) * liquid.area[d][I];
    const Real dt = control->dt[parity];
    if (qa != 0) atomic_add(totals, -dt * (ml / vol) * qa, serial);
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

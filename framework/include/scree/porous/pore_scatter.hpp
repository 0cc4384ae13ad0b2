// The two-phase bodies' P2G (porous/two_phase.hpp): both phases' nodal sums in one pass
// after the solid pass, then the fields read only at the surface nodes.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/stencil.hpp"
#include "scree/porous/pore_pass.hpp"
#include "scree/time/step_control.hpp"

namespace scree {

namespace detail {
SCREE_INLINE Real clamp01(Real x, Real lo, Real hi) { return x < lo ? lo : (x > hi ? hi : x); }
}  // namespace detail

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
///     (porous/two_phase.hpp), added as one value per node and axis,
///   the liquid: porosity from J, M_l, M_lm, the drag and conductance sums, the liquid
///     momentum, F_l = V p_w grad N + N m_l g, sum N V, and sum V grad N at every node (the
///     surface's share where the node is on it; PoreRate's divergence correction elsewhere),
/// and the volume the points fill in each cell. The fields read only at surface nodes follow in
/// SurfaceScatter.
/// One pass for both phases builds the stencil and the warp's runs once, and the mixture
/// force takes one atomic per node and axis where a solid scatter and a separate liquid
/// pass would take two.
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
    const bool apic = pp.physics.transfer == Transfer::apic;
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
    const bool serial = pp.policy.serial;
    // The cells' filling: sum V_p / h^D over the points in each cell, the volume fraction the
    // points fill (surface_node reads it; 1 inside the soil, 0 in an empty cell).
    Real inv_cell = 1;
    for (int d = 0; d < D; ++d) inv_cell /= pp.grid.h;
    const Real fill = V * inv_cell;
#if defined(__CUDA_ARCH__)
    const WarpSegment seg(active ? static_cast<long long>(pp.grid.flat(st.base))
                                 : -1 - static_cast<long long>(threadIdx.x));
    if (lp.cells) {
      // The lanes of one cell (sorted points share it: a run of lanes) add their volumes in
      // one atomic (one per point would serialise on a few addresses per warp).
      const long long cell = active ? static_cast<long long>(cell_of<D>(pp.grid, x)) : -1 - static_cast<long long>(threadIdx.x);
      const WarpSegment run(cell);
      const Real sum = run.sum(active ? fill : Real(0));
      if (active && run.head && sum != 0) atomic_add(lp.cells + cell, sum, serial);
    }
#else
    const WarpSegment seg(0);
    if (active && lp.cells && fill != 0) atomic_add(lp.cells + cell_of<D>(pp.grid, x), fill, serial);
#endif
    auto add = [&](Real* field, Real value) {
#if defined(__CUDA_ARCH__)
      const Real sum = seg.sum(value);
      if (active && seg.head && sum != 0) atomic_add(field, sum, serial);
#else
      if (active && value != 0) atomic_add(field, value, serial);
#endif
    };
    for_each_stencil_node(st, pp.grid, x, active, [&](Index I, Real N, const Vec<D>& gradN, const Vec<D>& dx) {
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
        add(pp.scatter.force[d] + I, -V * s + N * (m_s + m_lm) * pp.physics.gravity[d]);
        add(lp.scatter.momentum[d] + I, N * m_l * vl[d]);
        add(lp.scatter.force[d] + I, V * pw * gradN[d] + N * m_l * pp.physics.gravity[d]);
        add(lp.scatter.area[d] + I, V * gradN[d]);
      }
    });
    // The pore liquid's signal speed (undrained, the mixture's inertia): c^2 = S_l^2 /
    // (C rho_mix) with the storage C = n S_l / K_l + n dS_l/dp (K_l / (n rho_mix) when
    // saturated), plus |v_l|. The step takes the larger of it and the skeleton's.
    if (active && speed_wanted(pp) && V > 0) {
      const Real Cs = lp.pore.storage(n, S, pw);
      const Real rho_mix = (m_s + m_lm) / V;
      const Real c = sqrt(S * S / (Cs * rho_mix)) + norm(vl);
      // One global address for every point: read it first, and only a larger speed takes
      // the atomic (after the first warps, almost none): unconditional, every point's atomic
      // on the one word would serialise the pass.
      if (c > *static_cast<const volatile Real*>(&pp.control->max_speed[pp.parity]))
        atomic_max_nonneg(&pp.control->max_speed[pp.parity], c, serial);
    }
  }
};

/// The liquid's nodal fields read at surface nodes alone, added only into the nodes
/// SurfaceMask marked, by the points whose stencil reaches one: added by every point in
/// MixtureScatter, they would be atomics for nodes that are never read. Weights at x^{k+1},
/// as MixtureScatter's.
/// - The closed surface's p_b: sum N V p_w.
/// - The pond (PorePassParams::ponds): the water standing on the surface, which the points
///   near it carry between steps (PoreRate gathers it back), returns to the surface nodes
///   that can hold it, those whose share of the surface faces up inside the region of a
///   condition that keeps a pond: point p gives node I the share w_I / sum_J w_J of its pond,
///   w_I = N_I max(0, a_I . up) over such marked nodes (a_I = sum V grad N, this step's).
///   The shares add up to the point's pond, so the pond is kept whole; a point whose reach
///   holds no such node (the surface it stood on was covered, turned away, or moved out of
///   the rain's region) lets its pond run off (totals[4]).
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
    const Real pond = active && lp.ponds ? col(kPond<D>, p) : Real(0);
    Real level_sum = 0;  // sum_J w_J over the marked nodes facing up
    auto level = [&](Index I) {  // w_I / N_I
      if (!lp.open_masks || !(lp.open_masks[I] & lp.pond_bits)) return Real(0);
      const Real l = level_share<D>(lp.scatter, I, lp.up);
      return l > 0 ? l : Real(0);
    };
    for_each_stencil_node(st, pp.grid, x, active, [&](Index I, Real N, const Vec<D>&, const Vec<D>&) {
      const bool marked = active && lp.surface[I] != 0;
      touches = touches || marked;
      if (marked && pond > 0) level_sum += N * level(I);
    });
    if (pond > 0 && !(level_sum > 0) && lp.totals) atomic_add(lp.totals + 4, pond, pp.policy.serial);  // runs off
#if defined(__CUDA_ARCH__)
    if (!__any_sync(0xffffffffu, touches)) return;  // the whole warp inside the soil (uniform)
#endif
    active = active && touches;
    const Real pond_per_level = level_sum > 0 ? pond / level_sum : Real(0);
    Real V = 0, pw = 0;
    if (active) {
      Mat<D> F;
      for (int i = 0; i < D * D; ++i) F.a[i / D][i % D] = pa.F[i][p];
      V = pa.volume0[p] * det(F);
      pw = col(kPorePressure, p);
    }
    const bool serial = pp.policy.serial;
#if defined(__CUDA_ARCH__)
    const WarpSegment seg(active ? static_cast<long long>(pp.grid.flat(st.base))
                                 : -1 - static_cast<long long>(threadIdx.x));
#else
    const WarpSegment seg(0);
#endif
    for_each_stencil_node(st, pp.grid, x, active, [&](Index I, Real N, const Vec<D>&, const Vec<D>&) {
      const bool mine = active && lp.surface[I] != 0;  // the same node for a whole run of lanes
#if !defined(__CUDA_ARCH__)
      if (!mine || N == 0) return;
#endif
      auto add = [&](Real* field, Real value) {
#if defined(__CUDA_ARCH__)
        const Real sum = seg.sum(mine ? value : Real(0));
        if (mine && seg.head && sum != 0) atomic_add(field, sum, serial);
#else
        if (mine && value != 0) atomic_add(field, value, serial);
#endif
      };
      add(lp.scatter.pressure + I, N * V * pw);
      if (lp.ponds) add(lp.scatter.pond + I, N * pond_per_level * level(I));
    });
  }
};

}  // namespace scree

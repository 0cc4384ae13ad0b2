// The free surface of the two-phase bodies' points (porous/two_phase.hpp): which nodes lie
// on it, the seepage through it (closed, open, or set by rain), and the walls' share in its
// normal.
#pragma once

#include <cstdint>

#include "scree/core/config.hpp"
#include "scree/core/constants.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/wall_law.hpp"

namespace scree {

/// The surface normal at a node that walls hold lies in the walls' planes. A contact wall
/// (slip, friction) is a plane of symmetry of the soil it holds: mirrored across it, the
/// soil has no surface along the wall's normal. Without a mirror the points stop at the
/// wall, and sum V grad N tilts the normal towards it: at the top nodes of a
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

/// The share of a fully exposed node's surface from which a node whose cells all hold points
/// is on the surface (surface_node), if an empty cell lies within a cell of its own. One
/// point's filling missing from one of its cells (1/n^D of a cell, n points per axis) gives a
/// node an exposure of sqrt(D) / (n^D 2^(D-1)): 0.18 in 2D and 0.054 in 3D at n = 2, 0.079
/// in 2D at n = 3; a node half a cell below a level surface has 0.5. Below all of them, and
/// above a uniform compression's (J - 1 across the node's cells, 0.05 at 5%).
inline constexpr Real kSurfaceExposure = Real(0.05);

/// Whether node I of a grid is on a surface of the points (`cells`: the volume fraction of
/// each cell the points fill, cell (i, j) at i + j n_x):
/// - among the cells around it, one is empty and one holds points, or, with `has_mass` (the
///   node has mass), one is empty and none holds points; or
/// - its cells all hold points but the surface crosses them: the node's exposure
///   |sum_c phi_c s_c| / 2^(D-1) is at least `exposure` (kSurfaceExposure), phi_c in [0, 1]
///   the cells' filling and s_c in {-1, 1}^D the direction from cell c's centre to the node,
///   and an empty cell of the grid lies within one cell of the node's cells (its 4^D block):
///   inside the soil, a point that crossed into another cell leaves a node an exposure as
///   large as a face's smallest (0.18 in 2D at n = 2), but no empty cell near it.
///   It is the cells' estimate of the node's share of the surface, a_I = sum_p V_p grad N_I(x_p)
///   = int N_I n dGamma: with bilinear N_I the mean of grad N_I over cell c is
///   s_c / (2^(D-1) h), so a filled fraction phi_c of the cell adds phi_c h^(D-1) s_c / 2^(D-1),
///   and the exposure is |a_I| / h^(D-1): 1 at a node of a level surface whose lower cells
///   are full, 0 inside the soil, independent of h. Such a node, left off the surface, has
///   neither the closed surface's condition nor the rain's, and acts as an open surface at
///   p_w = 0 (the weak form's natural condition): suction draws liquid in through it.
/// Cells beyond the grid are empty. With `walls`, the cells behind a contact wall acting at
/// the node (on the side its normal points away from) count as neither: the wall is a
/// plane of symmetry of the soil it holds, not a surface of it (the sides of a column
/// between slip walls are no surface; its top nodes at the walls are). The exposure then
/// sums the cells in front of the walls, projected on the walls' planes (project_on_walls)
/// and scaled by 2^D over their number: the mirror images of the cells in front.
/// The `has_mass` case: a node whose cells hold no point but which has mass takes it from points
/// of the cells beyond, through shape functions wider than a cell (a GIMP point's domain
/// reaching past the cell of its centre, a B-spline's kernel). The body's boundary, the edge
/// of those domains, then crosses the node's support: the node is on the surface as much as
/// the node below it, and its liquid needs the surface's condition (closed, or the rain's
/// seepage). Without this second case such a node, with mass but off the surface, is neither
/// closed nor corrected by the rain: an open surface at p_w = 0 a fraction of a cell from
/// points in suction, whose share of div q at those points, n S_l (v_l - v_s) grad N, does not
/// shrink with the overlap (grad N^2 / N = 1 / (l_p h^2) for uGIMP), pumps liquid into the top
/// cell (cases/infiltration1D/README.md, "The soft skeleton under rain").
template <int D>
SCREE_INLINE bool surface_node(const GridGeometry<D>& grid, const Real* cells, Index I, const Wall* walls = nullptr,
                               WallMask mask = 0, Real t = 0, bool has_mass = false,
                               Real exposure = kSurfaceExposure, Real* direction = nullptr) {
  int idx[D];
  grid.unflat(I, idx);
  bool empty = false, full = false;
  Real a[D] = {};
  int in_front = 0;
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
    ++in_front;
    if (!ok) {
      empty = true;  // beyond the grid: nothing there
      continue;
    }
    const Real phi = cells[cell];
    (phi > 0 ? full : empty) = true;
    const Real f = phi < 1 ? phi : Real(1);
    for (int d = 0; d < D; ++d) a[d] += ((c >> d) & 1) ? -f : f;  // s_c: from the cell's centre to the node
  }
  if (empty) return full || has_mass;
  if (!full || !(exposure > 0)) return false;
  if (walls && mask) project_on_walls<D>(walls, mask, t, a);
  Real a2 = 0;
  for (int d = 0; d < D; ++d) a2 += a[d] * a[d];
  const Real scale = Real((1 << D) / 2) * Real(in_front) / Real(1 << D);  // 2^(D-1), for the cells in front
  if (a2 < (exposure * scale) * (exposure * scale)) return false;
  for (int c = 0; c < (1 << (2 * D)); ++c) {  // an empty cell of the grid in the 4^D block
    Index cell = 0, stride = 1;
    bool ok = true;
    for (int d = 0; d < D; ++d) {
      const int j = idx[d] - 2 + ((c >> (2 * d)) & 3);
      ok = ok && j >= 0 && j < grid.n[d] - 1;
      cell += j * stride;
      stride *= grid.n[d];
    }
    if (ok && !(cells[cell] > 0)) {
      if (direction)
        for (int d = 0; d < D; ++d) direction[d] = a[d];
      return true;
    }
  }
  return false;
}

/// The open surfaces (bits of `open_masks`, by node) that hold at a node on the surface by its
/// exposure alone (surface_node's `direction` a, nonzero): those of the nodes next to it
/// towards the surface, I + k with k_d in {0, sign(a_d)}. The face crosses such a node's
/// support between it and those nodes, which the selection by node position sees on the
/// surface (the empty and filled cells around them): a level top that settled a third of a
/// cell below a node row leaves the row under it an exposure of 0.3 (0.5 once a row of points
/// crossed down), with the open surface's box drawn around the top row. Its condition is the
/// surface's: opened with it, p_w = 0 there as at the node above; closed, it would stop the
/// flow along a (seepage along the normal set to zero) one node row inside the drained soil.
template <int D>
SCREE_INLINE std::uint32_t exposed_open_masks(const GridGeometry<D>& grid, const std::uint32_t* open_masks, Index I,
                                             const Real* direction) {
  if (!open_masks) return 0u;
  int idx[D];
  grid.unflat(I, idx);
  std::uint32_t m = open_masks[I];
  for (int k = 1; k < (1 << D); ++k) {
    int j[D];
    bool ok = true;
    for (int d = 0; d < D; ++d) {
      const int step = (k >> d) & 1 ? (direction[d] > 0 ? 1 : direction[d] < 0 ? -1 : 0) : 0;
      ok = ok && ((k >> d) & 1 ? step != 0 : true);
      j[d] = idx[d] + step;
      ok = ok && j[d] >= 0 && j[d] < grid.n[d];
    }
    if (ok) m |= open_masks[grid.flat(j)];
  }
  return m;
}

/// The seepage through a surface node set to w . n (w: a prescribed seepage velocity, e.g.
/// rain; n = grad / |grad| the outward normal, grad the node's share of the surface
/// sum V grad N, the flux through which SurfaceInflow counts: boundary/rainfall says why not
/// the seed's mixture-density weighting of eq. A), keeping the mixture's momentum (the
/// rainfall paper's supplement, eqs. C-E). With `only_if_more` the correction applies only
/// where the soil would take at least w (eq. B). Returns whether it was applied.
template <int D>
SCREE_HD inline bool seepage_correction(const Real* grad, Real ms, Real ml, Real mlm, const Real* w, Real* vs,
                                        Real* vl, bool only_if_more) {
  Real g2 = 0;
  for (int d = 0; d < D; ++d) g2 += grad[d] * grad[d];
  if (!(g2 > 0) || !(ml > 0) || !(mlm > 0) || !(ms > 0)) return false;
  const Real inv = 1 / sqrt(g2);
  Real n[D];
  for (int d = 0; d < D; ++d) n[d] = grad[d] * inv;
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

/// An open stretch of surface (ponding, rain): the pore liquid there has the natural
/// condition of the weak form, p_w = 0. Elsewhere a surface is closed (TwoPhaseGridUpdate);
/// the kernels' copy of an OpenSurface (porous/hydraulic_condition.hpp): its time window.
inline constexpr int kMaxOpenSurfaces = 16;
struct OpenSurfaceWindow {
  Real t_start = -kUnbounded, t_end = kUnbounded;
  int outflow_only = 0;  ///< a seepage face: open only where the nodal p_w >= 0
};

/// Which nodes lie on a surface of the points (surface_node, without the walls and with the
/// node's mass of either phase: a superset of the nodes any hydraulic law treats as
/// surface), from this step's cell filling, for SurfaceScatter, the grid update and
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
    // Half the exposure: the test with walls mirrors the cells in front of them, and finds
    // at most twice the exposure found without them.
    surface[I] = surface_node<D>(grid, cells, I, nullptr, 0, 0, has_mass, kSurfaceExposure / 2) ? 1 : 0;
  }
};

}  // namespace scree

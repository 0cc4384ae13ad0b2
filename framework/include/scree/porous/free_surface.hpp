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
/// seepage). Without this second case such a node, with mass but off the surface, is neither
/// closed nor corrected by the rain: an open surface at p_w = 0 a fraction of a cell from
/// points in suction, whose share of div q at those points, n S_l (v_l - v_s) grad N, does not
/// shrink with the overlap (grad N^2 / N = 1 / (l_p h^2) for uGIMP), pumps liquid into the top
/// cell (cases/infiltration1D/README.md, "The soft skeleton under rain").
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
/// condition of the weak form, p_w = 0. Elsewhere a surface is closed (TwoPhaseGridUpdate);
/// the kernels' copy of an OpenSurface (porous/hydraulic_condition.hpp): its time window.
inline constexpr int kMaxOpenSurfaces = 16;
struct OpenSurfaceWindow {
  Real t_start = -kUnbounded, t_end = kUnbounded;
  int outflow_only = 0;  ///< a seepage face: open only where the nodal p_w >= 0
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

}  // namespace scree

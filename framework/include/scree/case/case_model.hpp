// The case model: what the typed settings of a case give, derived once, for `scree
// --check` (setup_check.hpp), the memory estimate (memory_estimate.hpp) and the run
// alike, so that the three cannot drift apart.
//
//   GlobalGrid<D> g = grid_geometry<D>(c.settings().grid);  // the background grid
//   GridGeometry<D> part = g.sub_box(lo, hi);              // the grid of cells [lo, hi)
//   SolverContext ctx = plugin_context(c, g, device);      // what plugins learn
//
// The grid is the domain of system/gridDict extended to whole cells, with `ghostLayers`
// layers of nodes around it (mpm/grid.hpp). A run owns all of it today; a domain
// decomposition gives each part its own owned range and builds the part's grid with
// sub_box().
#pragma once

#include "scree/case/case.hpp"
#include "scree/exec/memory.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/plugin/context.hpp"

namespace scree {

/// The nodal fields of one grid set (GridFields<D>): the mass and D components each of
/// the momentum, the force, the velocity and the updated velocity.
template <int D>
inline constexpr int kGridFieldCount = 1 + 4 * D;

/// The cells the domain [lower, upper] spans along one axis at cell size h: its extent
/// in cells rounded up to a whole number (kWholeCellTolerance: an extent a rounding error
/// over a whole number of cells is that number). A double, so that the memory estimate
/// may ask it of a cell size whose grid would not fit an int.
SCREE_API double domain_cells(Real lower, Real upper, Real h);

/// Whether the domain's extent along an axis is a whole number of cells (otherwise the
/// grid extends it to the next whole cell, which the run warns about).
SCREE_API bool whole_cells(Real lower, Real upper, Real h);

/// A box of nodes of the global lattice: lo[d] <= i[d] < hi[d].
template <int D>
struct NodeRange {
  int lo[D];
  int hi[D];
  Index count() const {
    Index n = 1;
    for (int d = 0; d < D; ++d) n *= hi[d] - lo[d];
    return n;
  }
};

/// The global background grid of a case, with the nodes this run owns.
template <int D>
struct GlobalGrid : GridGeometry<D> {
  /// The nodes this run owns: the whole grid (a domain decomposition gives each part its
  /// own range).
  NodeRange<D> owned;
  /// The cells of the domain along each axis (the grid has cells + 1 + 2 ghost nodes).
  int cells[D];

  /// The grid of the domain's cells lo[d] <= c[d] < hi[d] (0: the domain's first cell),
  /// laid out as the global grid is around the whole domain: its nodes from lo to hi with
  /// `ghost` layers around them, `offset` its first node's index in the global lattice,
  /// `lower`/`upper` the part of the domain it covers. sub_box(0, cells) is the global grid.
  SCREE_API GridGeometry<D> sub_box(const int* lo, const int* hi) const;
};

/// The background grid of a case from its gridDict, owned whole.
template <int D>
SCREE_API GlobalGrid<D> grid_geometry(const GridSettings& grid);

/// What plugins (boundary conditions, writers, function objects) learn about the case
/// (plugin/context.hpp), on grid `g` and backend `device`; `name` is set per plugin.
template <int D>
SCREE_API SolverContext plugin_context(const Case& c, const GridGeometry<D>& g, Device device);

/// The context of the plugin instance named `name` (its dictionary key).
inline SolverContext named(SolverContext ctx, const std::string& name) {
  ctx.name = name;
  return ctx;
}

}  // namespace scree

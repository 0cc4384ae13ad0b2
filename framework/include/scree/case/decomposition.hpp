// The domain decomposition of a case over the ranks of a run (comm/comm.hpp): each rank
// owns a box of the grid's cells and holds the points inside it.
//
// The boxes are slabs cut on cell boundaries along one axis: the axis along which the
// points extend over the most cells, cut so that each slab holds about the same number of
// points (from the histogram of the points per cell layer, which every rank counts
// alike before any point is made; each rank then makes only the points of its box). A rank's grid is its box widened by `e_lo`/`e_hi` cells and
// the `ghost` node layers around it (GlobalGrid::sub_box): wide enough for the stencil of
// every point that lies up to `slack` cells outside its box, since points move between
// migrations (Solver: they migrate at the end of every chunk of steps). As the mass moves
// (a flume's down the chute) the cuts move with it: when the rank holding the most points
// holds more than kRebalanceRatio times the mean, the slabs are cut anew from the
// points' histogram (cut_slabs) and the points migrate to them. Neighbouring grids
// overlap in a slab of nodes; after each particle-to-grid transfer the two ranks add each
// other's partial sums on it (the halo sum), so that both hold the whole sum, bitwise
// equal (a + b = b + a), and the grid update runs on every local node alike.
//
// Shape functions (mpm/shape_functions.hpp): a point in cell c touches nodes c - a to
// c + b along an axis (node c: cell c's lower corner): linear a = 0, b = 1; GIMP and
// B-spline a = 1, b = 2.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scree/case/case_model.hpp"
#include "scree/mpm/schemes.hpp"

namespace scree {

/// The reach of a shape function along an axis (above): a point in cell c touches nodes
/// c - a to c + b.
inline void stencil_reach(ShapeKind s, int& a, int& b) {
  a = s == ShapeKind::linear ? 0 : 1;
  b = s == ShapeKind::linear ? 1 : 2;
}

/// The domain cell holding coordinate x along axis d, clamped into the domain (NaN: 0).
template <int D>
SCREE_API int domain_cell(const GlobalGrid<D>& g, int d, Real x);

/// The imbalance (most points on one rank over the mean) above which the cuts move.
inline constexpr double kRebalanceRatio = 1.15;

/// Cells a held point may lie outside its box between two migrations (the halo's slack).
inline constexpr int kSlackCells = 2;

template <int D>
struct Decomposition {
  int ranks = 1;
  int rank = 0;
  int axis = 0;            ///< the axis the slabs are cut across
  std::vector<int> cuts;   ///< ranks + 1 cell indices: rank r owns cells [cuts[r], cuts[r + 1]) along axis
  int slack = 0;           ///< cells a held point may lie outside its box between two migrations
  /// Every rank's grid (local[r]), in the global lattice: node i of local[r] is global node
  /// i + local[r].offset. The whole grid for one rank.
  std::vector<GridGeometry<D>> local;
  /// The global lattice's nodes each rank owns along axis: [owned[r], owned[r + 1]).
  std::vector<int> owned;

  bool decomposed() const { return ranks > 1; }
  const GridGeometry<D>& grid() const { return local[static_cast<std::size_t>(rank)]; }
  /// The rank owning a point at coordinate `x` along `axis` (outside the domain: the
  /// nearest box).
  SCREE_API int owner(Real x, const GlobalGrid<D>& g) const;
  /// The rank owning domain cell c along `axis` (domain_cell).
  SCREE_API int owner_of_cell(int c) const;
  /// This rank's owned nodes along axis, in local node indices: [lo, hi).
  SCREE_API void owned_local(int& lo, int& hi) const;
  /// The nodes this rank's grid shares with rank `peer` (a neighbour) along axis, in local
  /// node indices [lo, hi); empty (lo == hi) when they share none.
  SCREE_API void overlap(int peer, int& lo, int& hi) const;
};

/// The decomposition of grid `g` over `ranks` ranks for the points per cell layer along
/// every axis (layers[d][c]: the points in domain cell c along axis d, domain_cell), which
/// a run counts before it makes them, for a shape function of reach a, b (above) and
/// points `slack` cells outside their box at most. A single rank owns the whole grid.
/// Throws std::invalid_argument, saying how many ranks the grid allows, when a slab would
/// be too thin for its neighbours' halos not to meet.
template <int D>
SCREE_API Decomposition<D> decompose_layers(const GlobalGrid<D>& g, const std::array<std::vector<std::uint64_t>, D>& layers,
                                            int ranks, int rank, int a, int b, int slack);

/// The slabs across `axis` for the points per cell layer `layers` along it (a rebalance
/// keeps the axis and moves the cuts), as decompose_layers() cuts them.
template <int D>
SCREE_API Decomposition<D> cut_slabs(const GlobalGrid<D>& g, const std::vector<std::uint64_t>& layers, int axis,
                                     int ranks, int rank, int a, int b, int slack);

/// The slabs of the given cuts (ranks + 1 cell indices along `axis`): a restart takes up
/// its checkpoint's. Throws std::invalid_argument when they do not span the grid or a slab
/// is too thin for its halo.
template <int D>
SCREE_API Decomposition<D> slabs_from_cuts(const GlobalGrid<D>& g, int axis, const std::vector<int>& cuts, int rank,
                                           int a, int b, int slack);

}  // namespace scree

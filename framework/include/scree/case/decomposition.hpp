// The domain decomposition of a case over the ranks of a run (comm/comm.hpp): each rank
// owns a box of the grid's cells and holds the points inside it.
//
// The boxes come from recursive coordinate bisection, cut on cell boundaries: a box shared
// by n ranks is cut across the axis along which its points extend over the most cells, so
// that the lower part holds floor(n/2)/n of its points, and each part goes on to its share
// of the ranks (ranks in order, the lower part the lower ranks). Two ranks get two slabs; a
// long flume gets slabs on any number of ranks, a compact mass boxes. The counts come from
// the points' histograms per cell layer inside each box being cut: before any point is
// made, every rank counts the positions the generation would make, alike; at a rebalance,
// the ranks sum their points' histograms, one reduction per level of the tree. A rank's
// grid is its box widened by `e_lo`/`e_hi` cells within the domain, with the `ghost` node
// layers around it (GlobalGrid::sub_box): wide enough for the stencil of every point that
// lies up to `slack` cells outside its box, since points move between migrations (Solver:
// they migrate at the end of every chunk of steps). As the mass moves (a flume's down the
// chute) the boxes move with it: when the rank holding the most points holds more than
// kRebalanceRatio times the mean, the tree is cut anew and the points migrate to it.
//
// Neighbouring grids share nodes; where boxes meet at an edge or a corner a node lies in up
// to 2^D grids. After each particle-to-grid transfer every rank holding a node adds the
// partial sums of all of them in the ranks' order, starting from -0 (which adds exactly),
// its own at its own place (the halo sum): every copy of a node holds the same number, bit
// for bit, so the grid update runs on every local node alike.
//
// Shape functions (mpm/shape_functions.hpp): a point in cell c touches nodes c - a to
// c + b along an axis (node c: cell c's lower corner): linear a = 0, b = 1; GIMP and
// B-spline a = 1, b = 2.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scree/case/case_model.hpp"
#include "scree/core/tensor.hpp"
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

/// A box of the domain's cells: lo[d] <= c[d] < hi[d].
template <int D>
struct CellBox {
  int lo[D];
  int hi[D];
  bool contains(const int* c) const {
    for (int d = 0; d < D; ++d)
      if (c[d] < lo[d] || c[d] >= hi[d]) return false;
    return true;
  }
};

/// The points per cell layer of a box along every axis: [d][c - box.lo[d]].
template <int D>
using LayerCounts = std::array<std::vector<std::uint64_t>, D>;

/// The counts of the points in each of `boxes` (LayerCounts, sized to each box), given
/// `which`: the index into `boxes` of the box holding a domain cell, or -1 (a point there
/// is not counted). The same on every rank: a count of every rank's points is reduced.
template <int D>
using CountBoxes =
    std::function<std::vector<LayerCounts<D>>(const std::vector<CellBox<D>>& boxes, const std::function<int(const int*)>& which)>;

template <int D>
struct Decomposition {
  /// A node of the bisection tree: its box is cut at cell `cut` along `axis`, child[0]
  /// below, child[1] at and above; a child >= 0 is a node of `tree`, < 0 rank -child - 1.
  struct Split {
    int axis, cut;
    int child[2];
  };

  int ranks = 1;
  int rank = 0;
  int slack = 0;                  ///< cells a held point may lie outside its box between two migrations
  std::vector<Split> tree;        ///< root first; empty for one rank
  std::vector<CellBox<D>> boxes;  ///< each rank's cells
  /// Every rank's grid (local[r]), in the global lattice: node i of local[r] is global node
  /// i + local[r].offset. The whole grid for one rank.
  std::vector<GridGeometry<D>> local;
  /// The global lattice's nodes each rank owns (the lower corners of its cells; the last
  /// box along an axis also the domain's last node layer and the ghost layers beyond).
  std::vector<NodeRange<D>> owned;
  /// The ranks whose grids share nodes with this rank's, in ascending order.
  std::vector<int> neighbours;
  /// The points the counts gave each rank's box when it was cut (bisect; empty otherwise).
  std::vector<std::uint64_t> counted;

  bool decomposed() const { return ranks > 1; }
  const GridGeometry<D>& grid() const { return local[static_cast<std::size_t>(rank)]; }
  /// The rank owning domain cell c (domain_cell along each axis).
  SCREE_API int owner_of_cell(const int* c) const;
  /// The rank owning a point at `x` (outside the domain: the nearest box).
  SCREE_API int owner(const Vec<D>& x, const GlobalGrid<D>& g) const;
  /// This rank's owned nodes, in its local node indices.
  SCREE_API NodeRange<D> owned_local() const;
  /// The nodes this rank's grid shares with rank `peer`'s, in this rank's local node
  /// indices; false when they share none.
  SCREE_API bool overlap(int peer, NodeRange<D>& shared) const;
  /// Every rank's box, for the log: "[x0, x1) x [y0, y1) ...".
  SCREE_API std::string describe_box(int r) const;
  /// The tree as integers (4 per node: axis, cut, child[0], child[1]): a checkpoint's record.
  SCREE_API std::vector<std::int32_t> tree_code() const;
  /// Whether another decomposition has the same boxes.
  SCREE_API bool same_boxes(const Decomposition& o) const;
};

/// Recursive coordinate bisection of grid `g` over `ranks` ranks (above), from the counts
/// of the points in the boxes being cut (one call per level of the tree), for a shape
/// function of reach a, b and points `slack` cells outside their box at most. A single rank
/// owns the whole grid. Throws std::invalid_argument, saying how many ranks the grid
/// allows, when a box would be too thin for its neighbours' halos.
template <int D>
SCREE_API Decomposition<D> bisect(const GlobalGrid<D>& g, int ranks, int rank, int a, int b, int slack,
                                  const CountBoxes<D>& count);

/// The decomposition of a tree (Decomposition::tree_code) over `ranks` ranks: a restart
/// takes up its checkpoint's. Throws std::invalid_argument when the code is not a tree of
/// `ranks` leaves that cuts the grid into boxes wide enough for their halos.
template <int D>
SCREE_API Decomposition<D> from_tree_code(const GlobalGrid<D>& g, const std::vector<std::int32_t>& code, int ranks,
                                          int rank, int a, int b, int slack);

}  // namespace scree

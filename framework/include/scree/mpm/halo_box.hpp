// The boxes of nodes a decomposed run's grid shares with its neighbours' grids
// (case/decomposition.hpp), on the grid's backend: each rank packs its partial sums on each
// shared box into one contiguous buffer, the ranks exchange them, and every rank adds, at
// every shared node, the partial sums of all the grids holding it in the ranks' order
// (ordered_sum), so that every copy of the node holds the same number, bit for bit.
//
// Layout of a buffer: one block per neighbour (HaloPeer::offset); within a block field after
// field, each field's nodes of the box with x fastest, as GridGeometry lays out a grid.
// Both ranks of a pair enumerate the same global nodes in the same order.
#pragma once

#include <cstdint>
#include <stdexcept>

#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

/// The nodal fields one halo sum adds (grid-sized arrays): the 1 + 2 D a solid pass
/// scatters (mass, momentum, force), or the both phases' sums of a two-phase scatter (at
/// most 8 + 4 D, porous/porous_media.hpp).
struct HaloFields {
  static constexpr int kMax = 20;
  Real* field[kMax];
  int count = 0;
  void add(Real* f) {
    if (count == kMax) throw std::logic_error("HaloFields: more than kMax fields");
    field[count++] = f;
  }
};

/// A box of this rank's nodes shared with one neighbour (lo <= i < hi along each axis, local
/// indices), and where the neighbour's partial sums on it lie in the received buffer.
template <int D>
struct HaloPeer {
  int lo[D];
  int hi[D];
  Index offset = 0;  ///< the nodes of the boxes before this one: its block starts at offset x fields
  Index size = 0;    ///< nodes of the box (a field's share of the block)
  SCREE_HD bool holds(const int* i) const {
    for (int d = 0; d < D; ++d)
      if (i[d] < lo[d] || i[d] >= hi[d]) return false;
    return true;
  }
  /// The position of node i in the box's order (x fastest).
  SCREE_HD Index at(const int* i) const {
    Index k = 0, s = 1;
    for (int d = 0; d < D; ++d) {
      k += (i[d] - lo[d]) * s;
      s *= hi[d] - lo[d];
    }
    return k;
  }
  SCREE_HD void node(Index k, int* i) const {
    for (int d = 0; d < D; ++d) {
      const Index w = hi[d] - lo[d];
      i[d] = lo[d] + static_cast<int>(k % w);
      k /= w;
    }
  }
  Index nodes() const {
    Index n = 1;
    for (int d = 0; d < D; ++d) n *= hi[d] - lo[d];
    return n;
  }
};

/// buf[peer.offset x f.count ..] <- the fields' values on the peer's box (f.count x peer.size Reals).
template <int D>
SCREE_API void pack_box(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer, const HaloFields& f,
                        Real* buf);

/// At every node of the shared boxes, every field <- -0 + the partial sums of the grids
/// holding the node, in the ranks' order: the neighbours' from `buf` (their blocks as
/// `peers` lay them out, in ascending rank order), this rank's own (the field's value) at
/// position `self` (the number of neighbours of lower rank). `peers` on the backend,
/// `host_peers` its copy on the host; launches one pass per neighbour's box, a node shared
/// with several done by the first that holds it.
template <int D>
SCREE_API void ordered_sum(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>* peers,
                           const HaloPeer<D>* host_peers, int count, int self, const HaloFields& f, const Real* buf);

/// Every field <- 0 on the peer's box: sums added only where a rank's own test selects a
/// node (the pore liquid's surface sums, which each rank clears where it tested them), kept
/// from surviving on nodes of the box its test did not select.
template <int D>
SCREE_API void clear_box(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer, const HaloFields& f);

/// Stamp every tile (Tiles<D>) that holds a node of the peer's box with `stamp`: the sparse
/// grid update then visits the sums the neighbour's points added there.
template <int D>
SCREE_API void stamp_box_tiles(const Exec& ex, const GridGeometry<D>& g, const HaloPeer<D>& peer,
                               std::uint32_t* stamps, std::uint32_t stamp);

}  // namespace scree

// The slab of nodes two neighbouring grids of a decomposed run share (case/decomposition.hpp),
// gathered into one contiguous buffer and added back, on the grid's backend: the halo sum
// of the solver's decomposed step sends one block per neighbour instead of one strided
// copy per field.
//
// Layout of a buffer: field after field; within a field the rows of the slab (every node
// index above `axis`, x fastest) one after another, each row the layers lo..hi-1 along
// `axis` times the nodes below it.
#pragma once

#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

/// Up to the 1 + 2 D fields a pass scatters (mass, momentum, force).
struct SlabFields {
  static constexpr int kMax = 7;
  Real* field[kMax];
  int count = 0;
};

/// The nodes of the slab lo <= i < hi along `axis` (of one field).
template <int D>
SCREE_API Index slab_size(const GridGeometry<D>& g, int axis, int lo, int hi);

/// buf <- the nodes lo <= i < hi along `axis` of every field (buf: count x slab size Reals).
template <int D>
SCREE_API void pack_slab(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi, const SlabFields& f,
                         Real* buf);
/// field += buf on the same nodes (each rank adds the other's partial sums to its own).
template <int D>
SCREE_API void add_slab(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi, const SlabFields& f,
                        const Real* buf);

/// Stamp every tile (Tiles<D>) that holds a node of the slab with `stamp`: the sparse grid
/// update then visits the sums the neighbour's points added there.
template <int D>
SCREE_API void stamp_slab_tiles(const Exec& ex, const GridGeometry<D>& g, int axis, int lo, int hi,
                                std::uint32_t* stamps, std::uint32_t stamp);

}  // namespace scree

// The nodes of a rank's grid that count in a sum over the whole case (an energy ledger, the
// liquid that entered through a surface): in a run decomposed over ranks
// (case/decomposition.hpp) a node shared by several grids holds the same value on each after
// the halo sum, and only the rank that owns it counts it.
#pragma once

#include "scree/core/config.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

/// Every node of the grid (`all`: one rank), or those with lo[d] <= index < hi[d] along
/// every axis (indices of the rank's own grid).
template <int D>
struct OwnedNodes {
  bool all = true;
  int lo[D] = {};
  int hi[D] = {};

  SCREE_INLINE bool holds(const GridGeometry<D>& g, Index I) const {
    if (all) return true;
    int idx[D];
    g.unflat(I, idx);
    for (int d = 0; d < D; ++d)
      if (idx[d] < lo[d] || idx[d] >= hi[d]) return false;
    return true;
  }
};

}  // namespace scree

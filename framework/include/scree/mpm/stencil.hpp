// The walk over a point's stencil, the nodes its shape function reaches, written once for
// every pass that maps between a point and the grid: the solid's particle pass
// (mpm/particle_pass.hpp) and the pore liquid's passes (porous/pore_gather.hpp,
// porous/pore_scatter.hpp).
#pragma once

#include "scree/core/config.hpp"
#include "scree/core/tensor.hpp"
#include "scree/mpm/grid.hpp"

namespace scree {

/// Calls body(I, N, gradN, dx) for node k = 0 .. kNodes-1 of the stencil `st` (a
/// detail::Stencil of mpm/particle_pass.hpp: the shape function's weights at x): I the
/// node's flat index, N its weight, gradN its gradient, dx = x_I - x. A body skips a node
/// by returning.
///
/// An inactive point (stopped, or its stencil off the grid) walks the nodes with N = 0,
/// gradN = dx = 0 and I = 0 on the GPU, where the warp-collective sums of a scatter
/// (WarpSegment) need every lane at every node; on the CPU it adds nothing and skips them.
///
/// Unrolled: the stencil's weights stay in registers (a loop index would put the Stencil
/// in local memory, read back at every node).
template <class St, int D, class Body>
SCREE_INLINE void for_each_stencil_node(const St& st, const GridGeometry<D>& g, const Vec<D>& x, bool active,
                                        Body&& body) {
SCREE_UNROLL
  for (int k = 0; k < St::kNodes; ++k) {
    Index I = 0;
    Real N = 0;
    Vec<D> gradN = Vec<D>::zero(), dx = Vec<D>::zero();
    if (active) st.node(k, g, x, I, N, gradN, dx);
#if !defined(__CUDA_ARCH__)
    if (!active) continue;
#endif
    body(I, N, gradN, dx);
  }
}

}  // namespace scree

// The boundary layer's entry points that take a plugin's SolverContext: boundary/ works on
// the grid alone (NodeLattice) and, being below plugin/ in the README's layering, does not
// know the context; the grid is taken from it here.
#include "scree/plugin/context.hpp"

#include "scree/boundary/boundary_condition.hpp"

namespace scree {

NodeLattice NodeLattice::of(const SolverContext& ctx) {
  NodeLattice g;
  g.dimension = ctx.dimension;
  g.h = ctx.cell_size;
  for (int d = 0; d < ctx.dimension; ++d) {
    g.origin[d] = ctx.grid_origin[d];
    g.nodes[d] = ctx.grid_nodes[d];
    if (static_cast<std::size_t>(d) < ctx.domain_lower.size()) g.lower[d] = ctx.domain_lower[d];
    if (static_cast<std::size_t>(d) < ctx.domain_upper.size()) g.upper[d] = ctx.domain_upper[d];
  }
  return g;
}

Region Region::read(const ParamReader& r, const SolverContext& ctx) { return read(r, NodeLattice::of(ctx)); }

RegionWall::RegionWall(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, NodeLattice::of(ctx), ctx.name) {}

}  // namespace scree

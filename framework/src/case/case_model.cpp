// The grid geometry and the plugin context of a case (see case_model.hpp).
#include "scree/case/case_model.hpp"

#include <cmath>

#include "scree/core/constants.hpp"

namespace scree {

double domain_cells(Real lower, Real upper, Real h) { return std::ceil((upper - lower) / h - kWholeCellTolerance); }

bool whole_cells(Real lower, Real upper, Real h) {
  const Real cells = (upper - lower) / h;
  return std::fabs(cells - std::round(cells)) <= kWholeCellWarning;
}

template <int D>
GlobalGrid<D> grid_geometry(const GridSettings& gs) {
  GlobalGrid<D> g{};
  g.h = gs.cell_size;
  g.ghost = gs.ghost_layers;
  for (int d = 0; d < D; ++d) {
    const Real lo = gs.lower[d], hi = gs.upper[d];
    g.cells[d] = static_cast<int>(domain_cells(lo, hi, g.h));
    g.lower[d] = lo;
    g.upper[d] = lo + g.cells[d] * g.h;
    g.n[d] = g.cells[d] + 1 + 2 * gs.ghost_layers;
    g.origin[d] = lo - gs.ghost_layers * g.h;
    g.offset[d] = 0;
    g.owned.lo[d] = 0;
    g.owned.hi[d] = g.n[d];
  }
  return g;
}

template <int D>
GridGeometry<D> GlobalGrid<D>::sub_box(const int* lo, const int* hi) const {
  GridGeometry<D> s{};
  s.h = this->h;
  s.ghost = this->ghost;
  for (int d = 0; d < D; ++d) {
    // Domain cell c spans the global nodes ghost + c and ghost + c + 1.
    s.offset[d] = this->offset[d] + lo[d];
    s.n[d] = hi[d] - lo[d] + 1 + 2 * this->ghost;
    s.origin[d] = this->origin[d] + lo[d] * this->h;
    s.lower[d] = this->lower[d] + lo[d] * this->h;
    s.upper[d] = this->lower[d] + hi[d] * this->h;
  }
  return s;
}

template <int D>
SolverContext plugin_context(const Case& c, const GridGeometry<D>& g, Device device) {
  const CaseSettings& s = c.settings();
  SolverContext ctx;
  ctx.case_dir = c.dir();
  ctx.dimension = D;
  ctx.device = device;
  ctx.cell_size = g.h;
  for (int d = 0; d < D; ++d) {
    ctx.grid_origin.push_back(g.origin[d]);
    ctx.domain_lower.push_back(g.lower[d]);
    ctx.domain_upper.push_back(g.upper[d]);
    ctx.grid_nodes.push_back(g.n[d]);
    ctx.gravity.push_back(s.gravity[d]);
  }
  ctx.start_time = s.control.time.start_time;
  ctx.end_time = s.control.time.end_time;
  ctx.delta_t = s.control.time.delta_t;
  for (const Entry* e : c.body_entries()) ctx.body_names.push_back(e->key());
  return ctx;
}

template struct GlobalGrid<2>;
template struct GlobalGrid<3>;
template GlobalGrid<2> grid_geometry<2>(const GridSettings&);
template GlobalGrid<3> grid_geometry<3>(const GridSettings&);
template SolverContext plugin_context<2>(const Case&, const GridGeometry<2>&, Device);
template SolverContext plugin_context<3>(const Case&, const GridGeometry<3>&, Device);

}  // namespace scree

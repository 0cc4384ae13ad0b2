// The grid-update kernel (compiled as CUDA when the CUDA backend is on).
#include "scree/mpm/grid_update.hpp"

#include <cmath>

namespace scree {
namespace {

template <int D>
struct GridUpdate {
  GridUpdateParams<D> p;

  SCREE_HD void operator()(Index I) const {
    StepControl* ctl = p.control;
    const int par = p.parity;
    const Real t = ctl->t[par], dt = ctl->dt[par];
    const GridFields<D>& g = p.cur;
    const Real m = g.mass[I];
    // Any node with mass gets a velocity p/m (a ratio of weighted sums, well defined);
    // only nodes heavier than mass_eps are accelerated by f/m: a node at the far edge of
    // a particle's stencil has a tiny mass but an O(1/h) share of its internal force.
    const bool has_mass = m > 0;
    const bool accelerate = m > p.mass_eps;
    const ConstraintMask mask = p.masks ? p.masks[I] : 0;
    Real x[D];
    if (mask) {
      const Vec<D> xn = p.grid.node_position(I);
      for (int d = 0; d < D; ++d) x[d] = xn[d];
    }

    if (p.modes & (kNormalize | kRemap)) {
      Real* const* src = (p.modes & kRemap) ? g.force : g.momentum;
      Real v[D];
      for (int d = 0; d < D; ++d) v[d] = has_mass ? src[d][I] / m : Real(0);
      if (mask) apply_constraints<D>(p.constraints, mask, v, x, t);
      for (int d = 0; d < D; ++d) g.velocity[d][I] = v[d];
    }
    if (p.modes & kIntegrate) {
      Real v[D];
      const bool damp = p.damping > 0 && t >= p.damping_start && t < p.damping_end;
      for (int d = 0; d < D; ++d) {
        const Real vk = g.velocity[d][I];
        Real f = g.force[d][I];
        if (damp && vk != 0) f -= p.damping * fabs(f) * (vk > 0 ? Real(1) : Real(-1));
        v[d] = accelerate ? vk + dt * f / m : vk;
      }
      if (mask) apply_constraints<D>(p.constraints, mask, v, x, t);
      for (int d = 0; d < D; ++d) g.velocity_new[d][I] = v[d];
    }
    if (p.modes & kZeroForce)
      for (int d = 0; d < D; ++d) g.force[d][I] = 0;
    if (p.modes & kZeroOther) {
      p.other.mass[I] = 0;
      for (int d = 0; d < D; ++d) {
        p.other.momentum[d][I] = 0;
        p.other.force[d][I] = 0;
      }
    }
    if ((p.modes & kAdvance) && I == 0) advance(ctl, par, t, dt);
  }

  /// Time control for the next step (slot 1 - par). Only node 0's thread runs this; it
  /// writes slots nobody else reads in this step.
  SCREE_HD static void advance(StepControl* c, int par, Real t, Real dt) {
    const Real t1 = t + dt;
    Real dt1 = c->dt_max;
    if (c->cfl > 0 && c->max_speed[par] > 0) dt1 = fmin(dt1, c->cfl * c->h / c->max_speed[par]);
    const Real remaining = c->t_target - t1;
    // Land exactly on the target; never leave a sliver shorter than 1e-6 dt.
    if (remaining <= Real(1e-9) * dt1) dt1 = 0;
    else if (remaining < dt1 * (1 + Real(1e-6))) dt1 = remaining;
    c->t[1 - par] = t1;
    c->dt[1 - par] = dt1;
    c->max_speed[par] = 0;
    if (dt > 0) c->steps_done += 1;
  }
};

}  // namespace

template <int D>
void grid_update(const Exec& ex, const GridUpdateParams<D>& p) {
  parallel_for(ex, p.grid.num_nodes(), GridUpdate<D>{p});
}

template void grid_update<2>(const Exec&, const GridUpdateParams<2>&);
template void grid_update<3>(const Exec&, const GridUpdateParams<3>&);

}  // namespace scree

// fixed: a no-slip wall, or a prescribed velocity, on the nodes of a region.
//   floor { type fixed; face yMin; }
//   piston { type fixed; box { min (0 0.5); max (0.1 0.5); } value (0 -0.01); endTime 2; }
//   piston { type fixed; box { min (0 0.5); max (0.1 0.5); }
//            value table ((0 (0 0)) (1 (0 -0.01)) (2 (0 0))); }
//
// A constant value is a wall of the grid update (mpm/wall_law.hpp, stick: v = value). A
// value that varies in time (a function of time: time/function_of_time.hpp) keeps that wall
// at rest in the grid update (the nodes belong to a wall: masks, free surfaces) and sets the
// solid's nodal velocities to value(t) after every grid update, as a node law
// (node_law.hpp). The pore liquid of a two-phase body sees the wall at rest: an
// impermeable wall that moves in time is for single-phase bodies (or make it `drained`).
#pragma once

#include "scree/boundary/boundary_condition.hpp"
#include "scree/boundary/node_law.hpp"
#include "scree/plugin/context.hpp"
#include "scree/time/function_of_time.hpp"

namespace scree::boundary {

/// v = value(t) on a node within the wall's window.
struct FixedVelocityLaw {
  TimeTable value;  ///< [m/s], one component per dimension
  Real t0 = 0, t1 = 0;
  template <int D>
  SCREE_HD void apply(Real* v, const Real*, Real t) const {
    if (t < t0 || t >= t1) return;
    for (int d = 0; d < D; ++d) v[d] = value(t, d);
  }
};

class Fixed final : public RegionWall {
 public:
  static constexpr const char* type_name = "fixed";
  static ParamSpec spec() {
    ParamSpec s(type_name, "no-slip wall: every velocity component of the selected nodes is set to `value`");
    Region::declare(s);
    s.function("value", "m/s", "prescribed velocity (default zero: no-slip); a constant or a function of time")
        .size(-1)
        .optional();
    declare_time_window(s);
    return s;
  }
  Fixed(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, ctx) {
    wall_.mode = Wall::Mode::stick;  // the nodes move with the wall: v = value
    if (!r.has("value")) return;
    const FunctionTable f = r.function("value", ctx.dimension, ctx.case_dir);
    if (f.constant()) {
      for (int d = 0; d < f.components && d < 3; ++d) wall_.velocity[d] = f.values[d];
      return;
    }
    value_ = FunctionOfTime(f);
    moving_ = true;
    law_.t0 = wall_.t_start;
    law_.t1 = wall_.t_end;
    nodes_.host() = select_nodes(NodeLattice::of(ctx), [this](const Real* x) { return region_.contains(x); });
  }

  bool has_node_law() const override { return moving_; }
  void apply(const Exec& ex, const GridNodes<2>& g) const override { run(ex, g); }
  void apply(const Exec& ex, const GridNodes<3>& g) const override { run(ex, g); }

 private:
  FixedVelocityLaw law(const Exec& ex) const {
    FixedVelocityLaw l = law_;
    l.value = value_.on(ex);
    return l;
  }
  template <int D>
  void run(const Exec& ex, const GridNodes<D>& g) const {
    const Index n = static_cast<Index>(nodes_.host().size());
    if (n == 0 || !(g.velocity || g.velocity_new)) return;
    parallel_for(ex, n, scree::detail::NodeLawKernel<FixedVelocityLaw, D>{nodes_.on(ex), law(ex), g});
  }

  bool moving_ = false;   // the value varies in time
  FunctionOfTime value_;  // the value, when it varies in time
  FixedVelocityLaw law_;
  HostedList<Index> nodes_;
};

}  // namespace scree::boundary

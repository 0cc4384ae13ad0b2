// fixed: a no-slip wall, or a prescribed velocity, on the nodes of a region.
//   floor { type fixed; face yMin; }
//   piston { type fixed; box { min (0 0.5); max (0.1 0.5); } value (0 -0.01); endTime 2; }
#pragma once

#include "scree/boundary/boundary_condition.hpp"

namespace scree::boundary {

class Fixed final : public RegionWall {
 public:
  static constexpr const char* type_name = "fixed";
  static ParamSpec spec() {
    ParamSpec s(type_name, "no-slip wall: every velocity component of the selected nodes is set to `value`");
    Region::declare(s);
    s.vector("value", "m/s", "prescribed velocity (default zero: no-slip)").size(-1).optional();
    declare_time_window(s);
    return s;
  }
  Fixed(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, ctx) {
    wall_.mode = Wall::Mode::stick;  // the nodes move with the wall: v = value
    if (r.has("value")) {
      const auto v = r.scalars("value");
      for (std::size_t d = 0; d < v.size() && d < 3; ++d) wall_.velocity[d] = v[d];
    }
  }
};

}  // namespace scree::boundary

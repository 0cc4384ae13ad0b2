// friction: a rigid wall with Coulomb friction (coefficient mu) on the selected nodes.
// Approach along the normal is stopped; the tangential velocity is reduced by
// mu |v_n| (not past zero); the material may leave the wall (separable by default).
//   base { type friction; face yMin; coefficient 0.4; }
#pragma once

#include "scree/boundary/boundary_condition.hpp"

namespace scree::boundary {

class Friction final : public RegionWall {
 public:
  static constexpr const char* type_name = "friction";
  static ParamSpec spec() {
    ParamSpec s(type_name, "rigid wall with Coulomb friction on the selected nodes");
    Region::declare(s);
    declare_normal(s);
    s.scalar("coefficient", "-", "Coulomb friction coefficient mu = tan(wall friction angle)").non_negative();
    s.boolean("separable", "the material may leave the wall").default_value("yes");
    declare_time_window(s);
    return s;
  }
  Friction(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, ctx) {
    wall_.mode = Wall::Mode::contact;
    read_normal(r, region_, wall_);
    wall_.mu = r.scalar("coefficient");
    wall_.separable = r.boolean("separable") ? 1 : 0;
  }
};

}  // namespace scree::boundary

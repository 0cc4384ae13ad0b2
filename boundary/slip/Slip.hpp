// slip: a frictionless (roller) wall: the velocity component along the wall normal is
// removed on the selected nodes; tangential motion is free.
//   leftWall { type slip; face xMin; }
//   gate { type slip; box { min (0.2 0); max (0.2 0.1); } normal (-1 0); endTime 0.2; }
// separable yes: the material may leave the wall (only approach is stopped).
#pragma once

#include "scree/boundary/boundary_condition.hpp"

namespace scree::boundary {

class Slip final : public RegionWall {
 public:
  static constexpr const char* type_name = "slip";
  static ParamSpec spec() {
    ParamSpec s(type_name, "frictionless (roller) wall: the normal velocity of the selected nodes is removed");
    Region::declare(s);
    declare_normal(s);
    s.boolean("separable", "only stop motion into the wall (the material may leave it)").default_value("no");
    declare_time_window(s);
    return s;
  }
  Slip(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, ctx) {
    wall_.mode = Wall::Mode::contact;  // frictionless: mu = 0
    read_normal(r, region_, wall_);
    wall_.separable = r.boolean("separable") ? 1 : 0;
  }
};

}  // namespace scree::boundary

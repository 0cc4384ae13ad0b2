// rotatingWall: the selected nodes move as a rigid body rotating about `centre` with
// angular velocity omega: v = omega x (x - centre). A rotating drum's wall, or (over the
// whole grid) a kinematic rigid rotation for objectivity checks.
//   drum { type rotatingWall; halfSpace { point (0 -0.4); normal (0 1); }
//          angularVelocity (2.0); centre (0 0); }
#pragma once

#include "scree/boundary/boundary_condition.hpp"
#include "scree/plugin/context.hpp"

namespace scree::boundary {

class RotatingWall final : public RegionWall {
 public:
  static constexpr const char* type_name = "rotatingWall";
  static ParamSpec spec() {
    ParamSpec s(type_name, "nodes move rigidly: v = omega x (x - centre) (no-slip rotating wall)");
    Region::declare(s);
    s.scalar_list("angularVelocity", "rad/s", "(omega_z) in 2D, counter-clockwise positive; (wx wy wz) in 3D");
    s.vector("centre", "m", "centre of rotation").size(-1);
    declare_time_window(s);
    return s;
  }
  RotatingWall(const ParamReader& r, const SolverContext& ctx) : RegionWall(r, ctx) {
    wall_.mode = Wall::Mode::stick;
    wall_.rotating = 1;
    const auto w = r.scalars("angularVelocity");
    const auto c = r.scalars("centre");
    if (static_cast<int>(w.size()) != (ctx.dimension == 2 ? 1 : 3))
      throw InputError(r.entry("angularVelocity").where(),
                       "angularVelocity: expected " + std::string(ctx.dimension == 2 ? "(omega_z)" : "(wx wy wz)"));
    if (ctx.dimension == 2) wall_.omega[2] = w[0];
    else for (int d = 0; d < 3; ++d) wall_.omega[d] = w[d];
    for (std::size_t d = 0; d < c.size() && d < 3; ++d) wall_.centre[d] = c[d];
  }
};

}  // namespace scree::boundary

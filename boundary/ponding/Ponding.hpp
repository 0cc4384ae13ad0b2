// ponding: water stands on the surface of two-phase bodies inside a region, p_w = 0 there.
// (Where the liquid may leave but must not enter, use seepageFace.)
// The surface nodes in the region are open: the pore liquid has the weak form's natural
// condition (no liquid traction, p_w = 0), and enters or leaves as the pore pressure drives
// it: ponding water on an infiltrating surface, a drained top of a consolidating layer, a
// seepage face. Elsewhere a two-phase body's surface is closed (porous/two_phase.hpp).
//   pond { type ponding; box { min (-1 1.0); max (1 1.1); } }
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/plugin/context.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree::boundary {

class Ponding final : public BoundaryCondition, public HydraulicCondition {
 public:
  static constexpr const char* type_name = "ponding";
  static ParamSpec spec() {
    ParamSpec s(type_name, "open surface of two-phase bodies (p_w = 0): ponding water, a drained top, a seepage face");
    Region::declare(s);
    s.scalar("startTime", "s", "the condition acts from this time").default_value(-kUnbounded);
    s.scalar("endTime", "s", "the condition acts until this time").default_value(kUnbounded);
    return s;
  }
  Ponding(const ParamReader& r, const SolverContext& ctx)
      : region_(Region::read(r, ctx)), t_start_(r.scalar("startTime")), t_end_(r.scalar("endTime")) {}
  void open_surfaces(std::vector<OpenSurface>& out) const override {
    out.push_back({[this](const Real* x) { return region_.contains(x); }, t_start_, t_end_});
  }

 private:
  Region region_;
  Real t_start_, t_end_;
};

}  // namespace scree::boundary

// seepageFace: a face of two-phase bodies where the pore liquid may leave but not enter:
// where the soil behind it is saturated and in compression (nodal p_w >= 0) the face is
// open, p_w = 0 (the natural condition of the weak form) and the liquid seeps out; where the
// soil is in suction (p_w < 0) it is closed, no flow through it. The face of a dam's
// downstream slope above the tailwater, the toe of a slope where the water table meets
// the surface, a drain (Bear 1972, ch. 7; Neuman 1973).
//   toe { type seepageFace; box { min (4 0); max (6 0.5); } }
// Compare ponding, open whatever the sign of p_w: there water also enters the soil.
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/plugin/context.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree::boundary {

class SeepageFace final : public BoundaryCondition, public HydraulicCondition {
 public:
  static constexpr const char* type_name = "seepageFace";
  static ParamSpec spec() {
    ParamSpec s(type_name,
                "seepage face of two-phase bodies: open (p_w = 0) where the soil behind it is saturated and in "
                "compression, closed where it is in suction: the liquid leaves, never enters");
    Region::declare(s);
    s.scalar("startTime", "s", "the condition acts from this time").default_value(-kUnbounded);
    s.scalar("endTime", "s", "the condition acts until this time").default_value(kUnbounded);
    return s;
  }
  SeepageFace(const ParamReader& r, const SolverContext& ctx)
      : region_(Region::read(r, ctx)), t_start_(r.scalar("startTime")), t_end_(r.scalar("endTime")) {}
  void open_surfaces(std::vector<OpenSurface>& out) const override {
    OpenSurface o{[this](const Real* x) { return region_.contains(x); }, t_start_, t_end_};
    o.outflow_only = true;
    out.push_back(o);
  }

 private:
  Region region_;
  Real t_start_, t_end_;
};

}  // namespace scree::boundary

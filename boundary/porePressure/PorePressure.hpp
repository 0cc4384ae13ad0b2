// porePressure: a prescribed pore-liquid pressure on the points of two-phase bodies in the
// cells a box overlaps (the pore pressure is resolved per cell of the grid: a box that cuts
// a cell holds all of its points), applied after every step's pore-pressure update
// (porous/two_phase.hpp):
//   base  { type porePressure; min (0 -1); max (0.1 0.02); value 0; }          drained, p_w = 0
//   table { type porePressure; min (0 -1); max (0.1 0.02); waterTable 0; }     hydrostatic
//   pond  { type porePressure; min (0 1.04); max (0.1 2); value 0; }           ponding (p_w = 0)
// value is compression positive [Pa]; waterTable gives p_w = rho_l |g| (z_w - z) (negative,
// a suction, above it), z along -g. The points keep the prescribed pressure: the liquid's
// mass balance there is replaced by the condition, and water enters or leaves through them
// as the flow requires (with a `drained` wall where the liquid must cross the domain's
// boundary).
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/core/constants.hpp"
#include "scree/plugin/context.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree::boundary {

class PorePressure final : public BoundaryCondition, public HydraulicCondition {
 public:
  static constexpr const char* type_name = "porePressure";
  static ParamSpec spec() {
    ParamSpec s(type_name, "prescribed pore-liquid pressure on the points of two-phase bodies in the cells a box overlaps");
    s.vector("min", "m", "lower corner of the box").size(-1);
    s.vector("max", "m", "upper corner of the box").size(-1);
    s.scalar("value", "Pa", "pore pressure, compression positive (give this or waterTable)").optional();
    s.scalar("waterTable", "m", "hydrostatic: elevation of the water table along -g (give this or value)").optional();
    s.scalar("startTime", "s", "the condition acts from this time").default_value(-kUnbounded);
    s.scalar("endTime", "s", "the condition acts until this time").default_value(kUnbounded);
    s.check([](const Dictionary& d, std::vector<InputError>& errors) {
      if (d.has("value") == d.has("waterTable"))
        errors.emplace_back(d.where(), "porePressure: give exactly one of value [Pa] and waterTable [m]");
      if (d.has("min") && d.has("max")) {
        const auto lo = d.at("min").as_scalar_list(), hi = d.at("max").as_scalar_list();
        for (std::size_t i = 0; i < lo.size() && i < hi.size(); ++i)
          if (!(hi[i] >= lo[i]))
            errors.emplace_back(d.at("max").where(), "max: each component must be at least min's");
      }
    });
    return s;
  }
  PorePressure(const ParamReader& r, const SolverContext& ctx) {
    const auto lo = r.scalars("min"), hi = r.scalars("max");
    for (int d = 0; d < ctx.dimension; ++d) {
      law_.lo[d] = lo[d];
      law_.hi[d] = hi[d];
    }
    if (r.has("value")) {
      law_.value = r.scalar("value");
    } else {
      law_.hydrostatic = 1;
      law_.level = r.scalar("waterTable");
    }
    law_.t_start = r.scalar("startTime");
    law_.t_end = r.scalar("endTime");
  }
  void constrain_pores(std::vector<PorePressureLaw>& laws) const override { laws.push_back(law_); }

 private:
  PorePressureLaw law_;
};

}  // namespace scree::boundary

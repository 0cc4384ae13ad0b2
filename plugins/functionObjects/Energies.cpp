// energies (see Energies.hpp).
#include "Energies.hpp"

namespace scree::fo {

ParamSpec Energies::spec() {
  ParamSpec s(type_name,
              "kinetic, gravitational potential and total energy of the selected bodies, one CSV row per "
              "execution (postProcessing/<name>/energies.csv)");
  s.word_list("bodies", "bodies to sum over (default: all bodies)").optional();
  s.vector("origin", "m", "where the potential energy is zero (default: the origin)").size(-1).optional();
  return s;
}

Energies::Energies(const ParamReader& r, const SolverContext& ctx)
    : who_("energies '" + ctx.name + "'"), bodies_(read_bodies(r, ctx)), origin_(read_point(r, "origin", ctx)) {
  for (std::size_t d = 0; d < ctx.gravity.size() && d < 3; ++d) gravity_[d] = ctx.gravity[d];
  const std::string unit = ctx.dimension == 3 ? " [J]" : " [J/m]";
  ensure_writable_dir(ctx.post_processing_dir(), who_);
  csv_.open(ctx.post_processing_dir() / "energies.csv",
            {"time [s]", "kinetic" + unit, "potential" + unit, "total" + unit}, ctx.start_time);
}

Energies::Result Energies::evaluate(const Snapshot& s) const {
  Result res;
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    const FieldData& v = require_field(b, "velocity", who_);
    const FieldData& m = require_field(b, "mass", who_);
    for (Index p = 0; p < b.n; ++p) {
      const double* vp = &v.values[3 * p];
      const double* x = &b.position[3 * p];
      const double mp = m.values[p];
      res.kinetic += 0.5 * mp * (vp[0] * vp[0] + vp[1] * vp[1] + vp[2] * vp[2]);
      double gx = 0;
      for (int d = 0; d < 3; ++d) gx += gravity_[d] * (x[d] - origin_[d]);
      res.potential -= mp * gx;
    }
  }
  return res;
}

void Energies::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const Result r = evaluate(s);
  csv_.row({s.time, r.kinetic, r.potential, r.total()});
}

}  // namespace scree::fo

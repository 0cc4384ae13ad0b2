// runOut (see RunOut.hpp).
#include "RunOut.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scree::fo {

namespace {

/// The q-quantile of `v` (0 < q <= 1): the k-th smallest value with k = ceil(q n), so
/// q = 1 is the maximum. NaN for an empty set. Reorders `v`.
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto n = static_cast<double>(v.size());
  auto k = static_cast<std::size_t>(std::ceil(q * n - 1e-9));
  k = std::clamp<std::size_t>(k, 1, v.size()) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

ParamSpec RunOut::spec() {
  ParamSpec s(type_name,
              "run-out tracker: front position, deposit height, kinetic energy, max and mean velocity of the "
              "selected bodies, one CSV row per execution (postProcessing/<name>/runOut.csv)");
  s.word_list("bodies", "bodies to track (default: all bodies)").optional();
  s.vector("origin", "m", "reference point of the distances and heights (default: the origin)").size(-1).optional();
  s.vector("direction", "-", "direction of the run-out (normalised; default +x)").size(-1).optional();
  s.vector("up", "-", "direction of the height (normalised; default: against gravity)").size(-1).optional();
  s.scalar("frontQuantile", "-",
           "the front is this quantile of the particles' distances along direction (1: the furthest "
           "particle; 0.999 ignores the furthest 0.1 %, e.g. particles that separated from the mass)")
      .range(0, 1)
      .open_min()
      .default_value(1.0);
  s.scalar("heightQuantile", "-", "the height is this quantile of the particles' heights (1: the highest)")
      .range(0, 1)
      .open_min()
      .default_value(1.0);
  s.scalar_list("heightWindow", "m",
                "(a b): measure the height only over particles whose distance along direction from origin is "
                "in [a, b] (default: all particles)")
      .optional();
  return s;
}

RunOut::RunOut(const ParamReader& r, const SolverContext& ctx)
    : who_("runOut '" + ctx.name + "'"),
      dimension_(ctx.dimension),
      bodies_(read_bodies(r, ctx)),
      origin_(read_point(r, "origin", ctx)),
      direction_(read_direction(r, "direction", ctx, {1, 0, 0})),
      up_(read_direction(r, "up", ctx, default_up(ctx))),
      front_quantile_(r.scalar("frontQuantile")),
      height_quantile_(r.scalar("heightQuantile")) {
  if (r.has("heightWindow")) {
    const auto w = r.scalars("heightWindow");
    if (w.size() != 2 || !(w[0] <= w[1]))
      throw InputError(where_of(r, "heightWindow"), "heightWindow: expected (a b) with a <= b [m]");
    window_ = true;
    window_lo_ = w[0];
    window_hi_ = w[1];
  }
  const bool two_d = dimension_ != 3;
  const std::string per = two_d ? "/m" : "";
  std::vector<std::string> header = {"time [s]",
                                     "runout [m]",
                                     "height [m]",
                                     "kinetic_energy [J" + per + "]",
                                     "max_speed [m/s]",
                                     "mean_velocity_x [m/s]",
                                     "mean_velocity_y [m/s]"};
  if (!two_d) header.push_back("mean_velocity_z [m/s]");
  header.push_back("mass [kg" + per + "]");
  header.push_back("particles [-]");
  ensure_writable_dir(ctx.post_processing_dir(), who_);
  csv_.open(ctx.post_processing_dir() / "runOut.csv", header, ctx.start_time);
}

RunOut::Result RunOut::evaluate(const Snapshot& s) const {
  Result res;
  // Quantile 1 is the maximum: tracked on the fly; other quantiles need every value.
  const bool front_max = front_quantile_ >= 1, height_max = height_quantile_ >= 1;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double front_top = -std::numeric_limits<double>::infinity(), height_top = front_top;
  bool any_front = false, any_height = false;
  std::vector<double> front, height;
  double momentum[3] = {0, 0, 0};
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    const FieldData& v = require_field(b, "velocity", who_);
    const FieldData& m = require_field(b, "mass", who_);
    for (Index p = 0; p < b.n; ++p) {
      const double* x = &b.position[3 * p];
      const double rel[3] = {x[0] - origin_[0], x[1] - origin_[1], x[2] - origin_[2]};
      const double along = dot(direction_, rel);
      any_front = true;
      if (front_max)
        front_top = std::max(front_top, along);
      else
        front.push_back(along);
      if (!window_ || (along >= window_lo_ && along <= window_hi_)) {
        any_height = true;
        if (height_max)
          height_top = std::max(height_top, dot(up_, rel));
        else
          height.push_back(dot(up_, rel));
      }
      const double* vp = &v.values[3 * p];
      const double mp = m.values[p];
      const double v2 = vp[0] * vp[0] + vp[1] * vp[1] + vp[2] * vp[2];
      res.kinetic_energy += 0.5 * mp * v2;
      res.max_speed = std::max(res.max_speed, std::sqrt(v2));
      res.mass += mp;
      for (int d = 0; d < 3; ++d) momentum[d] += mp * vp[d];
      ++res.particles;
    }
  }
  res.runout = !any_front ? nan : (front_max ? front_top : quantile(front, front_quantile_));
  res.height = !any_height ? nan : (height_max ? height_top : quantile(height, height_quantile_));
  for (int d = 0; d < 3; ++d) res.mean_velocity[d] = res.mass > 0 ? momentum[d] / res.mass : nan;
  return res;
}

void RunOut::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const Result r = evaluate(s);
  std::vector<double> row = {s.time, r.runout, r.height, r.kinetic_energy, r.max_speed, r.mean_velocity[0],
                             r.mean_velocity[1]};
  if (dimension_ == 3) row.push_back(r.mean_velocity[2]);
  row.push_back(r.mass);
  row.push_back(static_cast<double>(r.particles));
  csv_.row(row);
}

}  // namespace scree::fo

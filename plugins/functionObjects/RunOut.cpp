// runOut (see RunOut.hpp).
#include "RunOut.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

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

/// "+x", "-z" for a unit vector along an axis, "" otherwise.
std::string axis_label(const Vec3& d) {
  static const char* names[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const double others = std::fabs(d[(k + 1) % 3]) + std::fabs(d[(k + 2) % 3]);
    if (others < 1e-12 && std::fabs(std::fabs(d[k]) - 1) < 1e-12) return std::string(d[k] > 0 ? "+" : "-") + names[k];
  }
  return "";
}

/// The parameters of `radial { }` (declared once, read with a ParamReader on the sub-dictionary).
std::shared_ptr<const ParamSpec> radial_spec() {
  static const auto spec = [] {
    auto s = std::make_shared<ParamSpec>(
        "radial", "run-out as the distance from an axis (axisymmetric collapse) and fronts in sectors");
    s->vector("centre", "m", "a point of the axis; distances and heights are measured from it").size(-1);
    s->vector("axis", "-", "direction of the axis (normalised; default: against gravity, +y/+z without gravity)")
        .size(-1)
        .optional();
    s->list("directions",
            "((dx dy [dz]) ...): one extra front per direction, over the particles within sectorHalfAngle of it "
            "around the axis (each projected on the plane normal to the axis); columns runout_+x [m], ... or "
            "runout_dir<i> [m]")
        .optional();
    s->scalar("sectorHalfAngle", "deg", "half-angle of each direction's sector")
        .range(0, 180)
        .open_min()
        .default_value(15.0);
    return s;
  }();
  return spec;
}

}  // namespace

ParamSpec RunOut::spec() {
  ParamSpec s(type_name,
              "run-out tracker: front position, deposit height, kinetic energy, max and mean velocity of the "
              "selected bodies, one CSV row per execution (postProcessing/<name>/runOut.csv)");
  s.word_list("bodies", "bodies to track (default: all bodies)").optional();
  s.vector("origin", "m", "reference point of the distances and heights (default: the origin)").size(-1).optional();
  s.vector("direction", "-", "direction of the run-out (normalised, non-zero; any vector in 3D; default +x)")
      .size(-1)
      .optional();
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
                "in [a, b] (radial: the distance from the axis; default: all particles)")
      .optional();
  s.dict("radial",
         "radial mode: the run-out is the distance from the axis through centre (the height along the axis from "
         "centre), with optional fronts in sectors around given directions; not with direction, origin, up")
      .sub_spec(radial_spec())
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
  if (r.has("radial")) {
    for (const char* k : {"direction", "origin", "up"})
      if (r.has(k))
        throw InputError(where_of(r, k), std::string(k) +
                                             ": not with radial (radial mode measures from radial's centre, along "
                                             "its axis)");
    const Dictionary& d = r.dict().sub("radial");
    ParamReader rr(*radial_spec(), d);
    radial_ = true;
    centre_ = read_point(rr, "centre", ctx);
    axis_ = read_direction(rr, "axis", ctx, default_up(ctx));
    sector_cos_ = std::cos(rr.scalar("sectorHalfAngle") * M_PI / 180.0);
    if (rr.has("directions")) {
      const Entry& de = rr.entry("directions");
      const Item& list = de.single_item();
      const int dim = dimension_ == 3 ? 3 : 2;
      const std::string form = dim == 3 ? "((1 0 0) (0 0 1))" : "((1 0) (-1 0))";
      if (list.kind != Item::Kind::list || list.list.empty())
        throw InputError(de.where(), "radial.directions: expected a non-empty list of directions, e.g. " + form);
      for (std::size_t i = 0; i < list.list.size(); ++i) {
        const Item& it = list.list[i];
        const SourceLocation at = it.where.file ? it.where : de.where();
        bool ok = it.kind == Item::Kind::list && static_cast<int>(it.list.size()) == dim;
        Vec3 v{0, 0, 0};
        for (int k = 0; ok && k < dim; ++k) {
          ok = it.list[k].kind == Item::Kind::number && std::isfinite(it.list[k].number);
          if (ok) v[k] = it.list[k].number;
        }
        if (!ok)
          throw InputError(at, "radial.directions: element " + std::to_string(i + 1) + " must be a direction of " +
                                   std::to_string(dim) + " numbers, e.g. " + form + ", found " + it.to_string());
        const double along = v[0] * axis_[0] + v[1] * axis_[1] + v[2] * axis_[2];
        for (int k = 0; k < 3; ++k) v[k] -= along * axis_[k];  // onto the plane normal to the axis
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(len > 1e-9 * (std::fabs(along) + 1)))
          throw InputError(at, "radial.directions: element " + std::to_string(i + 1) + " " + it.to_string() +
                                   " is zero or parallel to the axis; expected a direction with a component "
                                   "normal to the axis");
        for (auto& c : v) c /= len;
        for (const auto& u : sector_dirs_)
          if (std::fabs(u[0] - v[0]) + std::fabs(u[1] - v[1]) + std::fabs(u[2] - v[2]) < 1e-9)
            throw InputError(at, "radial.directions: element " + std::to_string(i + 1) + " " + it.to_string() +
                                     " repeats an earlier direction");
        sector_dirs_.push_back(v);
      }
    }
  }
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
  for (std::size_t i = 0; i < sector_dirs_.size(); ++i) {
    const std::string label = axis_label(sector_dirs_[i]);
    header.push_back("runout_" + (label.empty() ? "dir" + std::to_string(i) : label) + " [m]");
  }
  check_writable_dir(ctx.post_processing_dir(), who_);  // the file: at the first execution
  file_ = ctx.post_processing_dir() / "runOut.csv";
  header_ = std::move(header);
  start_time_ = ctx.start_time;
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
  // Radial mode's sectors: the largest component (quantile 1) or every component.
  const std::size_t ns = sector_dirs_.size();
  std::vector<double> sector_top(ns, -std::numeric_limits<double>::infinity());
  std::vector<std::vector<double>> sector(front_max ? 0 : ns);
  std::vector<bool> sector_any(ns, false);
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    const FieldData& v = require_field(b, "velocity", who_);
    const FieldData& m = require_field(b, "mass", who_);
    for (Index p = 0; p < b.n; ++p) {
      const double* x = &b.position[3 * p];
      double along, up;
      if (!radial_) {
        const double rel[3] = {x[0] - origin_[0], x[1] - origin_[1], x[2] - origin_[2]};
        along = dot(direction_, rel);
        up = dot(up_, rel);
      } else {
        const double rel[3] = {x[0] - centre_[0], x[1] - centre_[1], x[2] - centre_[2]};
        up = dot(axis_, rel);
        const double off[3] = {rel[0] - up * axis_[0], rel[1] - up * axis_[1], rel[2] - up * axis_[2]};
        along = std::sqrt(off[0] * off[0] + off[1] * off[1] + off[2] * off[2]);
        for (std::size_t i = 0; i < ns; ++i) {
          const double c = dot(sector_dirs_[i], off);
          if (c < along * sector_cos_) continue;  // outside the sector (a point on the axis is in every one)
          sector_any[i] = true;
          if (front_max)
            sector_top[i] = std::max(sector_top[i], c);
          else
            sector[i].push_back(c);
        }
      }
      any_front = true;
      if (front_max)
        front_top = std::max(front_top, along);
      else
        front.push_back(along);
      if (!window_ || (along >= window_lo_ && along <= window_hi_)) {
        any_height = true;
        if (height_max)
          height_top = std::max(height_top, up);
        else
          height.push_back(up);
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
  for (std::size_t i = 0; i < ns; ++i)
    res.sector_runout.push_back(!sector_any[i] ? nan : (front_max ? sector_top[i] : quantile(sector[i], front_quantile_)));
  return res;
}

void RunOut::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const Result r = evaluate(s);
  if (!csv_.is_open()) {
    ensure_writable_dir(file_.parent_path(), who_);
    csv_.open(file_, header_, start_time_);
  }
  std::vector<double> row = {s.time, r.runout, r.height, r.kinetic_energy, r.max_speed, r.mean_velocity[0],
                             r.mean_velocity[1]};
  if (dimension_ == 3) row.push_back(r.mean_velocity[2]);
  row.push_back(r.mass);
  row.push_back(static_cast<double>(r.particles));
  row.insert(row.end(), r.sector_runout.begin(), r.sector_runout.end());
  csv_.row(row);
}

}  // namespace scree::fo

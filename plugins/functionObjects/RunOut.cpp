// runOut (see RunOut.hpp).
#include "RunOut.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace scree::fo {

namespace {

/// "+x", "-z" for a unit vector along an axis, "" otherwise.
std::string axis_label(const Vec3& d) {
  static const char* names[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const double others = std::fabs(d[(k + 1) % 3]) + std::fabs(d[(k + 2) % 3]);
    if (others < 1e-12 && std::fabs(std::fabs(d[k]) - 1) < 1e-12) return std::string(d[k] > 0 ? "+" : "-") + names[k];
  }
  return "";
}

std::string not_with_radial(const char* key) {
  return std::string(key) + ": not with radial (radial mode measures from radial's centre, along its axis)";
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

/// The unit sector directions of `radial { directions (...); }`: each of `dim` numbers,
/// projected on the plane normal to `axis` (a unit vector) and normalised; an element that
/// is not `dim` numbers, is zero or parallel to the axis, or repeats one before is an
/// error appended to `errors`. axis null: not known yet (the spec's check, where the
/// default axis, from gravity, is not known): only the count and the repeats of the
/// directions as given are checked. Used by the spec's check (scree --check, before any
/// plugin exists) and by the constructor: one rule, one message.
std::vector<Vec3> sector_directions(const Dictionary& radial, int dim, const Vec3* axis,
                                    std::vector<InputError>& errors) {
  std::vector<Vec3> out;
  const Entry* de = radial.find("directions");
  if (!de) return out;
  const std::string form = dim == 3 ? "((1 0 0) (0 0 1))" : "((1 0) (-1 0))";
  if (de->items().size() != 1 || de->items()[0].kind() != Item::Kind::list || de->items()[0].list().empty()) {
    errors.emplace_back(de->where(), "radial.directions: expected a non-empty list of directions, e.g. " + form);
    return out;
  }
  const Item& list = de->items()[0];
  std::vector<Vec3> given;
  for (std::size_t i = 0; i < list.list().size(); ++i) {
    const Item& it = list.list()[i];
    const SourceLocation at = it.where().file ? it.where() : de->where();
    const std::string which = "radial.directions: element " + std::to_string(i + 1) + " ";
    bool ok = it.kind() == Item::Kind::list && static_cast<int>(it.list().size()) == dim;
    Vec3 v{0, 0, 0};
    for (int k = 0; ok && k < dim; ++k) {
      ok = it.list()[k].kind() == Item::Kind::number && std::isfinite(it.list()[k].number());
      if (ok) v[k] = it.list()[k].number();
    }
    if (!ok) {
      errors.emplace_back(at, which + "must be a direction of " + std::to_string(dim) + " numbers, e.g. " + form +
                                  ", found " + it.to_string());
      continue;
    }
    if (axis) {
      const double along = v[0] * (*axis)[0] + v[1] * (*axis)[1] + v[2] * (*axis)[2];
      for (int k = 0; k < 3; ++k) v[k] -= along * (*axis)[k];  // onto the plane normal to the axis
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (!(len > 1e-9 * (std::fabs(along) + 1))) {
        errors.emplace_back(at, which + it.to_string() +
                                    " is zero or parallel to the axis; expected a direction with a component normal "
                                    "to the axis");
        continue;
      }
      for (auto& c : v) c /= len;
    } else {
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (!(len > 0)) {
        errors.emplace_back(at, which + it.to_string() + " is zero; expected a direction with a component normal "
                                                         "to the axis");
        continue;
      }
      for (auto& c : v) c /= len;
    }
    for (const auto& u : out)
      if (std::fabs(u[0] - v[0]) + std::fabs(u[1] - v[1]) + std::fabs(u[2] - v[2]) < 1e-9) {
        errors.emplace_back(at, which + it.to_string() + " repeats an earlier direction");
        break;
      }
    out.push_back(v);
  }
  return out;
}

/// The whole-dictionary rules of runOut that need no case (run by the validation, so
/// scree --check reports them before any plugin is built); the constructor applies the
/// same ones (read_direction, sector_directions) with the case's gravity.
void check_runout(const Dictionary& d, std::vector<InputError>& errors) {
  for (const char* k : {"direction", "up"})
    if (zero_vector(d, k))
      errors.emplace_back(d.find(k)->where(), zero_direction(k, d.find(k)->value_string()));
  const Entry* re = d.find("radial");
  if (!re || !re->is_dict()) return;
  for (const char* k : {"direction", "origin", "up"})
    if (d.has(k)) errors.emplace_back(d.find(k)->where(), not_with_radial(k));
  const Dictionary& rd = re->dict();
  const Entry* centre = rd.find("centre");
  if (!centre || centre->items().size() != 1) return;
  const int dim = static_cast<int>(centre->items()[0].list().size());  // validated: one per dimension
  if (zero_vector(rd, "axis"))
    errors.emplace_back(rd.find("axis")->where(), zero_direction("axis", rd.find("axis")->value_string()));
  Vec3 axis{0, 0, 0};
  const bool given = rd.has("axis") && !zero_vector(rd, "axis");
  if (given) {
    const auto v = rd.find("axis")->as_scalar_list();
    double len = 0;
    for (std::size_t k = 0; k < v.size() && k < 3; ++k) len += v[k] * v[k];
    len = std::sqrt(len);
    for (std::size_t k = 0; k < v.size() && k < 3; ++k) axis[k] = v[k] / len;
  }
  sector_directions(rd, dim, given ? &axis : nullptr, errors);
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
  s.check(check_runout);
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
      height_quantile_(r.scalar("heightQuantile")),
      ranks_(ctx.comm) {
  lost_ = LostPoints(ctx, who_);
  if (r.has("radial")) {
    for (const char* k : {"direction", "origin", "up"})
      if (r.has(k)) throw InputError(where_of(r, k), not_with_radial(k));
    const Dictionary& d = r.dict().sub("radial");
    ParamReader rr(*radial_spec(), d);
    radial_ = true;
    centre_ = read_point(rr, "centre", ctx);
    axis_ = read_direction(rr, "axis", ctx, default_up(ctx));
    sector_cos_ = std::cos(rr.scalar("sectorHalfAngle") * M_PI / 180.0);
    std::vector<InputError> errors;
    sector_dirs_ = sector_directions(d, dimension_ == 3 ? 3 : 2, &axis_, errors);
    if (!errors.empty()) throw errors.front();
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
  if (ranks_.root())
    csv_.open_at_first_row(ctx.post_processing_dir() / "runOut.csv", std::move(header), ctx.start_time, who_);
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
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
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
  // Over the ranks (one rank: each value as it is).
  std::vector<double> sums = {res.kinetic_energy, res.mass, momentum[0], momentum[1], momentum[2]};
  ranks_.sum(sums);
  res.kinetic_energy = sums[0];
  res.mass = sums[1];
  for (int d = 0; d < 3; ++d) momentum[d] = sums[2 + d];
  std::vector<std::int64_t> counts = {res.particles, any_height ? 1 : 0};
  for (std::size_t i = 0; i < ns; ++i) counts.push_back(sector_any[i] ? 1 : 0);
  ranks_.sum(counts);
  res.particles = counts[0];
  any_front = res.particles > 0;
  any_height = counts[1] > 0;
  std::vector<double> tops = {res.max_speed, front_top, height_top};
  tops.insert(tops.end(), sector_top.begin(), sector_top.end());
  ranks_.max(tops);
  res.max_speed = tops[0];
  res.runout = !any_front ? nan : (front_max ? tops[1] : ranks_.quantile(front, front_quantile_));
  res.height = !any_height ? nan : (height_max ? tops[2] : ranks_.quantile(height, height_quantile_));
  for (int d = 0; d < 3; ++d) res.mean_velocity[d] = res.mass > 0 ? momentum[d] / res.mass : nan;
  for (std::size_t i = 0; i < ns; ++i)
    res.sector_runout.push_back(counts[2 + i] == 0 ? nan
                                                   : (front_max ? tops[3 + i] : ranks_.quantile(sector[i], front_quantile_)));
  return res;
}

void RunOut::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const Result r = evaluate(s);
  lost_.record(s, bodies_);  // after every reduction: the root's writes come last
  std::vector<double> row = {s.time, r.runout, r.height, r.kinetic_energy, r.max_speed, r.mean_velocity[0],
                             r.mean_velocity[1]};
  if (dimension_ == 3) row.push_back(r.mean_velocity[2]);
  row.push_back(r.mass);
  row.push_back(static_cast<double>(r.particles));
  row.insert(row.end(), r.sector_runout.begin(), r.sector_runout.end());
  if (ranks_.root()) csv_.row(row);
}

}  // namespace scree::fo

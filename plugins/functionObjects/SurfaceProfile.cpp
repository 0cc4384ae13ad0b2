// surfaceProfile (see SurfaceProfile.hpp).
#include "SurfaceProfile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree::fo {

namespace {

const char* const kWidthOnlySection =
    "width: only for a 3D section (a 3D case with direction); without direction a 3D case gives a height field, "
    "which counts every particle, and in 2D every particle counts";
const char* const kRangeProfile = "range: expected (a b) with a < b [m] (distances from origin along direction)";
const char* const kRangeField =
    "range: expected (a1 b1 a2 b2) with a1 < b1, a2 < b2 [m] (a 3D height field: distances from origin along its "
    "two horizontal axes)";

/// Whether `range` (v) fits: a height field needs (a1 b1 a2 b2), a profile (a b).
bool range_fits(const std::vector<double>& v, bool field) {
  return field ? v.size() == 4 && v[0] < v[1] && v[2] < v[3] : v.size() == 2 && v[0] < v[1];
}

/// The rules of surfaceProfile that need no case (run by the validation, so scree --check
/// reports them before any plugin is built); the constructor applies the same ones with
/// the case's dimension. The dimension is known here only from a vector given.
void check_surface(const Dictionary& d, std::vector<InputError>& errors) {
  for (const char* k : {"direction", "up"})
    if (zero_vector(d, k)) errors.emplace_back(d.find(k)->where(), zero_direction(k, d.find(k)->value_string()));
  const int dim = given_dimension(d, {"direction", "origin", "up"});
  const bool section = d.has("direction");
  if (const Entry* w = d.find("width"); w && (!section || dim == 2)) errors.emplace_back(w->where(), kWidthOnlySection);
  if (const Entry* r = d.find("range"); r && (section || dim != 0)) {
    const bool field = dim == 3 && !section;
    std::vector<double> v;
    for (const Item& x : r->items().size() == 1 ? r->items()[0].list() : std::span<const Item>())
      v.push_back(x.kind() == Item::Kind::number ? x.number() : std::nan(""));
    if (!range_fits(v, field)) errors.emplace_back(r->where(), field ? kRangeField : kRangeProfile);
  }
}

}  // namespace

ParamSpec SurfaceProfile::spec() {
  ParamSpec s(type_name,
              "free surface of the selected bodies: a profile (highest particle per bin along a direction; 2D, or "
              "a section in 3D with direction) or a height field over the horizontal plane (3D without "
              "direction), one file postProcessing/<name>/<time>.csv per execution");
  s.word_list("bodies", "bodies to include (default: all bodies)").optional();
  s.scalar("binWidth", "m", "bin width (both horizontal axes for a height field; default: the grid cell size)")
      .positive()
      .optional();
  s.vector("origin", "m", "reference point of distances and heights; bins are anchored at it (default: the origin)")
      .size(-1)
      .optional();
  s.vector("direction", "-",
           "direction along which the bins run (normalised; default +x). In 3D it selects a section profile "
           "instead of the height field")
      .size(-1)
      .optional();
  s.vector("up", "-", "direction of the height (normalised; default: against gravity)").size(-1).optional();
  s.scalar_list("range", "m",
                "fixed bins: (a b) distances from origin along direction; height field (a1 b1 a2 b2) along the two "
                "horizontal axes (default: where particles are)")
      .optional();
  s.scalar("width", "m",
           "3D section only: count particles at most width/2 from the vertical plane through origin holding "
           "direction (default: all particles)")
      .positive()
      .optional();
  s.check(check_surface);
  return s;
}

namespace {

/// a - (a.u) u, normalised (u a unit vector); zero when a is parallel to u.
Vec3 normal_part(const Vec3& a, const Vec3& u) {
  const double c = a[0] * u[0] + a[1] * u[1] + a[2] * u[2];
  Vec3 v{a[0] - c * u[0], a[1] - c * u[1], a[2] - c * u[2]};
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (len > 1e-12)
    for (auto& x : v) x /= len;
  else
    v = {0, 0, 0};
  return v;
}

}  // namespace

SurfaceProfile::SurfaceProfile(const ParamReader& r, const SolverContext& ctx)
    : who_("surfaceProfile '" + ctx.name + "'"),
      dir_(ctx.post_processing_dir()),
      bodies_(read_bodies(r, ctx)),
      ranks_(ctx.comm),
      origin_(read_point(r, "origin", ctx)),
      direction_(read_direction(r, "direction", ctx, {1, 0, 0})),
      up_(read_direction(r, "up", ctx, default_up(ctx))),
      width_(r.has("binWidth") ? r.scalar("binWidth") : ctx.cell_size) {
  lost_ = LostPoints(ctx, who_);
  if (!(width_ > 0))
    throw InputError(where_of(r, "binWidth"), "binWidth: must be positive (no grid cell size to default to)");
  const bool three_d = ctx.dimension == 3;
  field_ = three_d && !r.has("direction");
  if (r.has("width")) {
    if (!three_d || field_) throw InputError(where_of(r, "width"), kWidthOnlySection);
    // The band around the vertical plane holding direction: distances along direction x up.
    const Vec3& d = direction_;
    const Vec3 n{d[1] * up_[2] - d[2] * up_[1], d[2] * up_[0] - d[0] * up_[2], d[0] * up_[1] - d[1] * up_[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 1e-9))
      throw InputError(where_of(r, "direction"), "direction: parallel to up; a section needs a horizontal direction");
    lateral_ = {n[0] / len, n[1] / len, n[2] / len};
    band_ = true;
    half_band_ = 0.5 * r.scalar("width");
  }
  if (field_) {
    // The horizontal axes: the two grid axes other than the one closest to up, on the plane normal to up.
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::fabs(up_[i]) > std::fabs(up_[k])) k = i;
    const int i = k == 0 ? 1 : 0, j = k == 2 ? 1 : 2;
    Vec3 ei{0, 0, 0}, ej{0, 0, 0};
    ei[i] = 1;
    ej[j] = 1;
    axis_a_ = normal_part(ei, up_);
    Vec3 b = normal_part(ej, up_);
    axis_b_ = normal_part(b, axis_a_);
    name_a_ = std::string(1, "xyz"[i]);
    name_b_ = std::string(1, "xyz"[j]);
  }
  if (r.has("range")) {
    const auto v = r.scalars("range");
    if (!range_fits(v, field_)) throw InputError(where_of(r, "range"), field_ ? kRangeField : kRangeProfile);
    fixed_range_ = true;
    lo_ = v[0];
    hi_ = v[1];
    double bins = (hi_ - lo_) / width_;
    if (field_) {
      lo_b_ = v[2];
      hi_b_ = v[3];
      bins *= (hi_b_ - lo_b_) / width_;
    }
    if (bins > 1e7) throw InputError(where_of(r, "range"), "range: more than 10^7 bins of width " + csv_number(width_));
  }
  // The directory is made, and a fresh run's old profiles (<number>.csv) removed, at the
  // first execution.
  if (ranks_.root()) check_writable_dir(dir_, who_);
  start_time_ = ctx.start_time;
}

std::vector<SurfaceProfile::Bin> SurfaceProfile::evaluate(const Snapshot& s) const {
  const double anchor = fixed_range_ ? lo_ : 0.0;
  std::map<std::int64_t, Bin> bins;  // sparse while collecting
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    for (Index p = 0; p < b.n; ++p) {
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
      const double* x = &b.position[3 * p];
      const double rel[3] = {x[0] - origin_[0], x[1] - origin_[1], x[2] - origin_[2]};
      const double along = dot(direction_, rel);
      if (fixed_range_ && (along < lo_ || along > hi_)) continue;
      if (band_ && std::fabs(dot(lateral_, rel)) > half_band_) continue;
      auto k = static_cast<std::int64_t>(std::floor((along - anchor) / width_));
      if (fixed_range_) k = std::min<std::int64_t>(k, static_cast<std::int64_t>(std::ceil((hi_ - lo_) / width_)) - 1);
      const double h = dot(up_, rel);
      auto [it, fresh] = bins.try_emplace(k);
      if (fresh || h > it->second.height) it->second.height = h;
      ++it->second.particles;
    }
  }
  std::int64_t first = 0, last = -1;
  if (fixed_range_) {
    last = static_cast<std::int64_t>(std::ceil((hi_ - lo_) / width_)) - 1;
  } else {  // the occupied bins of every rank
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> lo = {bins.empty() ? inf : static_cast<double>(bins.begin()->first)},
                        hi = {bins.empty() ? -inf : static_cast<double>(bins.rbegin()->first)};
    ranks_.min(lo);
    ranks_.max(hi);
    if (hi[0] >= lo[0]) {
      first = static_cast<std::int64_t>(lo[0]);
      last = static_cast<std::int64_t>(hi[0]);
    }
  }
  std::vector<Bin> out;
  for (std::int64_t k = first; k <= last; ++k) {
    Bin bin;
    if (auto it = bins.find(k); it != bins.end()) bin = it->second;
    else bin.height = std::numeric_limits<double>::quiet_NaN();
    bin.centre = anchor + (static_cast<double>(k) + 0.5) * width_;
    out.push_back(bin);
  }
  combine(out);
  return out;
}

template <class B>
void SurfaceProfile::combine(std::vector<B>& bins) const {
  if (ranks_.size() == 1) return;
  // Over the ranks: the highest point of each bin and the count; empty everywhere: NaN.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> top(bins.size());
  std::vector<std::int64_t> count(bins.size());
  for (std::size_t i = 0; i < bins.size(); ++i) {
    top[i] = bins[i].particles > 0 ? bins[i].height : -std::numeric_limits<double>::infinity();
    count[i] = bins[i].particles;
  }
  ranks_.max(top);
  ranks_.sum(count);
  for (std::size_t i = 0; i < bins.size(); ++i) {
    bins[i].particles = count[i];
    bins[i].height = count[i] > 0 ? top[i] : nan;
  }
}

std::vector<SurfaceProfile::Cell> SurfaceProfile::evaluate_field(const Snapshot& s) const {
  const double anchor_a = fixed_range_ ? lo_ : 0.0, anchor_b = fixed_range_ ? lo_b_ : 0.0;
  std::int64_t last_a = 0, last_b = 0;
  if (fixed_range_) {
    last_a = static_cast<std::int64_t>(std::ceil((hi_ - lo_) / width_)) - 1;
    last_b = static_cast<std::int64_t>(std::ceil((hi_b_ - lo_b_) / width_)) - 1;
  }
  std::map<std::pair<std::int64_t, std::int64_t>, Cell> bins;  // (kb, ka): sparse while collecting
  std::int64_t min_a = 0, max_a = -1, min_b = 0, max_b = -1;
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    for (Index p = 0; p < b.n; ++p) {
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
      const double* x = &b.position[3 * p];
      const double rel[3] = {x[0] - origin_[0], x[1] - origin_[1], x[2] - origin_[2]};
      const double da = dot(axis_a_, rel), db = dot(axis_b_, rel);
      if (fixed_range_ && (da < lo_ || da > hi_ || db < lo_b_ || db > hi_b_)) continue;
      auto ka = static_cast<std::int64_t>(std::floor((da - anchor_a) / width_));
      auto kb = static_cast<std::int64_t>(std::floor((db - anchor_b) / width_));
      if (fixed_range_) {
        ka = std::min(ka, last_a);
        kb = std::min(kb, last_b);
      }
      const double h = dot(up_, rel);
      auto [it, fresh] = bins.try_emplace({kb, ka});
      if (fresh || h > it->second.height) it->second.height = h;
      ++it->second.particles;
      if (max_a < min_a) {
        min_a = max_a = ka;
        min_b = max_b = kb;
      } else {
        min_a = std::min(min_a, ka);
        max_a = std::max(max_a, ka);
        min_b = std::min(min_b, kb);
        max_b = std::max(max_b, kb);
      }
    }
  }
  if (fixed_range_) {
    min_a = min_b = 0;
    max_a = last_a;
    max_b = last_b;
  } else if (ranks_.size() > 1) {  // the occupied bins of every rank
    const double inf = std::numeric_limits<double>::infinity();
    const bool any = max_a >= min_a;
    std::vector<double> lo = {any ? static_cast<double>(min_a) : inf, any ? static_cast<double>(min_b) : inf},
                        hi = {any ? static_cast<double>(max_a) : -inf, any ? static_cast<double>(max_b) : -inf};
    ranks_.min(lo);
    ranks_.max(hi);
    if (hi[0] >= lo[0]) {
      min_a = static_cast<std::int64_t>(lo[0]);
      max_a = static_cast<std::int64_t>(hi[0]);
      min_b = static_cast<std::int64_t>(lo[1]);
      max_b = static_cast<std::int64_t>(hi[1]);
    }
  }
  const double oa = dot(axis_a_, origin_.data()), ob = dot(axis_b_, origin_.data());
  std::vector<Cell> out;
  for (std::int64_t kb = min_b; kb <= max_b; ++kb)
    for (std::int64_t ka = min_a; ka <= max_a; ++ka) {
      Cell c;
      if (auto it = bins.find({kb, ka}); it != bins.end()) c = it->second;
      else c.height = std::numeric_limits<double>::quiet_NaN();
      c.a = oa + anchor_a + (static_cast<double>(ka) + 0.5) * width_;
      c.b = ob + anchor_b + (static_cast<double>(kb) + 0.5) * width_;
      out.push_back(c);
    }
  combine(out);
  return out;
}

void SurfaceProfile::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  // Every rank's reductions first; then the root alone prepares and writes.
  auto prepare = [&] {
    if (prepared_) return;
    prepare_time_files(dir_, who_, start_time_);
    prepared_ = true;
  };
  if (field_) {
    const auto cells = evaluate_field(s);
    lost_.record(s, bodies_);
    if (!ranks_.root()) return;
    prepare();
    write_file_atomically(dir_ / (time_name(s.time) + ".csv"), [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::trunc);
      if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string());
      out << name_a_ << " [m]," << name_b_ << " [m],height [m],particles [-]\n";
      for (const auto& c : cells)
        out << csv_number(c.a) << "," << csv_number(c.b) << "," << csv_number(c.height) << "," << c.particles << "\n";
      out.close();
      if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string() + " (disk full?)");
    });
    return;
  }
  const auto bins = evaluate(s);
  lost_.record(s, bodies_);
  if (!ranks_.root()) return;
  prepare();
  write_file_atomically(dir_ / (time_name(s.time) + ".csv"), [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string());
    out << "distance [m],height [m],particles [-]\n";
    for (const auto& b : bins)
      out << csv_number(b.centre) << "," << csv_number(b.height) << "," << b.particles << "\n";
    out.close();
    if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string() + " (disk full?)");
  });
}

}  // namespace scree::fo

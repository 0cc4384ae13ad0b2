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

ParamSpec SurfaceProfile::spec() {
  ParamSpec s(type_name,
              "free-surface profile (highest particle per bin along a direction) of the selected bodies, one "
              "file postProcessing/<name>/<time>.csv per execution");
  s.word_list("bodies", "bodies to include (default: all bodies)").optional();
  s.scalar("binWidth", "m", "bin width along direction (default: the grid cell size)").positive().optional();
  s.vector("origin", "m", "reference point of distances and heights (default: the origin)").size(-1).optional();
  s.vector("direction", "-", "direction along which the bins run (normalised; default +x)").size(-1).optional();
  s.vector("up", "-", "direction of the height (normalised; default: against gravity)").size(-1).optional();
  s.scalar_list("range", "m", "(a b): fixed bins covering distances a..b from origin (default: where particles are)")
      .optional();
  return s;
}

SurfaceProfile::SurfaceProfile(const ParamReader& r, const SolverContext& ctx)
    : who_("surfaceProfile '" + ctx.name + "'"),
      dir_(ctx.post_processing_dir()),
      bodies_(read_bodies(r, ctx)),
      origin_(read_point(r, "origin", ctx)),
      direction_(read_direction(r, "direction", ctx, {1, 0, 0})),
      up_(read_direction(r, "up", ctx, default_up(ctx))),
      width_(r.has("binWidth") ? r.scalar("binWidth") : ctx.cell_size) {
  if (!(width_ > 0))
    throw InputError(where_of(r, "binWidth"), "binWidth: must be positive (no grid cell size to default to)");
  if (r.has("range")) {
    const auto v = r.scalars("range");
    if (v.size() != 2 || !(v[0] < v[1]))
      throw InputError(where_of(r, "range"), "range: expected (a b) with a < b [m]");
    fixed_range_ = true;
    lo_ = v[0];
    hi_ = v[1];
    if ((hi_ - lo_) / width_ > 1e7)
      throw InputError(where_of(r, "range"), "range: more than 10^7 bins of width " + csv_number(width_));
  }
  ensure_writable_dir(dir_, who_);
  if (ctx.start_time <= 0) {
    // A fresh run: remove the profiles of an earlier run (files named <number>.csv).
    std::error_code ec;
    for (const auto& de : fs::directory_iterator(dir_, ec)) {
      if (de.path().extension() != ".csv") continue;
      const std::string stem = de.path().stem().string();
      char* end = nullptr;
      std::strtod(stem.c_str(), &end);
      if (!stem.empty() && end == stem.c_str() + stem.size()) fs::remove(de.path(), ec);
    }
  }
}

std::vector<SurfaceProfile::Bin> SurfaceProfile::evaluate(const Snapshot& s) const {
  const double anchor = fixed_range_ ? lo_ : 0.0;
  std::map<std::int64_t, Bin> bins;  // sparse while collecting
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    for (Index p = 0; p < b.n; ++p) {
      const double* x = &b.position[3 * p];
      const double rel[3] = {x[0] - origin_[0], x[1] - origin_[1], x[2] - origin_[2]};
      const double along = dot(direction_, rel);
      if (fixed_range_ && (along < lo_ || along > hi_)) continue;
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
  } else if (!bins.empty()) {
    first = bins.begin()->first;
    last = bins.rbegin()->first;
  }
  std::vector<Bin> out;
  for (std::int64_t k = first; k <= last; ++k) {
    Bin bin;
    if (auto it = bins.find(k); it != bins.end()) bin = it->second;
    else bin.height = std::numeric_limits<double>::quiet_NaN();
    bin.centre = anchor + (static_cast<double>(k) + 0.5) * width_;
    out.push_back(bin);
  }
  return out;
}

void SurfaceProfile::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  last_step_ = s.step;
  const auto bins = evaluate(s);
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

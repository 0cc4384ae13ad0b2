// lineProfile (see LineProfile.hpp).
#include "LineProfile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree::fo {

namespace {

const char* kAxes[] = {"x", "y", "z"};

}  // namespace

ParamSpec LineProfile::spec() {
  ParamSpec s(type_name,
              "profiles of particle fields along a line segment (mean per bin over the points within a band "
              "around it), one file postProcessing/<name>/<time>.csv per execution");
  s.vector("start", "m", "first end of the segment; distances along the line are measured from it").size(-1);
  s.vector("end", "m", "second end of the segment").size(-1);
  s.scalar("width", "m",
           "full width of the band around the line: points at most width/2 from it are counted (default: the "
           "grid cell size)")
      .positive()
      .optional();
  s.scalar("binWidth", "m",
           "bin length along the line, bins anchored at start (the last one ends at end); default: the grid cell "
           "size. Not with bins")
      .positive()
      .optional();
  s.integer("bins", "number of equal bins between start and end (instead of binWidth)").min(1).optional();
  s.word_list("fields",
              "particle fields to profile, e.g. (porePressure saturation suction); (all): every field of the "
              "selected bodies. Vectors and tensors are expanded per component")
      .default_value("(all)");
  s.word_list("bodies", "bodies whose points are counted (default: all bodies)").optional();
  s.boolean("longFormat",
            "also write every profile into one file postProcessing/<name>/lineProfile.csv, one row per (time, bin)")
      .default_value("false");
  return s;
}

LineProfile::LineProfile(const ParamReader& r, const SolverContext& ctx)
    : who_("lineProfile '" + ctx.name + "'"),
      dir_(ctx.post_processing_dir()),
      dimension_(ctx.dimension == 3 ? 3 : 2),
      start_time_(ctx.start_time),
      bodies_(read_bodies(r, ctx)),
      ranks_(ctx.comm),
      start_(read_point(r, "start", ctx)),
      end_(read_point(r, "end", ctx)),
      long_format_(r.boolean("longFormat")) {
  lost_ = LostPoints(ctx, who_);
  Vec3 d{end_[0] - start_[0], end_[1] - start_[1], end_[2] - start_[2]};
  length_ = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(length_ > 0) || !std::isfinite(length_))
    throw InputError(where_of(r, "end"), "end: must differ from start (the line has zero length)");
  for (int k = 0; k < 3; ++k) direction_[k] = d[k] / length_;

  const double width = r.has("width") ? r.scalar("width") : ctx.cell_size;
  if (!(width > 0))
    throw InputError(where_of(r, "width"), "width: must be positive (no grid cell size to default to)");
  half_width_ = 0.5 * width;

  if (r.has("bins") && r.has("binWidth"))
    throw InputError(where_of(r, "bins"), "bins: give either bins or binWidth, not both");
  if (r.has("bins")) {
    const long long n = r.integer("bins");
    if (n < 1 || n > 10000000) throw InputError(where_of(r, "bins"), "bins: expected a whole number in [1, 10^7]");
    for (long long k = 0; k <= n; ++k) edges_.push_back(length_ * static_cast<double>(k) / static_cast<double>(n));
  } else {
    const double w = r.has("binWidth") ? r.scalar("binWidth") : ctx.cell_size;
    if (!(w > 0))
      throw InputError(where_of(r, "binWidth"), "binWidth: must be positive (no grid cell size to default to)");
    if (length_ / w > 1e7)
      throw InputError(where_of(r, "binWidth"),
                       "binWidth: more than 10^7 bins over the line's length " + csv_number(length_) + " m");
    // Bins of width w from start; a last piece shorter than 1e-9 w is merged into the
    // bin before it (a length that is a multiple of w up to rounding).
    const auto n = std::max<long long>(1, static_cast<long long>(std::ceil(length_ / w - 1e-9)));
    for (long long k = 0; k < n; ++k) edges_.push_back(w * static_cast<double>(k));
    edges_.push_back(length_);
  }

  const auto fw = r.words("fields");
  all_fields_ = fw.empty() || std::find(fw.begin(), fw.end(), "all") != fw.end();
  for (const auto& f : fw)
    if (f != "all" && std::find(fields_.begin(), fields_.end(), f) == fields_.end()) fields_.push_back(f);

  // The directory is made, and a fresh run's old profiles (<number>.csv and the
  // long-format file) removed, at the first execution.
  check_writable_dir(dir_, who_);
}

void LineProfile::decide_columns(const Snapshot& s) {
  // The fields of the selected bodies, in the order first met; the first body having a
  // field fixes its number of components and its unit.
  std::vector<const FieldData*> have;
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    for (const auto& f : b.fields)
      if (std::none_of(have.begin(), have.end(), [&](const FieldData* h) { return h->name == f.name; }))
        have.push_back(&f);
  }
  auto find = [&](const std::string& name) -> const FieldData* {
    for (const FieldData* f : have)
      if (f->name == name) return f;
    return nullptr;
  };
  std::vector<const FieldData*> chosen;
  if (all_fields_)
    for (const FieldData* f : have)
      if (f->name != "bodyId") chosen.push_back(f);
  for (const auto& name : fields_) {
    const FieldData* f = find(name);
    if (!f) {
      std::vector<std::string> names;
      for (const FieldData* h : have) names.push_back(h->name);
      std::string msg = who_ + ": fields: unknown field '" + name + "'";
      const std::string near = nearest_name(name, names);
      if (!near.empty()) msg += " (did you mean '" + near + "'?)";
      throw std::runtime_error(msg + "; the fields of the selected bodies are: " +
                               (names.empty() ? std::string("none (no selected body in the snapshot)") : join(names)));
    }
    if (std::find(chosen.begin(), chosen.end(), f) == chosen.end()) chosen.push_back(f);
  }
  columns_.clear();
  for (const FieldData* f : chosen)
    for (const auto& [suffix, c] : component_suffixes(f->components, dimension_))
      columns_.push_back({f->name, c, f->name + suffix + " [" + (f->unit.empty() ? "-" : f->unit) + "]"});
  columns_decided_ = true;
}

std::vector<std::string> LineProfile::header(bool with_time) const {
  std::vector<std::string> h;
  if (with_time) h.push_back("time [s]");
  h.push_back("distance [m]");
  for (int d = 0; d < dimension_; ++d) h.push_back(std::string(kAxes[d]) + " [m]");
  h.push_back("points [-]");
  for (const auto& c : columns_) h.push_back(c.header);
  return h;
}

LineProfile::Profile LineProfile::evaluate(const Snapshot& s) {
  if (!columns_decided_) decide_columns(s);
  const std::size_t nb = bin_count();
  Profile out;
  out.points.assign(nb, 0);
  std::vector<std::vector<double>> sum(columns_.size(), std::vector<double>(nb, 0.0));
  std::vector<std::vector<std::int64_t>> count(columns_.size(), std::vector<std::int64_t>(nb, 0));
  for (const auto& b : s.bodies) {
    if (!selected(bodies_, b)) continue;
    // Each column's field in this body (null: the body does not have it).
    std::vector<const FieldData*> field(columns_.size(), nullptr);
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      const FieldData* f = b.find(columns_[c].field);
      if (f && columns_[c].component < f->components &&
          f->values.size() >= static_cast<std::size_t>(b.n) * static_cast<std::size_t>(f->components))
        field[c] = f;
    }
    for (Index p = 0; p < b.n; ++p) {
      if (b.is_lost(p)) continue;  // left the grid (LostPoints)
      const double* x = &b.position[3 * static_cast<std::size_t>(p)];
      const double rel[3] = {x[0] - start_[0], x[1] - start_[1], x[2] - start_[2]};
      const double along = dot(direction_, rel);
      if (!(along >= 0 && along <= length_)) continue;
      double off2 = 0;
      for (int d = 0; d < 3; ++d) {
        const double o = rel[d] - along * direction_[d];
        off2 += o * o;
      }
      if (!(off2 <= half_width_ * half_width_ * (1 + 1e-12))) continue;
      // The bin: the last edge not above `along` (the far end belongs to the last bin).
      auto it = std::upper_bound(edges_.begin(), edges_.end(), along);
      auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - edges_.begin()) - 1));
      k = std::min(k, nb - 1);
      ++out.points[k];
      for (std::size_t c = 0; c < columns_.size(); ++c) {
        if (!field[c]) continue;
        sum[c][k] += field[c]->values[static_cast<std::size_t>(p) * field[c]->components + columns_[c].component];
        ++count[c][k];
      }
    }
  }
  {  // over the ranks
    std::vector<double> sums;
    std::vector<std::int64_t> counts = out.points;
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      sums.insert(sums.end(), sum[c].begin(), sum[c].end());
      counts.insert(counts.end(), count[c].begin(), count[c].end());
    }
    ranks_.sum(sums);
    ranks_.sum(counts);
    std::copy_n(counts.begin(), nb, out.points.begin());
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      std::copy_n(sums.begin() + static_cast<std::ptrdiff_t>(c * nb), nb, sum[c].begin());
      std::copy_n(counts.begin() + static_cast<std::ptrdiff_t>((c + 1) * nb), nb, count[c].begin());
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.mean.assign(columns_.size(), std::vector<double>(nb, nan));
  for (std::size_t c = 0; c < columns_.size(); ++c)
    for (std::size_t k = 0; k < nb; ++k)
      if (count[c][k] > 0) out.mean[c][k] = sum[c][k] / static_cast<double>(count[c][k]);
  for (std::size_t k = 0; k < nb; ++k) {
    const double centre = 0.5 * (edges_[k] + edges_[k + 1]);
    out.distance.push_back(centre);
    out.position.push_back({start_[0] + centre * direction_[0], start_[1] + centre * direction_[1],
                            start_[2] + centre * direction_[2]});
  }
  return out;
}

void LineProfile::execute(const Snapshot& s) {
  if (s.step == last_step_) return;  // the same state again (the final output)
  const Profile prof = evaluate(s);
  last_step_ = s.step;
  lost_.record(s, bodies_);
  if (!ranks_.root()) return;
  if (!prepared_) {
    prepare_time_files(dir_, who_, start_time_, "lineProfile.csv");
    prepared_ = true;
  }
  auto cells = [&](std::size_t k) {
    std::vector<std::string> row = {csv_number(prof.distance[k])};
    for (int d = 0; d < dimension_; ++d) row.push_back(csv_number(prof.position[k][d]));
    row.push_back(std::to_string(prof.points[k]));
    for (std::size_t c = 0; c < columns_.size(); ++c) row.push_back(csv_number(prof.mean[c][k]));
    return row;
  };
  write_file_atomically(dir_ / (time_name(s.time) + ".csv"), [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string());
    const auto h = header(false);
    for (std::size_t i = 0; i < h.size(); ++i) out << (i ? "," : "") << csv_text(h[i]);
    out << "\n";
    for (std::size_t k = 0; k < bin_count(); ++k) {
      const auto row = cells(k);
      for (std::size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << row[i];
      out << "\n";
    }
    out.close();
    if (!out) throw std::runtime_error(who_ + ": cannot write " + tmp.string() + " (disk full?)");
  });
  if (long_format_) {
    if (!long_csv_.is_open()) long_csv_.open(dir_ / "lineProfile.csv", header(true), start_time_);
    for (std::size_t k = 0; k < bin_count(); ++k) {
      auto row = cells(k);
      row.insert(row.begin(), csv_number(s.time));
      long_csv_.row_text(row);
    }
  }
}

}  // namespace scree::fo

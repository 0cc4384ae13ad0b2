// Shared pieces of the function objects (see FoCommon.hpp).
#include "FoCommon.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace scree::fo {

/// "a, b, c" (FoCommon.hpp).
std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// ------------------------------------------------------------------ LostPoints

LostPoints::LostPoints(const SolverContext& ctx, std::string who)
    : ranks_(ctx.comm), path_(ctx.post_processing_dir() / "lostPoints.csv"), start_time_(ctx.start_time), who_(std::move(who)) {}

std::int64_t LostPoints::record(const Snapshot& s, const std::vector<std::string>& bodies) {
  const bool writes = ranks_.root() && !path_.empty();
  if (!started_) {
    started_ = true;
    std::error_code ec;
    if (start_time_ <= 0 && writes) fs::remove(path_, ec);  // an earlier run's
  }
  std::int64_t lost = 0;
  for (const auto& b : s.bodies)
    if (selected(bodies, b))
      for (Index p = 0; p < b.n; ++p) lost += b.is_lost(p);
  lost = ranks_.sum(lost);
  if (lost > 0 && writes) {
    if (!csv_.is_open()) {
      ensure_writable_dir(path_.parent_path(), who_);
      csv_.open(path_, {"time [s]", "lost points [-]"}, start_time_);
    }
    csv_.row({s.time, static_cast<double>(lost)});
  }
  return lost;
}

// ------------------------------------------------------------------ helpers

void prepare_time_files(const fs::path& dir, const std::string& who, double start_time, const std::string& also) {
  ensure_writable_dir(dir, who);
  if (start_time > 0) return;  // a restart keeps them
  std::error_code ec;
  if (!also.empty()) fs::remove(dir / also, ec);
  for (const auto& de : fs::directory_iterator(dir, ec)) {
    if (de.path().extension() != ".csv") continue;
    const std::string stem = de.path().stem().string();
    char* end = nullptr;
    std::strtod(stem.c_str(), &end);
    if (!stem.empty() && end == stem.c_str() + stem.size()) fs::remove(de.path(), ec);
  }
}

SourceLocation where_of(const ParamReader& r, const char* key) {
  if (const Entry* e = r.dict().find(key)) return e->where();
  return r.dict().where();
}

std::vector<std::string> read_bodies(const ParamReader& r, const SolverContext& ctx) {
  if (!r.has("bodies")) return {};
  auto names = r.words("bodies");
  for (const auto& b : names) {
    if (ctx.body_names.empty() || std::find(ctx.body_names.begin(), ctx.body_names.end(), b) != ctx.body_names.end())
      continue;
    std::string msg = "bodies: unknown body '" + b + "'";
    const std::string near = nearest_name(b, ctx.body_names);
    if (!near.empty()) msg += " (did you mean '" + near + "'?)";
    throw InputError(where_of(r, "bodies"), msg + "; the bodies of this case are: " + join(ctx.body_names));
  }
  if (names.empty()) throw InputError(where_of(r, "bodies"), "bodies: the list is empty (leave it out for all bodies)");
  return names;
}

bool selected(const std::vector<std::string>& selection, const BodySnapshot& b) {
  return selection.empty() || std::find(selection.begin(), selection.end(), b.name) != selection.end();
}

Vec3 read_point(const ParamReader& r, const char* key, const SolverContext& ctx) {
  Vec3 p{0, 0, 0};
  if (!r.has(key)) return p;
  const auto v = r.scalars(key);
  if (static_cast<int>(v.size()) != ctx.dimension)
    throw InputError(where_of(r, key), std::string(key) + ": expected " + std::to_string(ctx.dimension) +
                                           " components (one per dimension), found " + std::to_string(v.size()));
  for (std::size_t d = 0; d < v.size() && d < 3; ++d) p[d] = v[d];
  return p;
}

std::string zero_direction(const std::string& key, const std::string& found) {
  return key + ": expected a non-zero direction (it is normalised), found " + found;
}

bool zero_vector(const Dictionary& d, const char* key) {
  const Entry* e = d.find(key);
  if (!e || e->items().size() != 1 || e->items()[0].kind() != Item::Kind::list) return false;
  for (const Item& x : e->items()[0].list())
    if (x.kind() != Item::Kind::number || x.number() != 0) return false;
  return true;
}

int given_dimension(const Dictionary& d, std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (const Entry* e = d.find(k); e && e->items().size() == 1 && e->items()[0].kind() == Item::Kind::list)
      return static_cast<int>(e->items()[0].list().size());
  return 0;
}

Vec3 read_direction(const ParamReader& r, const char* key, const SolverContext& ctx, Vec3 def) {
  Vec3 v = r.has(key) ? read_point(r, key, ctx) : def;
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(len > 0) || !std::isfinite(len))
    throw InputError(where_of(r, key), zero_direction(key, r.has(key) ? r.entry(key).value_string() : "zero"));
  for (auto& c : v) c /= len;
  return v;
}

Vec3 default_up(const SolverContext& ctx) {
  Vec3 g{0, 0, 0};
  for (std::size_t d = 0; d < ctx.gravity.size() && d < 3; ++d) g[d] = -ctx.gravity[d];
  const double len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (len > 0) {
    for (auto& c : g) c /= len;
    return g;
  }
  return ctx.dimension == 3 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
}

const FieldData& require_field(const BodySnapshot& b, const std::string& name, const std::string& who) {
  if (const FieldData* f = b.find(name)) return *f;
  std::vector<std::string> have;
  for (const auto& f : b.fields) have.push_back(f.name);
  throw std::runtime_error(who + ": body '" + b.name + "' has no field '" + name + "' (its fields: " + join(have) +
                           ")");
}

std::vector<std::pair<std::string, int>> component_suffixes(int components, int dimension) {
  std::vector<std::pair<std::string, int>> out;
  if (components == 1) {
    out.emplace_back("", 0);
  } else if (components == 3) {
    static const char* s[] = {"_x", "_y", "_z"};
    for (int c = 0; c < (dimension == 3 ? 3 : 2); ++c) out.emplace_back(s[c], c);
  } else if (components == 6) {
    static const char* s[] = {"_xx", "_yy", "_zz", "_xy", "_yz", "_zx"};
    for (int c = 0; c < (dimension == 3 ? 6 : 4); ++c) out.emplace_back(s[c], c);
  } else {
    for (int c = 0; c < components; ++c) {
      std::string suffix(1, '_');
      suffix += std::to_string(c);
      out.emplace_back(std::move(suffix), c);
    }
  }
  return out;
}

}  // namespace scree::fo

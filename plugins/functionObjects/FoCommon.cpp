// Shared pieces of the function objects (see FoCommon.hpp).
#include "FoCommon.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree::fo {

/// "a, b, c" (FoCommon.hpp).
std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

namespace {

std::string header_line(const std::vector<std::string>& header) {
  std::string line;
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (i) line += ',';
    line += csv_text(header[i]);
  }
  return line;
}

}  // namespace

std::string csv_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (v == 0) v = 0;  // no "-0"
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string time_name(double t) {
  if (t == 0) t = 0;  // no "-0"
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.8g", t);
  return buf;
}

std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cells.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}

// ------------------------------------------------------------------ CsvFile

void CsvFile::open(const fs::path& path, const std::vector<std::string>& header, double start_time) {
  path_ = path;
  columns_ = header.size();
  const std::string head = header_line(header);
  if (out_.is_open()) out_.close();
  fs::create_directories(path.parent_path());

  bool append = false;
  if (start_time > 0 && fs::exists(path)) {
    // Restart: keep the header and the rows before start_time (complete lines only),
    // rewritten atomically, then append after them.
    std::ifstream in(path);
    std::string line;
    std::vector<std::string> keep;
    if (std::getline(in, line) && line == head) {
      const double eps = 1e-9 * std::max(1.0, start_time);
      while (std::getline(in, line)) {
        if (in.eof()) break;  // a last line without '\n' was cut short by a kill
        const auto cells = csv_split(line);
        char* end = nullptr;
        const double t = std::strtod(cells[0].c_str(), &end);
        if (end == cells[0].c_str() || !(t < start_time - eps)) break;
        keep.push_back(line);
      }
      write_file_atomically(path, [&](const fs::path& tmp) {
        std::ofstream o(tmp, std::ios::trunc);
        o << head << '\n';
        for (const auto& l : keep) o << l << '\n';
        o.close();
        if (!o) throw std::runtime_error("cannot write " + tmp.string());
      });
      append = true;
    } else {
      std::cerr << "warning: " << path.string() << " has other columns than this run writes; it is replaced\n";
    }
  }
  out_.open(path, append ? std::ios::app : std::ios::trunc);
  if (!out_)
    throw std::runtime_error("cannot open " + path.string() + " for writing: " +
                             std::system_category().message(errno));
  if (!append) out_ << head << '\n' << std::flush;
  if (!out_) throw std::runtime_error("cannot write " + path.string());
}

void CsvFile::row(const std::vector<double>& values) {
  std::vector<std::string> cells;
  cells.reserve(values.size());
  for (double v : values) cells.push_back(csv_number(v));
  row_text(cells);
}

void CsvFile::open_at_first_row(const fs::path& path, std::vector<std::string> header, double start_time,
                                const std::string& who) {
  check_writable_dir(path.parent_path(), who);
  path_ = path;
  pending_ = std::make_unique<Pending>(Pending{std::move(header), start_time, who});
}

void CsvFile::row_text(const std::vector<std::string>& cells) {
  if (!out_.is_open() && pending_) {
    const auto p = std::move(pending_);
    ensure_writable_dir(path_.parent_path(), p->who);
    open(path_, p->header, p->start_time);
  }
  if (!out_.is_open()) throw std::logic_error("CsvFile::row on a file that is not open");
  if (cells.size() != columns_)
    throw std::logic_error(path_.string() + ": a row of " + std::to_string(cells.size()) + " cells for " +
                           std::to_string(columns_) + " columns");
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += cells[i];
  }
  out_ << line << '\n' << std::flush;
  if (!out_) throw std::runtime_error("cannot write " + path_.string() + " (disk full?)");
}

// ------------------------------------------------------------------ LostPoints

LostPoints::LostPoints(const SolverContext& ctx, std::string who)
    : path_(ctx.post_processing_dir() / "lostPoints.csv"), start_time_(ctx.start_time), who_(std::move(who)) {}

std::int64_t LostPoints::record(const Snapshot& s, const std::vector<std::string>& bodies) {
  if (!started_) {
    started_ = true;
    std::error_code ec;
    if (start_time_ <= 0 && !path_.empty()) fs::remove(path_, ec);  // an earlier run's
  }
  std::int64_t lost = 0;
  for (const auto& b : s.bodies)
    if (selected(bodies, b))
      for (Index p = 0; p < b.n; ++p) lost += b.is_lost(p);
  if (lost > 0 && !path_.empty()) {
    if (!csv_.is_open()) {
      ensure_writable_dir(path_.parent_path(), who_);
      csv_.open(path_, {"time [s]", "lost points [-]"}, start_time_);
    }
    csv_.row({s.time, static_cast<double>(lost)});
  }
  return lost;
}

// ------------------------------------------------------------------ helpers

void ensure_writable_dir(const fs::path& dir, const std::string& who) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error(who + ": cannot create the output directory " + dir.string() + ": " +
                             (ec ? ec.message() : "a file of that name exists"));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw std::runtime_error(who + ": the output directory " + dir.string() +
                             " is not writable: " + std::system_category().message(errno));
}

void check_writable_dir(const fs::path& dir, const std::string& who) {
  std::error_code ec;
  fs::path p = dir;
  while (!p.empty() && !fs::exists(p, ec) && p.has_relative_path() && p != p.parent_path()) p = p.parent_path();
  if (p.empty()) p = ".";
  if (!fs::is_directory(p, ec))
    throw std::runtime_error(who + ": cannot create the output directory " + dir.string() + ": " + p.string() +
                             " is not a directory");
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw std::runtime_error(who + ": the output directory " + dir.string() + " cannot be made or written: " +
                             p.string() + ": " + std::system_category().message(errno));
}

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
  if (!e || e->items().size() != 1 || e->items()[0].kind != Item::Kind::list) return false;
  for (const Item& x : e->items()[0].list)
    if (x.kind != Item::Kind::number || x.number != 0) return false;
  return true;
}

int given_dimension(const Dictionary& d, std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (const Entry* e = d.find(k); e && e->items().size() == 1 && e->items()[0].kind == Item::Kind::list)
      return static_cast<int>(e->items()[0].list.size());
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

// Ensembles: the dictionary, the members' values and cases, the summary's statistics
// (scree/ensemble/ensemble.hpp). The run of the members is ensemble_run.cpp.
#include "scree/ensemble/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <regex>
#include <set>

#include "scree/output/csv_file.hpp"

namespace fs = std::filesystem;

namespace scree {

namespace {

constexpr std::int64_t kMaxMembers = 100000;

// ------------------------------------------------------------------ draws

/// splitmix64's finaliser: a bijection of 64-bit words whose outputs pass BigCrush for
/// consecutive inputs (Steele, Lea & Flood 2014).
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

/// The draw of parameter `name` for member k: uniform in (0, 1), a function of the seed,
/// the name and k only (so that members added later leave the earlier ones as they were).
double draw(std::uint64_t seed, const std::string& name, std::int64_t k) {
  const std::uint64_t x = mix64(mix64(seed ^ mix64(fnv1a(name))) + 0x9e3779b97f4a7c15ULL * (static_cast<std::uint64_t>(k) + 1));
  return (static_cast<double>(x >> 11) + 0.5) * 0x1.0p-53;
}

/// The standard normal distribution function.
double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// Its inverse: Acklam's rational approximation (relative error 1.15e-9) refined by one
/// step of Halley's method on normal_cdf, which takes it to double precision.
double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (p <= 0) return -std::numeric_limits<double>::infinity();
  if (p >= 1) return std::numeric_limits<double>::infinity();
  const double plow = 0.02425;
  double x;
  if (p < plow) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - plow) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  const double e = normal_cdf(x) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

/// A number as the members' dictionaries write it: the shortest text that reads back the
/// same double.
std::string number_text(double v) { return Item::make_number(v, false).to_string(); }

// ------------------------------------------------------------------ the dictionary

std::string describe_keys(const std::vector<std::string>& keys) {
  std::string s;
  for (std::size_t i = 0; i < keys.size(); ++i) s += (i ? ", " : "") + keys[i];
  return s;
}

/// Unknown keys of `d` as errors naming the valid ones.
void check_keys(const Dictionary& d, const std::vector<std::string>& valid, const std::string& what,
                std::vector<InputError>& errors) {
  for (const Entry& e : d.entries())
    if (std::find(valid.begin(), valid.end(), e.key()) == valid.end())
      errors.emplace_back(e.where(), "unknown entry '" + e.key() + "' in " + what + " (valid: " +
                                         describe_keys(valid) + ")");
}

std::vector<std::string> split_path(const std::string& s) {
  std::vector<std::string> out;
  std::string part;
  for (char c : s) {
    if (c == '/') {
      out.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  out.push_back(part);
  return out;
}

std::string join_path(const std::vector<std::string>& p) {
  std::string s;
  for (std::size_t i = 0; i < p.size(); ++i) s += (i ? "/" : "") + p[i];
  return s;
}

/// The file read as a dictionary, or nullopt when it is not one (a data file, a table, a
/// fragment that only reads inside the file that includes it).
std::optional<Dictionary> read_dictionary(const fs::path& file, const fs::path& rel) {
  try {
    return Dictionary::read_file(file, rel.string());
  } catch (const InputError&) {
    return std::nullopt;
  } catch (const InputErrors&) {
    return std::nullopt;
  }
}

/// Files and folders of a case that are not its input: everything outside system/ and
/// constant/ (results, the ensemble's members, a README, figures), and what runs leave.
bool left_by_a_run(const fs::path& rel) {
  const std::string name = rel.filename().string();
  if (name.empty() || name[0] == '.' || name.ends_with(".lock")) return true;
  if (name == "VTK" || name == "postProcessing" || name == "checkpoints" || name == "log.scree") return true;
  return rel.begin() == rel.end() || (*rel.begin() != "system" && *rel.begin() != "constant");
}

void read_parameter(const Entry& pe, const fs::path& case_dir, EnsembleParameter& p,
                    std::vector<InputError>& errors) {
  const std::string what = "parameter '" + pe.key() + "' of " + std::string(EnsembleSpec::kFile);
  if (!pe.is_dict()) {
    errors.emplace_back(pe.where(), what + ": expected a dictionary { file ...; entry ...; values (...); } "
                                           "(or range { } or distribution { } instead of values)");
    return;
  }
  const Dictionary& d = pe.dict();
  check_keys(d, {"file", "entry", "values", "range", "distribution"}, what, errors);
  p.name = pe.key();
  p.where = pe.where();
  try {
    p.file = d.get_word("file");
    p.entry = split_path(d.get_word("entry"));
  } catch (const InputError& e) {
    errors.push_back(e);
    return;
  }
  const int kinds = d.has("values") + d.has("range") + d.has("distribution");
  if (kinds != 1) {
    errors.emplace_back(d.where(), what + ": give exactly one of values (...), range { from; to; count; } and "
                                          "distribution { type ...; } (found " + std::to_string(kinds) + ")");
    return;
  }
  try {
    if (const Entry* v = d.find("values")) {
      const std::span<const Item> items = v->items();
      if (v->is_dict() || items.size() != 1 || items[0].kind() != Item::Kind::list || items[0].list().empty())
        throw InputError(v->where(), what + ": values: expected a list of one or more values, e.g. (28 30 32)");
      for (const Item& it : items[0].list()) p.values.push_back(it.to_string());
    } else if (const Entry* r = d.find("range")) {
      const Dictionary& rd = r->dict();
      check_keys(rd, {"from", "to", "count"}, what + " range", errors);
      const double from = rd.get_scalar("from"), to = rd.get_scalar("to");
      const long long n = rd.get_integer("count");
      if (n < 2 || n > kMaxMembers)
        throw InputError(rd.at("count").where(), what + ": range count must be 2 to " +
                                                     std::to_string(kMaxMembers) + ", found " + std::to_string(n));
      for (long long i = 0; i < n; ++i)
        p.values.push_back(number_text(from + (to - from) * static_cast<double>(i) / static_cast<double>(n - 1)));
    } else {
      const Entry& de = *d.find("distribution");
      const Dictionary& dd = de.dict();
      const std::string type = dd.get_word("type");
      p.kind = EnsembleParameter::Kind::distribution;
      const std::string law = what + ": distribution " + type;
      if (type == "uniform") {
        check_keys(dd, {"type", "lower", "upper"}, law, errors);
        p.law = EnsembleParameter::Law::uniform;
        p.lower = dd.get_scalar("lower");
        p.upper = dd.get_scalar("upper");
      } else if (type == "normal" || type == "lognormal") {
        check_keys(dd, {"type", "mean", "standardDeviation", "lower", "upper"}, law, errors);
        p.law = type == "normal" ? EnsembleParameter::Law::normal : EnsembleParameter::Law::lognormal;
        p.mean = dd.get_scalar("mean");
        p.sd = dd.get_scalar("standardDeviation");
        p.lower = dd.get_scalar_or("lower", type == "normal" ? -1e300 : 0.0);
        p.upper = dd.get_scalar_or("upper", 1e300);
        if (!(p.sd > 0)) throw InputError(dd.at("standardDeviation").where(), law + ": standardDeviation must be > 0");
        if (type == "lognormal" && !(p.mean > 0))
          throw InputError(dd.at("mean").where(), law + ": the mean of a lognormal quantity must be > 0");
        if (type == "lognormal" && p.lower < 0)
          throw InputError(dd.at("lower").where(), law + ": a lognormal quantity is positive: lower must be >= 0");
      } else {
        throw InputError(dd.at("type").where(), law + ": unknown distribution type '" + type +
                                                    "' (valid: uniform, normal, lognormal)");
      }
      if (!(p.lower < p.upper))
        throw InputError(dd.where(), law + ": lower (" + number_text(p.lower) + ") must be below upper (" +
                                         number_text(p.upper) + ")");
      // A truncation that leaves (almost) nothing of the distribution is a slip.
      if (p.law != EnsembleParameter::Law::uniform) {
        const double lo = p.quantile(1e-300), hi = p.quantile(1 - 1e-16);
        if (!(std::isfinite(lo) && std::isfinite(hi)))
          throw InputError(dd.where(), law + ": [lower, upper] holds no probability of this distribution");
      }
    }
  } catch (const InputError& e) {
    errors.push_back(e);
    return;
  }
  // The file and the entry's place in it.
  const fs::path file = case_dir / p.file;
  if (p.file.is_absolute() || !fs::is_regular_file(file) || left_by_a_run(p.file)) {
    errors.emplace_back(d.at("file").where(), what + ": file " + p.file.string() +
                                                 " is not a file of the case's system/ or constant/ (a path relative to "
                                                 "the case directory, e.g. constant/materialProperties)");
    return;
  }
  try {
    const Dictionary base = Dictionary::read_file(file, p.file.string());  // its own errors, located
    const Dictionary* at = &base;
    for (std::size_t i = 0; i + 1 < p.entry.size(); ++i) {
      const Entry* e = at->find(p.entry[i]);
      if (!e || !e->is_dict()) {
        std::vector<std::string> subs;
        for (const Entry& s : at->entries())
          if (s.is_dict()) subs.push_back(s.key());
        throw InputError(d.at("entry").where(),
                         what + ": entry " + join_path(p.entry) + ": " + p.file.string() + " has no dictionary '" +
                             join_path({p.entry.begin(), p.entry.begin() + static_cast<std::ptrdiff_t>(i) + 1}) +
                             "' (its dictionaries there: " + (subs.empty() ? "none" : describe_keys(subs)) + ")");
      }
      at = &e->dict();
    }
    if (const Entry* e = at->find(p.entry.back()); e && e->is_dict())
      throw InputError(d.at("entry").where(), what + ": entry " + join_path(p.entry) + " is a dictionary in " +
                                                  p.file.string() + ": name one of its entries");
  } catch (const InputError& e) {
    errors.push_back(e);
  }
}

void read_quantity_spec(const Entry& qe, EnsembleQuantity& q, std::vector<InputError>& errors) {
  const std::string what = "summary quantity '" + qe.key() + "'";
  if (!qe.is_dict()) {
    errors.emplace_back(qe.where(), what + ": expected { file postProcessing/<name>/<file>.csv; column <name>; "
                                           "at end|max|min|<time>; }");
    return;
  }
  const Dictionary& d = qe.dict();
  check_keys(d, {"file", "column", "at"}, what, errors);
  q.name = qe.key();
  q.where = qe.where();
  try {
    q.file = d.get_word("file");
    q.column = d.get_word("column");
    if (const Entry* a = d.find("at")) {
      const Item& it = a->single_item();
      if (it.kind() == Item::Kind::number) {
        q.at = EnsembleQuantity::At::time;
        q.time = it.number();
      } else {
        const std::string w = a->as_word();
        if (w == "end") q.at = EnsembleQuantity::At::end;
        else if (w == "max") q.at = EnsembleQuantity::At::max;
        else if (w == "min") q.at = EnsembleQuantity::At::min;
        else throw InputError(a->where(), what + ": at: expected end, max, min or a time in seconds, found '" + w + "'");
      }
    }
  } catch (const InputError& e) {
    errors.push_back(e);
  }
}

/// Set `path` in `d` to the items of `value` (copying the sub-dictionaries on the way).
void set_path(Dictionary& d, const std::vector<std::string>& path, std::size_t i, const std::vector<Item>& value,
              SourcePos where) {
  if (i + 1 == path.size()) {
    d.set(Entry(path[i], where, value));
    return;
  }
  const Entry* e = d.find(path[i]);
  auto sub = std::make_shared<Dictionary>(e->dict());
  set_path(*sub, path, i + 1, value, where);
  d.set(Entry(path[i], e->pos(), std::shared_ptr<const Dictionary>(std::move(sub))));
}

}  // namespace

// ------------------------------------------------------------------ EnsembleParameter

double EnsembleParameter::quantile(double u) const {
  switch (law) {
    case Law::uniform: return lower + u * (upper - lower);
    case Law::normal: {
      const double a = normal_cdf((lower - mean) / sd), b = normal_cdf((upper - mean) / sd);
      return mean + sd * normal_quantile(a + u * (b - a));
    }
    case Law::lognormal: {
      // mean and sd of the quantity: ln X is normal with s^2 = ln(1 + (sd/mean)^2) and
      // m = ln(mean) - s^2/2.
      const double s = std::sqrt(std::log1p((sd / mean) * (sd / mean))), m = std::log(mean) - s * s / 2;
      const double a = lower > 0 ? normal_cdf((std::log(lower) - m) / s) : 0.0;
      const double b = upper < 1e300 ? normal_cdf((std::log(upper) - m) / s) : 1.0;
      return std::exp(m + s * normal_quantile(a + u * (b - a)));
    }
  }
  return 0;
}

// ------------------------------------------------------------------ EnsembleSpec

bool EnsembleSpec::present(const fs::path& case_dir) { return fs::exists(case_dir / kFile); }

EnsembleSpec EnsembleSpec::read(const fs::path& case_dir) {
  const Dictionary d = Dictionary::read_file(case_dir / kFile, kFile);
  std::vector<InputError> errors;
  check_keys(d, {"seed", "samples", "membersAtOnce", "writers", "parameters", "summary"}, kFile, errors);
  EnsembleSpec s;
  try {
    const long long seed = d.get_integer_or("seed", 0);
    if (seed < 0) throw InputError(d.at("seed").where(), "seed must be >= 0, found " + std::to_string(seed));
    s.seed = static_cast<std::uint64_t>(seed);
    s.samples = d.get_integer_or("samples", 1);
    if (s.samples < 1 || s.samples > kMaxMembers)
      throw InputError(d.at("samples").where(), "samples must be 1 to " + std::to_string(kMaxMembers) + ", found " +
                                                    std::to_string(s.samples));
    s.writers = d.get_bool_or("writers", true);
    s.members_at_once = d.get_integer_or("membersAtOnce", 0);
    if (d.has("membersAtOnce") && s.members_at_once < 1)
      throw InputError(d.at("membersAtOnce").where(), "membersAtOnce must be >= 1, found " +
                                                          std::to_string(s.members_at_once));
  } catch (const InputError& e) {
    errors.push_back(e);
  }
  const Entry* pe = d.find("parameters");
  if (!pe || !pe->is_dict() || pe->dict().entries().size() == 0) {
    errors.emplace_back(pe ? pe->where() : d.where(),
                        "an ensemble needs parameters { <name> { file ...; entry ...; values (...); } ... } naming "
                        "at least one entry of the case to vary");
  } else {
    std::set<std::pair<fs::path, std::string>> seen;
    for (const Entry& e : pe->dict().entries()) {
      EnsembleParameter p;
      const std::size_t before = errors.size();
      read_parameter(e, case_dir, p, errors);
      if (errors.size() != before) continue;
      if (!seen.insert({p.file.lexically_normal(), join_path(p.entry)}).second) {
        errors.emplace_back(e.where(), "parameter '" + p.name + "': another parameter sets " + p.file.string() +
                                           " " + join_path(p.entry) + " already");
        continue;
      }
      s.parameters.push_back(std::move(p));
    }
  }
  if (const Entry* se = d.find("summary")) {
    if (!se->is_dict()) {
      errors.emplace_back(se->where(), "summary: expected a dictionary of quantities { <name> { file ...; column "
                                        "...; at ...; } }");
    } else {
      for (const Entry& e : se->dict().entries()) {
        EnsembleQuantity q;
        const std::size_t before = errors.size();
        read_quantity_spec(e, q, errors);
        if (errors.size() != before) continue;
        for (const auto& p : s.parameters)
          if (p.name == q.name)
            errors.emplace_back(e.where(), "summary quantity '" + q.name + "' has the name of a parameter (" +
                                               p.where.str() + "): members.csv has a column for each; rename one");
        s.summary.push_back(std::move(q));
      }
    }
  }
  // An entry used as a $macro elsewhere: its uses were expanded where they stand when the
  // member's files are written out, so setting it would leave them as they were.
  if (!s.parameters.empty()) {
    static const std::regex macro(R"(\$\{?:?([A-Za-z0-9_.]+))");
    for (auto it = fs::recursive_directory_iterator(case_dir); it != fs::recursive_directory_iterator(); ++it) {
      const fs::path rel = it->path().lexically_relative(case_dir);
      if (left_by_a_run(rel)) {
        if (it->is_directory()) it.disable_recursion_pending();
        continue;
      }
      if (!it->is_regular_file() || it->file_size() > (1u << 20) || rel == kFile) continue;
      std::ifstream in(it->path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        const std::string code = line.substr(0, line.find("//"));
        for (auto m = std::sregex_iterator(code.begin(), code.end(), macro); m != std::sregex_iterator(); ++m) {
          const std::string name = (*m)[1];
          const std::string last = name.substr(name.rfind('.') == std::string::npos ? 0 : name.rfind('.') + 1);
          for (const auto& p : s.parameters)
            if (p.entry.back() == last)
              errors.emplace_back(p.where, "parameter '" + p.name + "': " + join_path(p.entry) + " is used as $" + name +
                                               " in " + rel.string() + ":" + std::to_string(n) +
                                               "; a member's files are written out with such uses expanded, so "
                                               "setting it would not change them: vary the entries that use it");
        }
      }
    }
  }
  const bool drawn = std::any_of(s.parameters.begin(), s.parameters.end(),
                                 [](const EnsembleParameter& p) { return p.kind == EnsembleParameter::Kind::distribution; });
  if (errors.empty() && s.samples > 1 && !drawn)
    errors.emplace_back(d.at("samples").where(), "samples " + std::to_string(s.samples) +
                                                     ": samples are draws of distributions, and no parameter has one "
                                                     "(give a parameter a distribution { }, or leave samples out)");
  if (errors.empty()) {
    double n = static_cast<double>(s.samples);
    for (const auto& p : s.parameters)
      if (p.kind == EnsembleParameter::Kind::values) n *= static_cast<double>(p.values.size());
    if (n > kMaxMembers)
      errors.emplace_back(pe->where(), "the ensemble has " + number_text(n) + " members, more than " +
                                           std::to_string(kMaxMembers) + ": fewer values or samples");
  }
  if (!errors.empty()) throw InputErrors(std::move(errors));
  return s;
}

std::int64_t EnsembleSpec::members() const {
  std::int64_t n = samples;
  for (const auto& p : parameters)
    if (p.kind == EnsembleParameter::Kind::values) n *= static_cast<std::int64_t>(p.values.size());
  return n;
}

std::vector<std::string> EnsembleSpec::member_values(std::int64_t k) const {
  // k = combination * samples + sample; the combination's digits run over the listed
  // parameters, the last one fastest.
  std::vector<std::string> out(parameters.size());
  std::int64_t combo = k / samples;
  for (std::size_t i = parameters.size(); i-- > 0;) {
    const EnsembleParameter& p = parameters[i];
    if (p.kind != EnsembleParameter::Kind::values) continue;
    const auto n = static_cast<std::int64_t>(p.values.size());
    out[i] = p.values[static_cast<std::size_t>(combo % n)];
    combo /= n;
  }
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (parameters[i].kind == EnsembleParameter::Kind::distribution)
      out[i] = number_text(parameters[i].quantile(draw(seed, parameters[i].name, k)));
  return out;
}

fs::path member_dir(const fs::path& case_dir, std::int64_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "member_%04lld", static_cast<long long>(k));
  return case_dir / "ensemble" / name;
}

// ------------------------------------------------------------------ a member's case

void write_member_case(const fs::path& case_dir, const EnsembleSpec& spec, std::int64_t k, const fs::path& dest) {
  const std::vector<std::string> values = spec.member_values(k);
  const fs::path tmp = dest.parent_path() / ("." + dest.filename().string() + ".tmp");
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::set<std::size_t> applied;
  for (auto it = fs::recursive_directory_iterator(case_dir); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path rel = it->path().lexically_relative(case_dir);
    if (left_by_a_run(rel) || rel == EnsembleSpec::kFile) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory()) {
      fs::create_directories(tmp / rel);
      continue;
    }
    if (!it->is_regular_file()) continue;
    std::optional<Dictionary> read = read_dictionary(it->path(), rel);
    if (!read) {  // copied as it is (a dictionary with errors: the member's check names them)
      fs::copy_file(it->path(), tmp / rel, fs::copy_options::overwrite_existing);
      continue;
    }
    Dictionary& d = *read;
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
      const EnsembleParameter& p = spec.parameters[i];
      if (p.file.lexically_normal() != rel.lexically_normal()) continue;
      const Dictionary v = Dictionary::parse("v " + values[i] + ";", std::string(EnsembleSpec::kFile));
      const std::span<const Item> items = v.at("v").items();
      set_path(d, p.entry, 0, std::vector<Item>(items.begin(), items.end()), SourcePos::of(p.where));
      applied.insert(i);
    }
    if (!spec.writers && rel.lexically_normal() == fs::path("system/controlDict") && d.has("writers"))
      d.set(Entry("writers", d.find("writers")->pos(), std::make_shared<const Dictionary>()));
    std::string text = "// Member " + std::to_string(k) + " of the ensemble of " + fs::absolute(case_dir).lexically_normal().string() +
                       " (system/ensembleDict):\n// " + rel.string() + " written out whole";
    for (std::size_t i = 0; i < spec.parameters.size(); ++i)
      if (spec.parameters[i].file.lexically_normal() == rel.lexically_normal())
        text += ", " + join_path(spec.parameters[i].entry) + " = " + values[i];
    if (!spec.writers && rel.lexically_normal() == fs::path("system/controlDict")) text += ", without writers";
    text += ".\n\n" + d.to_string();
    // The text reads back as the same dictionary (it is what the member runs).
    if (Dictionary::parse(text, rel.string()).to_string() != d.to_string())
      throw std::runtime_error("ensemble: " + rel.string() + " of member " + std::to_string(k) +
                               " does not read back as written; please report this case");
    std::ofstream out(tmp / rel, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + (tmp / rel).string() + " (disk full?)");
  }
  for (std::size_t i = 0; i < spec.parameters.size(); ++i)
    if (!applied.count(i))
      throw InputError(spec.parameters[i].where, "parameter '" + spec.parameters[i].name + "': the case has no file " +
                                                     spec.parameters[i].file.string());
  fs::remove_all(dest);
  fs::rename(tmp, dest);
}

// ------------------------------------------------------------------ the summary

std::optional<double> read_quantity(const fs::path& member, const EnsembleQuantity& q, std::string& why) {
  std::ifstream in(member / q.file);
  if (!in) {
    why = "no file " + q.file.string();
    return std::nullopt;
  }
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_split(line);
  // A column named as in the header, or without its unit ("runout" for "runout [m]").
  std::size_t col = header.size();
  for (std::size_t i = 0; i < header.size(); ++i) {
    const std::string bare = header[i].substr(0, header[i].find(" ["));
    if (header[i] == q.column || bare == q.column) col = i;
  }
  if (col == header.size() || (col == 0 && q.at == EnsembleQuantity::At::time)) {
    why = q.file.string() + " has no column '" + q.column + "' (its columns: " + line + ")";
    return std::nullopt;
  }
  std::optional<double> out;
  double best_dt = 1e300;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = csv_split(line);
    if (cells.size() <= col) continue;  // a row being written when the run stopped
    double t = 0, v = 0;
    try {
      t = std::stod(cells[0]);
      v = std::stod(cells[col]);
    } catch (const std::exception&) {
      continue;
    }
    switch (q.at) {
      case EnsembleQuantity::At::end: out = v; break;
      case EnsembleQuantity::At::max: out = out ? std::max(*out, v) : v; break;
      case EnsembleQuantity::At::min: out = out ? std::min(*out, v) : v; break;
      case EnsembleQuantity::At::time:
        if (std::fabs(t - q.time) < best_dt) {
          best_dt = std::fabs(t - q.time);
          out = v;
        }
        break;
    }
  }
  // At a time: the row at it (within the file's own rounding of times), not the nearest of a
  // run that stopped before it.
  if (q.at == EnsembleQuantity::At::time && out && best_dt > 1e-9 * std::max(1.0, std::fabs(q.time))) {
    why = q.file.string() + " has no row at t = " + number_text(q.time) + " s";
    return std::nullopt;
  }
  if (!out) why = q.file.string() + " has no rows";
  return out;
}

SampleStats sample_stats(std::vector<double> x) {
  SampleStats s;
  s.n = x.size();
  if (x.empty()) return s;
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  s.mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  double ss = 0;
  for (double v : x) ss += (v - s.mean) * (v - s.mean);
  s.sd = x.size() > 1 && x.front() != x.back() ? std::sqrt(ss / (n - 1)) : 0.0;
  auto pct = [&](double p) {
    const double h = (n - 1) * p;
    const auto lo = static_cast<std::size_t>(std::floor(h));
    const std::size_t hi = std::min(lo + 1, x.size() - 1);
    return x[lo] + (h - static_cast<double>(lo)) * (x[hi] - x[lo]);
  };
  s.min = x.front();
  s.max = x.back();
  s.p05 = pct(0.05);
  s.p25 = pct(0.25);
  s.p50 = pct(0.5);
  s.p75 = pct(0.75);
  s.p95 = pct(0.95);
  return s;
}

}  // namespace scree

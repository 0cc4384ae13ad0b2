// Parameter specs, whole-dictionary validation and reading with defaults.
#include "scree/params/spec.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace scree {

const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::scalar: return "scalar";
    case ParamType::integer: return "integer";
    case ParamType::boolean: return "bool";
    case ParamType::word: return "word";
    case ParamType::vector: return "vector";
    case ParamType::scalarList: return "scalarList";
    case ParamType::wordList: return "wordList";
    case ParamType::list: return "list";
    case ParamType::dict: return "dictionary";
    case ParamType::any: return "any";
    case ParamType::function: return "function of time";
  }
  return "?";
}

// ---------------------------------------------------------------- Param

Param::Param(std::string name, ParamType type, std::string unit, std::string doc)
    : name_(std::move(name)), type_(type), unit_(std::move(unit)), doc_(std::move(doc)) {}

Param& Param::default_value(std::string text) {
  default_ = std::move(text);
  return *this;
}
Param& Param::default_value(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back as v
  default_ = std::string(buf, r.ptr);
  return *this;
}
Param& Param::optional() {
  optional_ = true;
  return *this;
}
Param& Param::range(double lo, double hi) {
  lo_ = lo;
  hi_ = hi;
  return *this;
}
Param& Param::min(double lo) {
  lo_ = lo;
  return *this;
}
Param& Param::max(double hi) {
  hi_ = hi;
  return *this;
}
Param& Param::open_min() {
  lo_open_ = true;
  return *this;
}
Param& Param::open_max() {
  hi_open_ = true;
  return *this;
}
Param& Param::positive() {
  lo_ = 0.0;
  lo_open_ = true;
  return *this;
}
Param& Param::non_negative() {
  lo_ = 0.0;
  lo_open_ = false;
  return *this;
}
Param& Param::choices(std::vector<std::string> words) {
  choices_ = std::move(words);
  return *this;
}
Param& Param::size(int n) {
  size_ = n;
  return *this;
}
Param& Param::sub_spec(std::shared_ptr<const ParamSpec> s) {
  sub_ = std::move(s);
  return *this;
}
Param& Param::each_entry(std::shared_ptr<const ParamSpec> s) {
  each_ = std::move(s);
  return *this;
}

namespace {
std::string fmt(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}
std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}
}  // namespace

std::string Param::expectation() const {
  std::string e;
  switch (type_) {
    case ParamType::scalar: e = "a number"; break;
    case ParamType::integer: e = "a whole number"; break;
    case ParamType::boolean: e = "true or false"; break;
    case ParamType::word: e = choices_.empty() ? "a word" : "one of: " + join(choices_); break;
    case ParamType::vector:
      e = size_ > 0 ? "a vector of " + std::to_string(size_) + " numbers, e.g. (0 1)"
                    : (size_ < 0 ? "a vector with one number per dimension, e.g. (0 -9.81)"
                                 : "a vector of numbers");
      break;
    case ParamType::scalarList: e = "a list of numbers, e.g. (1 2 3)"; break;
    case ParamType::wordList: e = "a list of words, e.g. (a b)"; break;
    case ParamType::list: e = "a list ( ... )"; break;
    case ParamType::dict: e = "a dictionary { ... }"; break;
    case ParamType::any: e = "a value"; break;
    case ParamType::function:
      e = std::string(size_ == 0 ? "a function of time" : "a vector function of time") + " with values" + bounds() +
          " (" + function_forms() + ")";
      return e;
  }
  return e + bounds();
}

std::string Param::bounds() const {
  if (lo_ && hi_)
    return std::string(" in ") + (lo_open_ ? "(" : "[") + fmt(*lo_) + ", " + fmt(*hi_) + (hi_open_ ? ")" : "]");
  if (lo_) return std::string(lo_open_ ? " > " : " >= ") + fmt(*lo_);
  if (hi_) return std::string(hi_open_ ? " < " : " <= ") + fmt(*hi_);
  return "";
}

// ---------------------------------------------------------------- ParamSpec

ParamSpec::ParamSpec(std::string name, std::string doc) : name_(std::move(name)), doc_(std::move(doc)) {}

Param& ParamSpec::add(Param p) {
  for (auto& q : params_)
    if (q.name() == p.name()) {
      q = std::move(p);
      return q;
    }
  params_.push_back(std::move(p));
  return params_.back();
}
Param& ParamSpec::scalar(std::string n, std::string unit, std::string doc) {
  return add(Param(std::move(n), ParamType::scalar, std::move(unit), std::move(doc)));
}
Param& ParamSpec::integer(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::integer, "", std::move(doc)));
}
Param& ParamSpec::boolean(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::boolean, "", std::move(doc)));
}
Param& ParamSpec::word(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::word, "", std::move(doc)));
}
Param& ParamSpec::vector(std::string n, std::string unit, std::string doc) {
  return add(Param(std::move(n), ParamType::vector, std::move(unit), std::move(doc)));
}
Param& ParamSpec::scalar_list(std::string n, std::string unit, std::string doc) {
  return add(Param(std::move(n), ParamType::scalarList, std::move(unit), std::move(doc)));
}
Param& ParamSpec::word_list(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::wordList, "", std::move(doc)));
}
Param& ParamSpec::list(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::list, "", std::move(doc)));
}
Param& ParamSpec::dict(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::dict, "", std::move(doc)));
}
Param& ParamSpec::any(std::string n, std::string doc) {
  return add(Param(std::move(n), ParamType::any, "", std::move(doc)));
}
Param& ParamSpec::function(std::string n, std::string unit, std::string doc) {
  return add(Param(std::move(n), ParamType::function, std::move(unit), std::move(doc)));
}
ParamSpec& ParamSpec::allow_keys(std::vector<std::string> keys) {
  for (auto& k : keys)
    if (std::find(allowed_.begin(), allowed_.end(), k) == allowed_.end()) allowed_.push_back(std::move(k));
  return *this;
}
ParamSpec& ParamSpec::allow_unknown(bool yes) {
  allow_unknown_ = yes;
  return *this;
}
ParamSpec& ParamSpec::check(Check c) {
  checks_.push_back(std::move(c));
  return *this;
}
const Param* ParamSpec::find(std::string_view n) const {
  for (auto& p : params_)
    if (p.name() == n) return &p;
  return nullptr;
}

std::string ParamSpec::describe(int indent) const {
  std::ostringstream os;
  const std::string pad(indent, ' ');
  std::size_t w = 0;
  for (auto& p : params_) w = std::max(w, p.name().size());
  for (auto& p : params_) {
    os << pad << p.name() << std::string(w + 2 - p.name().size(), ' ') << to_string(p.type());
    if (!p.unit().empty() && p.unit() != "-") os << " [" << p.unit() << "]";
    if (p.required())
      os << ", required";
    else if (p.default_text())
      os << ", default " << *p.default_text();
    else
      os << ", optional";
    os << "\n" << pad << std::string(w + 2, ' ') << p.doc();
    const std::string e = p.expectation();
    if (p.type() == ParamType::function) {
      os << (p.bounds().empty() ? "" : " (values" + p.bounds() + ")") << "\n" << pad << std::string(w + 2, ' ')
         << "a function of time: " << function_forms();
      std::string units;
      for (const auto& [name, f] : units_of(p.unit())) units += (units.empty() ? "" : ", ") + name;
      os << "\n" << pad << std::string(w + 2, ' ') << "units: " << units;
    } else if (p.lower() || p.upper() || !p.choice_list().empty()) {
      os << " (" << e << ")";
    }
    os << "\n";
    if (p.sub()) os << p.sub()->describe(indent + int(w) + 4);
    if (p.each()) {
      os << pad << std::string(w + 2, ' ') << "each entry: a dictionary with\n";
      os << p.each()->describe(indent + int(w) + 4);
    }
  }
  return os.str();
}

// ---------------------------------------------------------------- validation

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
      const std::size_t sub = prev[j - 1] + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

void check_range(const Param& p, const Entry& e, double v, std::vector<InputError>& errors) {
  bool bad = false;
  if (!std::isfinite(v)) bad = true;
  if (p.lower()) bad |= p.lower_open() ? !(v > *p.lower()) : !(v >= *p.lower());
  if (p.upper()) bad |= p.upper_open() ? !(v < *p.upper()) : !(v <= *p.upper());
  if (bad) {
    std::string unit = (!p.unit().empty() && p.unit() != "-") ? " [" + p.unit() + "]" : "";
    errors.emplace_back(e.where(), p.name() + ": expected " + p.expectation() + unit + ", found " +
                                       e.value_string() + " (" + p.doc() + ")");
  }
}

void validate_value(const Param& p, const Entry& e, std::vector<InputError>& errors, int dimension) {
  try {
    switch (p.type()) {
      case ParamType::scalar: check_range(p, e, e.as_scalar(), errors); break;
      case ParamType::integer: check_range(p, e, static_cast<double>(e.as_integer()), errors); break;
      case ParamType::boolean: e.as_bool(); break;
      case ParamType::word: {
        const std::string w = e.as_word();
        const auto& c = p.choice_list();
        if (!c.empty() && std::find(c.begin(), c.end(), w) == c.end()) {
          std::string msg = p.name() + ": '" + w + "' is not valid; expected one of: " + join(c);
          const std::string near = nearest_name(w, c);
          if (!near.empty()) msg += " (did you mean '" + near + "'?)";
          errors.emplace_back(e.where(), msg);
        }
        break;
      }
      case ParamType::vector: {
        const auto v = e.as_scalar_list();
        const int want = p.vector_size() < 0 ? dimension : p.vector_size();
        if (want > 0 && static_cast<int>(v.size()) != want) {
          errors.emplace_back(e.where(), p.name() + ": expected " + std::to_string(want) + " components (" +
                                             (p.vector_size() < 0 ? "one per dimension" : "fixed size") +
                                             "), found " + std::to_string(v.size()) + ": " + e.value_string());
        } else {
          for (double x : v) check_range(p, e, x, errors);
        }
        break;
      }
      case ParamType::scalarList: {
        for (double x : e.as_scalar_list()) check_range(p, e, x, errors);
        break;
      }
      case ParamType::wordList: e.as_word_list(); break;
      case ParamType::list: {
        const Item& it = e.single_item();
        if (it.kind() != Item::Kind::list)
          errors.emplace_back(e.where(), p.name() + ": expected " + p.expectation() + ", found " + it.kind_name());
        break;
      }
      case ParamType::dict: {
        const Dictionary& d = e.dict();
        if (p.sub()) validate(*p.sub(), d, errors, dimension);
        if (p.each()) {
          for (const Entry& sub : d.entries()) {
            if (!sub.is_dict()) {
              errors.emplace_back(sub.where(), sub.key() + ": expected a dictionary { ... }, found " +
                                                   sub.value_string());
              continue;
            }
            validate(*p.each(), sub.dict(), errors, dimension);
          }
        }
        break;
      }
      case ParamType::any: break;
      case ParamType::function: {
        const int want = p.vector_size() < 0 ? dimension : p.vector_size();
        // A vector function's length is known once the dimension is (the file is read at setup).
        if (!(p.vector_size() < 0 && dimension <= 0)) read_function_table(p, e, std::max(want, 1), {});
        break;
      }
    }
  } catch (const InputError& err) {
    errors.push_back(err);
  }
}

}  // namespace

std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = static_cast<std::size_t>(-1);
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  // Close enough: at most a third of the letters differ (min 1, max 3).
  const std::size_t limit = std::clamp<std::size_t>(word.size() / 3, 1, 3);
  return best_d <= limit ? best : std::string();
}

void validate(const ParamSpec& spec, const Dictionary& dict, std::vector<InputError>& errors, int dimension) {
  const std::size_t before = errors.size();
  for (const Param& p : spec.params()) {
    const Entry* e = dict.find(p.name());
    if (!e) {
      if (p.required()) {
        std::string unit = (!p.unit().empty() && p.unit() != "-") ? " [" + p.unit() + "]" : "";
        errors.emplace_back(dict.where(), "missing required entry '" + p.name() + "' in '" + dict.name() +
                                              "': " + p.doc() + unit + ", expected " + p.expectation());
      }
      continue;
    }
    validate_value(p, *e, errors, dimension);
  }
  if (!spec.unknown_allowed()) {
    std::vector<std::string> valid;
    for (const Param& p : spec.params()) valid.push_back(p.name());
    for (const auto& k : spec.allowed_keys()) valid.push_back(k);
    for (const Entry& e : dict.entries()) {
      if (std::find(valid.begin(), valid.end(), e.key()) != valid.end()) continue;
      if (!e.key().empty() && e.key()[0] == '_') continue;  // a variable for $macros
      std::string msg = "unknown entry '" + e.key() + "' in '" + dict.name() + "'";
      const std::string near = nearest_name(e.key(), valid);
      if (!near.empty())
        msg += "; did you mean '" + near + "'?";
      else
        msg += "; valid entries: " + join(valid);
      errors.emplace_back(e.where(), msg);
    }
  }
  if (errors.size() == before)
    for (const auto& c : spec.checks()) c(dict, errors);
}

// ---------------------------------------------------------------- ParamReader

ParamReader::ParamReader(const ParamSpec& spec, const Dictionary& dict) : spec_(spec), dict_(dict) {}

const Entry& ParamReader::entry(std::string_view name) const {
  if (const Entry* e = dict_.find(name)) return *e;
  const Param* p = spec_.find(name);
  if (!p || !p->default_text())
    throw InputError(dict_.where(), "missing required entry '" + std::string(name) + "' in '" + dict_.name() + "'");
  auto d = std::make_unique<Dictionary>(
      Dictionary::parse(std::string(name) + " " + *p->default_text() + ";", "<default of " + spec_.name() + "." +
                                                                               std::string(name) + ">"));
  defaults_.push_back(std::move(d));
  return defaults_.back()->at(name);
}
double ParamReader::scalar(std::string_view n) const { return entry(n).as_scalar(); }
long long ParamReader::integer(std::string_view n) const { return entry(n).as_integer(); }
bool ParamReader::boolean(std::string_view n) const { return entry(n).as_bool(); }
std::string ParamReader::word(std::string_view n) const { return entry(n).as_word(); }
std::vector<double> ParamReader::scalars(std::string_view n) const { return entry(n).as_scalar_list(); }
std::vector<std::string> ParamReader::words(std::string_view n) const { return entry(n).as_word_list(); }
FunctionTable ParamReader::function(std::string_view n, int components, const std::filesystem::path& case_dir,
                                    const FunctionDefaults& defaults) const {
  const Param* p = spec_.find(n);
  if (!p) throw std::logic_error("ParamReader::function: '" + std::string(n) + "' is not in the spec of " + spec_.name());
  return read_function_table(*p, entry(n), components, case_dir, defaults);
}

}  // namespace scree

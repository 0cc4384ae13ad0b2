// Parameter specifications: what a plugin (or a core dictionary) accepts.
//
// Every plugin declares its parameters before anything is constructed: name, type,
// unit, required or default, allowed range or choices, one-line doc. The framework
// validates a whole case against the specs before it runs (validate() below collects
// every error with file:line), and `scree --list-plugins` prints the specs, so the
// documentation cannot drift from the code.
//
//   ParamSpec s("linearElastic", "Isotropic linear elasticity (Hooke's law)");
//   s.scalar("E", "Pa", "Young's modulus").positive();
//   s.scalar("nu", "-", "Poisson's ratio").range(-1.0, 0.5).open_max();
//   s.scalar("rho", "kg/m^3", "mass density").positive();
//   s.word("mode", "", "how to do it").choices({"a", "b"}).default_value("a");
//
// Then, after validation, read values with ParamReader (defaults applied):
//   ParamReader r(s, dict);  double E = r.scalar("E");
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/function_table.hpp"

namespace scree {

enum class ParamType {
  scalar,      ///< a real number
  integer,     ///< a whole number
  boolean,     ///< true/false, yes/no, on/off
  word,        ///< a word or quoted string
  vector,      ///< a list of numbers (size() fixes the length; -1: the case's dimension)
  scalarList,  ///< a list of numbers of any length
  wordList,    ///< a list of words or strings
  list,        ///< any list (validated by the plugin)
  dict,        ///< a sub-dictionary (validated against sub_spec if given)
  any,         ///< anything (validated by the plugin)
  function,    ///< a function of time: a constant, a table, a CSV file (function_table.hpp);
               ///< size() as for vector: 0 a scalar function, n or -1 (the dimension) a vector one
};

SCREE_API const char* to_string(ParamType t);

class ParamSpec;

/// One parameter. Built fluently from ParamSpec::scalar(...) etc.
class SCREE_API Param {
 public:
  Param(std::string name, ParamType type, std::string unit, std::string doc);

  // ---- declaration (fluent) ----
  /// Default value, written as it would be in a dictionary ("0.3", "(0 -9.81)", "linear").
  Param& default_value(std::string text);
  Param& default_value(double v);
  Param& optional();  ///< neither required nor defaulted (the plugin checks has())
  Param& range(double lo, double hi);
  Param& min(double lo);
  Param& max(double hi);
  Param& open_min();  ///< make the lower bound exclusive
  Param& open_max();  ///< make the upper bound exclusive
  Param& positive();  ///< > 0
  Param& non_negative();  ///< >= 0
  Param& choices(std::vector<std::string> words);
  Param& size(int n);  ///< vector length (-1: the case's dimension)
  Param& sub_spec(std::shared_ptr<const ParamSpec> s);
  /// A dictionary parameter whose entries are all dictionaries of the same kind
  /// (e.g. `materials { sand {...} clay {...} }`): each validated against `s`.
  Param& each_entry(std::shared_ptr<const ParamSpec> s);

  // ---- queries ----
  const std::string& name() const { return name_; }
  ParamType type() const { return type_; }
  const std::string& unit() const { return unit_; }
  const std::string& doc() const { return doc_; }
  bool required() const { return !default_ && !optional_; }
  const std::optional<std::string>& default_text() const { return default_; }
  const std::vector<std::string>& choice_list() const { return choices_; }
  std::optional<double> lower() const { return lo_; }
  std::optional<double> upper() const { return hi_; }
  bool lower_open() const { return lo_open_; }
  bool upper_open() const { return hi_open_; }
  int vector_size() const { return size_; }
  const ParamSpec* sub() const { return sub_.get(); }
  const ParamSpec* each() const { return each_.get(); }
  /// "a number in (0, 0.5]" and the like, for messages and docs.
  std::string expectation() const;
  /// The range alone: " in (0, 0.5]", " >= 0", or "" when unbounded.
  std::string bounds() const;

 private:
  std::string name_;
  ParamType type_;
  std::string unit_;
  std::string doc_;
  std::optional<std::string> default_;
  bool optional_ = false;
  std::optional<double> lo_, hi_;
  bool lo_open_ = false, hi_open_ = false;
  std::vector<std::string> choices_;
  int size_ = 0;  // 0: any length
  std::shared_ptr<const ParamSpec> sub_, each_;
};

/// The parameters of one plugin or one core dictionary.
class SCREE_API ParamSpec {
 public:
  ParamSpec() = default;
  ParamSpec(std::string name, std::string doc);

  Param& scalar(std::string name, std::string unit, std::string doc);
  Param& integer(std::string name, std::string doc);
  Param& boolean(std::string name, std::string doc);
  Param& word(std::string name, std::string doc);
  Param& vector(std::string name, std::string unit, std::string doc);
  Param& scalar_list(std::string name, std::string unit, std::string doc);
  Param& word_list(std::string name, std::string doc);
  Param& list(std::string name, std::string doc);
  Param& dict(std::string name, std::string doc);
  Param& any(std::string name, std::string doc);
  /// A function of time (function_table.hpp), in the SI unit `unit`; range checks apply to
  /// every value of its table.
  Param& function(std::string name, std::string unit, std::string doc);

  /// Keys that are accepted without a spec (e.g. `type`, which selected the plugin).
  ParamSpec& allow_keys(std::vector<std::string> keys);
  /// Accept any further key (for dictionaries whose entries are user-named).
  ParamSpec& allow_unknown(bool yes = true);
  /// A whole-dictionary check that runs after the per-key checks pass (e.g. "min < max").
  /// It appends errors to the list.
  using Check = std::function<void(const Dictionary&, std::vector<InputError>&)>;
  ParamSpec& check(Check c);

  const std::string& name() const { return name_; }
  const std::string& doc() const { return doc_; }
  const std::vector<Param>& params() const { return params_; }
  const Param* find(std::string_view name) const;
  const std::vector<std::string>& allowed_keys() const { return allowed_; }
  bool unknown_allowed() const { return allow_unknown_; }
  const std::vector<Check>& checks() const { return checks_; }

  /// Human-readable documentation of every parameter (for --list-plugins).
  std::string describe(int indent = 0) const;

 private:
  Param& add(Param p);
  std::string name_, doc_;
  std::vector<Param> params_;
  std::vector<std::string> allowed_;
  bool allow_unknown_ = false;
  std::vector<Check> checks_;
};

/// Validate `dict` against `spec`, appending every problem to `errors` (nothing thrown):
/// missing required keys, wrong types, out-of-range values, bad choices, unknown keys
/// (with "did you mean 'x'?" for near misses), and sub-dictionaries recursively.
/// Keys starting with '_' are variables for $macros (e.g. `_releaseTime 0.1;`) and are
/// never reported as unknown.
/// `dimension` fixes the length of vector parameters declared with size(-1).
SCREE_API void validate(const ParamSpec& spec, const Dictionary& dict, std::vector<InputError>& errors,
                        int dimension = 0);

/// The closest candidate within a small edit distance, or "" if none is close.
SCREE_API std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates);

/// Reads parameters of a validated dictionary, applying the spec's defaults.
class SCREE_API ParamReader {
 public:
  ParamReader(const ParamSpec& spec, const Dictionary& dict);
  double scalar(std::string_view name) const;
  long long integer(std::string_view name) const;
  bool boolean(std::string_view name) const;
  std::string word(std::string_view name) const;
  std::vector<double> scalars(std::string_view name) const;
  std::vector<std::string> words(std::string_view name) const;
  /// A function of time with `components` values a row (1: a scalar), its CSV file read
  /// relative to `case_dir`, its values converted to the parameter's SI unit.
  FunctionTable function(std::string_view name, int components, const std::filesystem::path& case_dir,
                         const FunctionDefaults& defaults = {}) const;
  bool has(std::string_view name) const { return dict_.has(name); }
  /// The entry if present, else the spec's default parsed as an entry.
  const Entry& entry(std::string_view name) const;
  const Dictionary& dict() const { return dict_; }
  const ParamSpec& spec() const { return spec_; }

 private:
  const ParamSpec& spec_;
  const Dictionary& dict_;
  mutable std::vector<std::unique_ptr<Dictionary>> defaults_;  // parsed default values
};

}  // namespace scree

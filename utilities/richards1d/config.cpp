// scree-richards config files.
//
//   // a comment, or # a comment
//   key value;                 the semicolon is optional; several "key value;" may share a line
//   profileTimes 0 10 50 200;  lists are numbers separated by blanks
//   include "base.conf";       read another file here (relative to this one); keys given
//                              after it, in this file or by --set, override its keys
//
// Every problem is reported, all together, as "file:line: key 'name': message"; a key that
// the chosen options do not use is a warning.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

#include "richards1d.hpp"

namespace scree::richards1d {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Kind { number, integer, word, list };

struct KeySpec {
  const char* name;
  Kind kind;
  const char* unit;
  const char* fallback;  // the default as written in --help; "" when required or conditional
  const char* help;
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;
  std::vector<std::string> choices = {};
};

// The keys. Ranges: [lo, hi] with open ends where marked.
const std::vector<KeySpec>& specs() {
  static const std::vector<KeySpec> k = {
      {"height", Kind::number, "m", "", "column height L (required)", 0, kInf, true},
      {"cells", Kind::integer, "-", "", "cells of the uniform grid (required); nodes at z = i L/cells", 2, 1e7},
      {"porosity", Kind::number, "-", "", "porosity n (required); theta = n S", 0, 1, true},
      {"rhoW", Kind::number, "kg/m^3", "1000", "liquid density rho_w", 0, kInf, true},
      {"g", Kind::number, "m/s^2", "9.81", "gravity", 0, kInf, true},
      {"retention", Kind::word, "", "", "retention model (required)", -kInf, kInf, false, false,
       {"vanGenuchten", "gardner"}},
      {"p0", Kind::number, "Pa", "", "vanGenuchten: S = Smin + (Smax-Smin)[1 + (s/p0)^(1/(1-lambda))]^-lambda",
       0, kInf, true},
      {"lambda", Kind::number, "-", "", "vanGenuchten: exponent (= m of van Genuchten; n_vG = 1/(1-lambda))", 0, 1,
       true, true},
      {"alpha", Kind::number, "1/m", "", "gardner: S_e = k_rel = exp(alpha h)", 0, kInf, true},
      {"Smin", Kind::number, "-", "0", "residual saturation", 0, 1, false, true},
      {"Smax", Kind::number, "-", "1", "saturation at zero suction", 0, 1, true},
      {"krelMin", Kind::number, "-", "1e-12", "floor on k_rel (keeps very dry cells coupled)", 0, 1, false, true},
      {"Ksat", Kind::number, "m/s", "", "saturated hydraulic conductivity (or intrinsicPermeability)", 0, kInf,
       true},
      {"intrinsicPermeability", Kind::number, "m^2", "", "kappa: Ksat = kappa rho_w g / viscosity", 0, kInf, true},
      {"viscosity", Kind::number, "Pa s", "1e-3", "dynamic viscosity mu (with intrinsicPermeability)", 0, kInf, true},
      {"specificStorage", Kind::number, "1/m", "0", "S_s (or liquidBulkModulus)", 0, kInf},
      {"liquidBulkModulus", Kind::number, "Pa", "", "K_l: S_s = n rho_w g / K_l", 0, kInf, true},
      {"oedometricModulus", Kind::number, "Pa", "0",
       "E_oed of a deformable skeleton (oedometric, Bishop chi = S): its storage S (S + p dS/dp)/E_oed; "
       "0: rigid", 0, kInf},
      {"waterLoad", Kind::word, "", "yes",
       "oedometricModulus > 0: the weight of the water gained or lost changes the total stress", -kInf, kInf,
       false, false, {"yes", "no"}},
      {"initial", Kind::word, "", "", "initial condition (required)", -kInf, kInf, false, false,
       {"hydrostatic", "uniform", "steadyFlux"}},
      {"waterTable", Kind::number, "m", "0", "hydrostatic: h = waterTable - z", -kInf, kInf},
      {"initialHead", Kind::number, "m", "", "uniform: h everywhere", -kInf, kInf},
      {"initialFlux", Kind::number, "m/s", "", "steadyFlux: the steady profile under this infiltration rate "
       "above the base head (needs bottom head)", 0, kInf},
      {"top", Kind::word, "", "", "top condition (required; flux ponds when the surface saturates)",
       -kInf, kInf, false, false, {"head", "flux"}},
      {"topHead", Kind::number, "m", "0", "head: h at the surface", -kInf, kInf},
      {"topFlux", Kind::number, "m/s", "", "flux: infiltration rate, downward positive", 0, kInf},
      {"pondingHead", Kind::number, "m", "0", "flux: the head held at the surface while ponded", -kInf, kInf},
      {"bottom", Kind::word, "", "", "bottom condition (required)", -kInf, kInf, false, false,
       {"head", "noFlux", "freeDrainage"}},
      {"bottomHead", Kind::number, "m", "0", "head: h at the base (a water table there: 0)", -kInf, kInf},
      {"conductivityMean", Kind::word, "", "arithmetic", "K between two nodes", -kInf, kInf, false, false,
       {"arithmetic", "geometric"}},
      {"endTime", Kind::number, "s", "", "end of the run (required)", 0, kInf, true},
      {"dtInitial", Kind::number, "s", "1e-3", "first time step", 0, kInf, true},
      {"dtMin", Kind::number, "s", "1e-9", "a step failing at this size stops the run", 0, kInf, true},
      {"dtMax", Kind::number, "s", "none", "largest time step", 0, kInf, true},
      {"picardTolerance", Kind::number, "m", "1e-8", "converged when max |delta h| < this", 0, kInf, true},
      {"picardMaxIterations", Kind::integer, "-", "30", "iterations before a step is cut", 2, 10000},
      {"fastIterations", Kind::integer, "-", "3", "converged within this many: dt *= dtGrow", 1, 10000},
      {"slowIterations", Kind::integer, "-", "8", "converged in this many or more: dt *= dtShrink", 1, 10000},
      {"dtGrow", Kind::number, "-", "1.25", "time step growth factor", 1, 10},
      {"dtShrink", Kind::number, "-", "0.7", "time step reduction after a slow step", 0, 1, true},
      {"timeTolerance", Kind::number, "m", "1e-6",
       "bound on the estimated local time error of h per step; 0: steps follow the Picard count only", 0, kInf},
      {"dtCut", Kind::number, "-", "0.5", "time step reduction after a failed step", 0, 1, true, true},
      {"profileTimes", Kind::list, "s", "0 endTime", "times of the rows of profiles.csv", 0, kInf},
      {"historyInterval", Kind::number, "s", "endTime/1000",
       "interval of the rows of surface.csv and front.csv; 0: every step", 0, kInf},
  };
  return k;
}

const KeySpec* find_spec(const std::string& name) {
  for (const auto& s : specs())
    if (name == s.name) return &s;
  return nullptr;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> d(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t prev = d[0];
    d[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cur = d[j];
      const bool same = std::tolower(a[i - 1]) == std::tolower(b[j - 1]);
      d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (same ? 0 : 1)});
      prev = cur;
    }
  }
  return d[b.size()];
}

std::string closest(const std::string& word, const std::vector<std::string>& options) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& o : options) {
    const std::size_t d = edit_distance(word, o);
    if (d < best_d) best_d = d, best = o;
  }
  return best;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::optional<double> to_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string number_text(double x) {
  std::ostringstream o;
  if (x == std::floor(x) && std::abs(x) < 1e15)
    o << static_cast<long long>(x);
  else
    o << x;
  return o.str();
}

struct Entry {
  std::vector<std::string> values;
  std::string where;  // "file:line"
  std::string file;   // the file (or "--set") that set it
  bool used = false;
};

class Parser {
 public:
  std::map<std::string, Entry> entries;
  std::vector<std::string> errors;

  void error(const std::string& where, const std::string& key, const std::string& msg) {
    errors.push_back(where + ": " + (key.empty() ? "" : "key '" + key + "': ") + msg);
  }

  void parse_text(const std::string& text, const std::string& file, const std::filesystem::path& dir, int depth) {
    std::istringstream in(text);
    std::string line;
    for (int lineno = 1; std::getline(in, line); ++lineno) {
      for (const char* c : {"//", "#"})
        if (const auto p = line.find(c); p != std::string::npos) line.erase(p);
      std::istringstream statements(line);
      std::string stmt;
      while (std::getline(statements, stmt, ';')) {
        std::istringstream words(stmt);
        std::vector<std::string> w;
        for (std::string x; words >> x;) w.push_back(x);
        if (w.empty()) continue;
        const std::string where = file + ":" + std::to_string(lineno);
        if (w[0] == "include") {
          if (w.size() != 2) {
            error(where, "", "include takes one file name");
            continue;
          }
          std::string name = w[1];
          if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
          if (depth > 8) {
            error(where, "", "includes nested deeper than 8 (a cycle?)");
            continue;
          }
          parse_file(dir / name, where, depth + 1);
          continue;
        }
        set(w[0], {w.begin() + 1, w.end()}, where, file);
      }
    }
  }

  void parse_file(const std::filesystem::path& path, const std::string& from, int depth) {
    std::ifstream f(path);
    if (!f) {
      error(from, "", "cannot open '" + path.string() + "'");
      return;
    }
    std::stringstream ss;
    ss << f.rdbuf();
    parse_text(ss.str(), path.string(), path.parent_path(), depth);
  }

  void set(const std::string& key, std::vector<std::string> values, const std::string& where,
           const std::string& file) {
    const KeySpec* spec = find_spec(key);
    if (!spec) {
      std::vector<std::string> names;
      for (const auto& s : specs()) names.emplace_back(s.name);
      const std::string guess = closest(key, names);
      error(where, key, "unknown key" + (guess.empty() ? std::string() : " (did you mean '" + guess + "'?)") +
                            "; scree-richards --help lists the keys");
      return;
    }
    if (auto it = entries.find(key); it != entries.end() && it->second.file == file && file != "--set") {
      error(where, key, "given twice (first at " + it->second.where + ")");
      return;
    }
    if (values.empty()) {
      error(where, key, "has no value");
      return;
    }
    const std::size_t before = errors.size();
    if (spec->kind != Kind::list && values.size() != 1) error(where, key, "takes one value");
    for (const auto& v : values) {
      if (spec->kind == Kind::word) {
        if (std::find(spec->choices.begin(), spec->choices.end(), v) == spec->choices.end()) {
          const std::string guess = closest(v, spec->choices);
          error(where, key, "'" + v + "' is not one of " + join(spec->choices) +
                                (guess.empty() ? "" : " (did you mean '" + guess + "'?)"));
        }
        continue;
      }
      const auto x = to_number(v);
      if (!x) {
        error(where, key, "'" + v + "' is not a number");
        continue;
      }
      if (spec->kind == Kind::integer && *x != std::floor(*x)) error(where, key, "'" + v + "' is not an integer");
      const bool below = spec->lo_open ? !(*x > spec->lo) : !(*x >= spec->lo);
      const bool above = spec->hi_open ? !(*x < spec->hi) : !(*x <= spec->hi);
      if (below || above) {
        std::ostringstream r;
        r << "value " << v << " is out of range: ";
        if (std::isinf(spec->hi))
          r << "must be " << (spec->lo_open ? "> " : ">= ") << number_text(spec->lo);
        else
          r << "must be in " << (spec->lo_open ? '(' : '[') << number_text(spec->lo) << ", " << number_text(spec->hi)
            << (spec->hi_open ? ')' : ']');
        if (*spec->unit && std::string(spec->unit) != "-") r << " [" << spec->unit << "]";
        error(where, key, r.str());
      }
    }
    if (errors.size() == before) entries[key] = Entry{std::move(values), where, file};
  }

  // Typed access: marks the key used. The value is valid (checked in set()).
  bool has(const std::string& k) const { return entries.count(k) > 0; }
  double number(const std::string& k, double fallback) {
    auto it = entries.find(k);
    if (it == entries.end()) return fallback;
    it->second.used = true;
    return *to_number(it->second.values[0]);
  }
  std::string word(const std::string& k, const std::string& fallback) {
    auto it = entries.find(k);
    if (it == entries.end()) return fallback;
    it->second.used = true;
    return it->second.values[0];
  }
  std::vector<double> list(const std::string& k) {
    std::vector<double> v;
    auto it = entries.find(k);
    if (it == entries.end()) return v;
    it->second.used = true;
    for (const auto& s : it->second.values) v.push_back(*to_number(s));
    return v;
  }
  std::string where(const std::string& k) const {
    auto it = entries.find(k);
    return it == entries.end() ? std::string() : it->second.where;
  }
};

Settings build(Parser& p, const std::string& name, std::vector<std::string>* warnings) {
  Settings s;
  // Missing keys are reported against the top-level file, without a line.
  auto require = [&](const std::string& k, const std::string& why = "") {
    if (p.has(k)) return true;
    p.error(name, k, "missing" + (why.empty() ? std::string() : " (" + why + ")"));
    return false;
  };
  for (const char* k : {"height", "cells", "porosity", "retention", "initial", "top", "bottom", "endTime"})
    require(k, "required");

  s.height = p.number("height", 0);
  s.cells = static_cast<int>(p.number("cells", 0));
  Soil& soil = s.soil;
  soil.porosity = p.number("porosity", 0);
  soil.rho_w = p.number("rhoW", 1000);
  soil.g = p.number("g", 9.81);
  soil.S_min = p.number("Smin", 0);
  soil.S_max = p.number("Smax", 1);
  if (soil.S_max <= soil.S_min)
    p.error(p.has("Smax") ? p.where("Smax") : p.where("Smin"), "Smax", "must exceed Smin");
  soil.kr_min = p.number("krelMin", 1e-12);

  const std::string retention = p.word("retention", "");
  if (retention == "vanGenuchten") {
    soil.retention = Retention::vanGenuchten;
    require("p0", "retention vanGenuchten");
    require("lambda", "retention vanGenuchten");
    soil.p0 = p.number("p0", 0);
    soil.lambda = p.number("lambda", 0);
  } else if (retention == "gardner") {
    soil.retention = Retention::gardner;
    require("alpha", "retention gardner");
    soil.alpha = p.number("alpha", 0);
  }

  if (p.has("Ksat") && p.has("intrinsicPermeability")) {
    p.error(p.where("intrinsicPermeability"), "intrinsicPermeability",
            "give Ksat or intrinsicPermeability, not both (Ksat at " + p.where("Ksat") + ")");
  } else if (p.has("intrinsicPermeability")) {
    // K = kappa rho_w g / mu  [m^2 kg/m^3 m/s^2 / (Pa s) = m/s]
    soil.K_sat = p.number("intrinsicPermeability", 0) * soil.rho_w * soil.g / p.number("viscosity", 1e-3);
  } else if (p.has("Ksat")) {
    soil.K_sat = p.number("Ksat", 0);
  } else {
    p.error(name, "Ksat", "missing (give Ksat or intrinsicPermeability)");
  }

  if (p.has("specificStorage") && p.has("liquidBulkModulus")) {
    p.error(p.where("liquidBulkModulus"), "liquidBulkModulus",
            "give specificStorage or liquidBulkModulus, not both (specificStorage at " + p.where("specificStorage") +
                ")");
  } else if (p.has("liquidBulkModulus")) {
    // Liquid compressibility: S_s = n rho_w g / K_l [1/m].
    soil.S_s = soil.porosity * soil.rho_w * soil.g / p.number("liquidBulkModulus", 1);
  } else {
    soil.S_s = p.number("specificStorage", 0);
  }

  // Deformable skeleton (richards1d.cpp, "Skeleton storage"): E_oed = E (1 - nu)/((1 + nu)(1 - 2 nu)).
  soil.E_oed = p.number("oedometricModulus", 0);
  if (soil.E_oed > 0) soil.water_load = p.word("waterLoad", "yes") == "yes";

  const std::string initial = p.word("initial", "");
  const std::string bottom = p.word("bottom", "");
  if (initial == "hydrostatic") {
    s.initial = InitialCondition::hydrostatic;
    s.water_table = p.number("waterTable", 0);
  } else if (initial == "uniform") {
    s.initial = InitialCondition::uniform;
    require("initialHead", "initial uniform");
    s.initial_head = p.number("initialHead", 0);
  } else if (initial == "steadyFlux") {
    s.initial = InitialCondition::steadyFlux;
    require("initialFlux", "initial steadyFlux");
    s.initial_flux = p.number("initialFlux", 0);
    if (!bottom.empty() && bottom != "head")
      p.error(p.where("initial"), "initial", "steadyFlux starts from the base head: needs bottom head");
  }

  const std::string top = p.word("top", "");
  if (top == "head") {
    s.top = TopCondition::head;
    s.top_head = p.number("topHead", 0);
  } else if (top == "flux") {
    s.top = TopCondition::flux;
    require("topFlux", "top flux");
    s.top_flux = p.number("topFlux", 0);
    s.ponding_head = p.number("pondingHead", 0);
  }

  if (bottom == "head") {
    s.bottom = BottomCondition::head;
    s.bottom_head = p.number("bottomHead", 0);
  } else if (bottom == "noFlux") {
    s.bottom = BottomCondition::noFlux;
  } else if (bottom == "freeDrainage") {
    s.bottom = BottomCondition::freeDrainage;
  }
  s.mean = p.word("conductivityMean", "arithmetic") == "geometric" ? ConductivityMean::geometric
                                                                    : ConductivityMean::arithmetic;

  s.end_time = p.number("endTime", 0);
  s.dt_initial = p.number("dtInitial", 1e-3);
  s.dt_min = p.number("dtMin", 1e-9);
  s.dt_max = p.number("dtMax", kUnbounded);
  if (s.dt_min > s.dt_initial) p.error(p.where(p.has("dtMin") ? "dtMin" : "dtInitial"), "dtMin", "exceeds dtInitial");
  if (s.dt_max < s.dt_min) p.error(p.where("dtMax"), "dtMax", "is below dtMin");
  s.picard_tolerance = p.number("picardTolerance", 1e-8);
  s.picard_max_iterations = static_cast<int>(p.number("picardMaxIterations", 30));
  s.fast_iterations = static_cast<int>(p.number("fastIterations", 3));
  s.slow_iterations = static_cast<int>(p.number("slowIterations", 8));
  if (s.slow_iterations <= s.fast_iterations)
    p.error(p.where(p.has("slowIterations") ? "slowIterations" : "fastIterations"), "slowIterations",
            "must exceed fastIterations");
  s.dt_grow = p.number("dtGrow", 1.25);
  s.dt_shrink = p.number("dtShrink", 0.7);
  s.dt_cut = p.number("dtCut", 0.5);
  s.time_tolerance = p.number("timeTolerance", 1e-6);

  if (p.has("profileTimes")) {
    for (double t : p.list("profileTimes")) {
      if (t <= s.end_time) {
        s.profile_times.push_back(t);
      } else if (warnings) {
        std::ostringstream m;
        m << p.where("profileTimes") << ": key 'profileTimes': " << t << " s is after endTime " << s.end_time
          << " s; not written";
        warnings->push_back(m.str());
      }
    }
  } else {
    s.profile_times = {0.0, s.end_time};
  }
  s.history_interval = p.number("historyInterval", s.end_time / 1000);

  for (const auto& [k, e] : p.entries)
    if (!e.used && warnings)
      warnings->push_back(e.where + ": key '" + k + "' is not used with these options (retention " + retention +
                          ", initial " + initial + ", top " + top + ", bottom " + bottom + ")");
  if (!p.errors.empty()) {
    std::string all;
    for (const auto& e : p.errors) all += e + "\n";
    throw ConfigError(all);
  }
  return s;
}

void apply_overrides(Parser& p, const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) {
    const auto eq = o.find('=');
    const std::string where = "--set " + o;
    if (eq == std::string::npos || eq == 0) {
      p.error(where, "", "expected key=value");
      continue;
    }
    std::istringstream words(o.substr(eq + 1));
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    p.set(o.substr(0, eq), w, where, "--set");
  }
}

}  // namespace

Settings read_config(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                     std::vector<std::string>* warnings) {
  if (!std::ifstream(file)) throw ConfigError(file.string() + ": cannot open the config file\n");
  Parser p;
  p.parse_file(file, "command line", 0);
  apply_overrides(p, overrides);
  return build(p, file.string(), warnings);
}

Settings parse_config(const std::string& text, const std::string& name, const std::vector<std::string>& overrides,
                      std::vector<std::string>* warnings) {
  Parser p;
  p.parse_text(text, name, ".", 0);
  apply_overrides(p, overrides);
  return build(p, name, warnings);
}

void print_config_keys(std::ostream& os) {
  for (const auto& s : specs()) {
    std::string head = std::string(s.name);
    if (*s.unit && std::string(s.unit) != "-") head += " [" + std::string(s.unit) + "]";
    os << "  " << head << std::string(head.size() < 30 ? 30 - head.size() : 1, ' ') << s.help;
    if (!s.choices.empty()) os << ": " << join(s.choices);
    if (*s.fallback) os << " (default " << s.fallback << ")";
    os << '\n';
  }
}

}  // namespace scree::richards1d

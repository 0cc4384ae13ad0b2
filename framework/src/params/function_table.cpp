// Functions of time as dictionaries write them: parsing, units, CSV files.
#include "scree/params/function_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include "scree/params/spec.hpp"

namespace scree {

namespace {

using Units = std::vector<std::pair<std::string, double>>;

const Units& time_units() {
  static const Units u = {{"s", 1.0}, {"min", 60.0}, {"h", 3600.0}, {"day", 86400.0}};
  return u;
}

std::string names(const Units& u) {
  std::string s;
  for (std::size_t i = 0; i < u.size(); ++i) s += (i ? ", " : "") + u[i].first;
  return s;
}

/// The factor of `unit` among `u`, or throws at `where` naming the valid ones.
double factor_of(const Units& u, const std::string& unit, const SourceLocation& where, const std::string& what) {
  for (const auto& [name, f] : u)
    if (name == unit) return f;
  std::string msg = what + ": '" + unit + "' is not a unit of this quantity; expected one of: " + names(u);
  std::vector<std::string> candidates;
  for (const auto& [name, f] : u) candidates.push_back(name);
  const std::string near = nearest_name(unit, candidates);
  if (!near.empty()) msg += " (did you mean '" + near + "'?)";
  throw InputError(where, msg);
}

const char* kForms =
    "a number; `table ((t v) ...)`; or { type table|csvFile|constant; values ((t v) ...) | file \"x.csv\" "
    "columns (t v) | value v; timeUnit s|min|h|day; unit ...; interpolation linear|step; "
    "outOfBounds clamp|zero|repeat; }";

/// One row's value(s) from a table item: a number (one component) or a list of numbers.
void read_value(const Item& it, int components, const std::string& key, std::vector<double>& out) {
  if (components == 1 && it.kind() == Item::Kind::number) {
    out.push_back(it.number());
    return;
  }
  const std::string want = components == 1 ? "a number" : "a vector of " + std::to_string(components) + " numbers";
  if (it.kind() != Item::Kind::list || static_cast<int>(it.list().size()) != components)
    throw InputError(it.where(), key + ": expected " + want + " as a row's value, found " + it.kind_name() + " " +
                                     it.to_string());
  for (const Item& x : it.list()) {
    if (x.kind() != Item::Kind::number)
      throw InputError(x.where(), key + ": expected " + want + " as a row's value, found " + x.kind_name() + " " +
                                      x.to_string());
    out.push_back(x.number());
  }
}

/// Rows ((t v) (t v) ...) written in a dictionary.
void read_rows(const Item& list, int components, const std::string& key, FunctionTable& f) {
  if (list.kind() != Item::Kind::list || list.list().empty())
    throw InputError(list.where(), key + ": expected a table of rows ((t v) (t v) ...), found " + list.kind_name() +
                                       " " + list.to_string());
  for (const Item& row : list.list()) {
    if (row.kind() != Item::Kind::list || row.list().size() != 2 || row.list()[0].kind() != Item::Kind::number)
      throw InputError(row.where(), key + ": expected a row (t value), found " + row.kind_name() + " " +
                                        row.to_string());
    f.times.push_back(row.list()[0].number());
    read_value(row.list()[1], components, key, f.values);
  }
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

std::vector<std::string> split(const std::string& line, const std::string& sep) {
  std::vector<std::string> out;
  if (sep == " ") {
    std::istringstream is(line);
    std::string w;
    while (is >> w) out.push_back(w);
    return out;
  }
  std::size_t start = 0;
  while (true) {
    const auto k = line.find(sep, start);
    out.push_back(trim(std::string_view(line).substr(start, k == std::string::npos ? std::string::npos : k - start)));
    if (k == std::string::npos) break;
    start = k + sep.size();
  }
  return out;
}

bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* b = s.data();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// Rows from a CSV file: the columns `columns` names (indices or header names), the first
/// the time.
void read_csv(const Dictionary& d, int components, const std::string& key, const std::filesystem::path& case_dir,
              FunctionTable& f) {
  const Entry& fe = d.at("file");
  const std::string name = fe.as_word();
  const std::filesystem::path path = case_dir / name;
  std::ifstream in(path);
  if (!std::filesystem::is_regular_file(path) || !in)
    throw InputError(fe.where(), key + ": cannot read the file '" + name + "' (looked for " + path.string() +
                                     "); expected a CSV file of rows time,value relative to the case directory");
  const std::string sep = d.has("separator") ? d.at("separator").as_word() : ",";
  if (sep != "," && sep != ";" && sep != " ")
    throw InputError(d.at("separator").where(),
                     key + ": separator '" + sep + "' is not valid; expected one of: \",\", \";\", \" \" (whitespace)");
  const auto file = std::make_shared<const std::string>(name);
  auto at = [&](int line) { return SourceLocation{file, line, 1}; };

  // The columns: as written (indices or names), resolved against the header once it is read.
  std::vector<const Item*> wanted;
  const Entry* ce = d.find("columns");
  if (ce) {
    const Item& it = ce->single_item();
    if (it.kind() != Item::Kind::list || static_cast<int>(it.list().size()) != components + 1)
      throw InputError(ce->where(), key + ": columns: expected " + std::to_string(components + 1) +
                                        " columns (the time, then " +
                                        (components == 1 ? std::string("the value") :
                                                           std::to_string(components) + " components") +
                                        "), as zero-based indices or the header's names, found " + ce->value_string());
    for (const Item& x : it.list()) wanted.push_back(&x);
  }
  std::vector<int> cols;
  if (!ce)
    for (int c = 0; c <= components; ++c) cols.push_back(c);

  std::vector<std::string> header;
  std::string line;
  int lineno = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto fields = split(t, sep);
    if (first) {
      first = false;
      bool numeric = true;
      for (const auto& s : fields) {
        double v;
        numeric &= parse_number(s, v);
      }
      if (!numeric) header = fields;
      if (ce) {
        for (const Item* x : wanted) {
          if (x->kind() == Item::Kind::number && x->integral() && x->number() >= 0) {
            cols.push_back(static_cast<int>(x->number()));
            continue;
          }
          const std::string nm = x->text();
          const auto k = std::find(header.begin(), header.end(), nm);
          if (x->kind() == Item::Kind::number || k == header.end()) {
            std::string msg = key + ": columns: '" + x->to_string() + "' is not a column of '" + name + "'; expected ";
            if (header.empty())
              msg += "a zero-based index (the file has no header line)";
            else {
              msg += "a zero-based index or one of the header's names:";
              for (const auto& h : header) msg += " '" + h + "'";
              const std::string near = nearest_name(nm, header);
              if (!near.empty()) msg += " (did you mean '" + near + "'?)";
            }
            throw InputError(x->where(), msg);
          }
          cols.push_back(static_cast<int>(k - header.begin()));
        }
      }
      if (!numeric) continue;
    }
    for (int c : cols) {
      if (c >= static_cast<int>(fields.size()))
        throw InputError(at(lineno), key + ": row has " + std::to_string(fields.size()) + " fields, column " +
                                         std::to_string(c) + " was asked for (separator '" + sep + "')");
      double v;
      if (!parse_number(fields[c], v))
        throw InputError(at(lineno), key + ": expected a number in column " + std::to_string(c) + ", found '" +
                                         fields[c] + "'");
      if (c == cols[0])
        f.times.push_back(v);
      else
        f.values.push_back(v);
    }
    // A column named twice (time and value) is read once above: keep the row whole.
    if (f.values.size() != f.times.size() * static_cast<std::size_t>(components))
      throw InputError(at(lineno), key + ": the time and the values must be different columns");
  }
  if (f.times.empty())
    throw InputError(fe.where(), key + ": the file '" + name + "' has no rows of numbers");
  f.source = "the file '" + name + "' (" + std::to_string(f.times.size()) + " rows)";
}

}  // namespace

Units units_of(std::string_view si) {
  if (si == "m/s")
    return {{"m/s", 1.0},          {"mm/s", 1e-3},        {"cm/s", 1e-2},       {"mm/min", 1e-3 / 60},
            {"mm/h", 1e-3 / 3600}, {"mm/day", 1e-3 / 86400}, {"m/h", 1.0 / 3600}, {"m/day", 1.0 / 86400}};
  if (si == "m/s^2") return {{"m/s^2", 1.0}, {"g", 9.80665}, {"gal", 1e-2}, {"cm/s^2", 1e-2}};
  if (si == "m") return {{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}};
  if (si == "Pa") return {{"Pa", 1.0}, {"kPa", 1e3}, {"MPa", 1e6}};
  if (si == "s") return time_units();
  if (si == "rad/s") return {{"rad/s", 1.0}, {"rpm", 2 * 3.14159265358979323846 / 60}};
  return {{std::string(si.empty() ? "-" : si), 1.0}};
}

std::string function_forms() { return kForms; }

FunctionTable read_function_table(const Param& p, const Entry& e, int components,
                                  const std::filesystem::path& case_dir, const FunctionDefaults& defaults) {
  FunctionTable f;
  f.components = components;
  const std::string& key = e.key();
  const SourceLocation where = e.where();
  std::string unit = defaults.unit.empty() ? p.unit() : defaults.unit;
  std::string time_unit = "s", interp = "linear", out = defaults.out_of_bounds;
  SourceLocation unit_at = where, time_unit_at = where;
  const Units units = units_of(p.unit());

  auto bad_form = [&](const std::string& found) {
    throw InputError(where, key + ": expected a function of time: " + std::string(kForms) + "; found " + found);
  };

  if (e.is_dict()) {
    const Dictionary& d = e.dict();
    static const std::vector<std::string> valid = {"type",     "values",   "value",         "file",       "columns",
                                                   "separator", "timeUnit", "unit", "interpolation", "outOfBounds"};
    for (const Entry& x : d.entries()) {
      if (std::find(valid.begin(), valid.end(), x.key()) != valid.end() || x.key().rfind('_', 0) == 0) continue;
      std::string msg = key + ": unknown entry '" + x.key() + "' in a function of time";
      const std::string near = nearest_name(x.key(), valid);
      msg += near.empty() ? "; valid entries: type, values, value, file, columns, separator, timeUnit, unit, "
                            "interpolation, outOfBounds"
                          : "; did you mean '" + near + "'?";
      throw InputError(x.where(), msg);
    }
    if (!d.has("type"))
      throw InputError(d.where(), key + ": a function of time written as { } needs a type: table, csvFile or constant");
    const std::string type = d.get_word("type");
    auto needs = [&](const char* k, const char* what) {
      if (!d.has(k))
        throw InputError(d.where(), key + ": a function of type " + type + " needs '" + k + "' (" + what + ")");
    };
    if (type == "table") {
      needs("values", "rows ((t v) ...)");
      read_rows(d.at("values").single_item(), components, key, f);
      f.source = "a table of " + std::to_string(f.times.size()) + " rows (" + d.at("values").where().str() + ")";
    } else if (type == "csvFile") {
      needs("file", "a CSV file relative to the case directory");
      if (case_dir.empty()) {
        f.source = "the file '" + d.at("file").as_word() + "'";
      } else {
        read_csv(d, components, key, case_dir, f);
      }
    } else if (type == "constant") {
      needs("value", "the value");
      f.times.push_back(0);
      read_value(d.at("value").single_item(), components, key, f.values);
      f.source = "a constant";
    } else {
      const std::vector<std::string> types = {"table", "csvFile", "constant"};
      std::string msg = key + ": type '" + type + "' is not a function of time; expected one of: table, csvFile, constant";
      const std::string near = nearest_name(type, types);
      if (!near.empty()) msg += " (did you mean '" + near + "'?)";
      throw InputError(d.at("type").where(), msg);
    }
    if (const Entry* x = d.find("unit")) {
      unit = x->as_word();
      unit_at = x->where();
    }
    if (const Entry* x = d.find("timeUnit")) {
      time_unit = x->as_word();
      time_unit_at = x->where();
    }
    if (const Entry* x = d.find("interpolation")) interp = x->as_word();
    if (const Entry* x = d.find("outOfBounds")) out = x->as_word();
    if (interp != "linear" && interp != "step")
      throw InputError(d.at("interpolation").where(),
                       key + ": interpolation '" + interp + "' is not valid; expected one of: linear, step");
    if (out != "clamp" && out != "zero" && out != "repeat")
      throw InputError(d.at("outOfBounds").where(),
                       key + ": outOfBounds '" + out + "' is not valid; expected one of: clamp, zero, repeat");
  } else {
    const auto items = e.items();
    if (items.size() == 1) {
      f.times.push_back(0);
      const Item& it = items[0];
      if (!(it.kind() == Item::Kind::number || it.kind() == Item::Kind::list)) bad_form(it.kind_name() + " " + it.to_string());
      read_value(it, components, key, f.values);
      f.source = "a constant";
    } else if (items.size() == 2 && items[0].kind() == Item::Kind::word && items[0].text() == "table") {
      read_rows(items[1], components, key, f);
      f.source = "a table of " + std::to_string(f.times.size()) + " rows (" + where.str() + ")";
    } else if (items.size() == 2 && items[0].kind() == Item::Kind::word && items[0].text() == "constant") {
      f.times.push_back(0);
      read_value(items[1], components, key, f.values);
      f.source = "a constant";
    } else {
      bad_form(e.value_string());
    }
  }
  if (f.source.rfind("the file", 0) == 0 && f.times.empty()) return f;  // not opened: checked at setup

  const double fu = factor_of(units, unit, unit_at, key + ": unit");
  const double ft = factor_of(time_units(), time_unit, time_unit_at, key + ": timeUnit");
  for (double& t : f.times) t *= ft;
  for (double& v : f.values) v *= fu;
  f.interpolation = interp == "step" ? FunctionTable::Interpolation::step : FunctionTable::Interpolation::linear;
  f.out_of_bounds = out == "zero" ? FunctionTable::OutOfBounds::zero
                    : out == "repeat" ? FunctionTable::OutOfBounds::repeat
                                      : FunctionTable::OutOfBounds::clamp;
  for (std::size_t i = 0; i < f.times.size(); ++i) {
    if (!std::isfinite(f.times[i]))
      throw InputError(where, key + ": the time of row " + std::to_string(i + 1) + " is not finite");
    if (i > 0 && !(f.times[i] > f.times[i - 1]))
      throw InputError(where, key + ": times must increase strictly; row " + std::to_string(i + 1) + " (t = " +
                                  std::to_string(f.times[i] / ft) + " " + time_unit + ") does not follow row " +
                                  std::to_string(i) + " (t = " + std::to_string(f.times[i - 1] / ft) + ")");
  }
  if (f.out_of_bounds == FunctionTable::OutOfBounds::repeat && f.times.size() < 2)
    throw InputError(where, key + ": outOfBounds repeat needs at least two rows (the period is the table's span)");
  // Every value within the parameter's range (in its SI unit).
  const bool has_lo = p.lower().has_value(), has_hi = p.upper().has_value();
  for (std::size_t i = 0; i < f.values.size(); ++i) {
    const double v = f.values[i];
    bool bad = !std::isfinite(v);
    if (has_lo) bad |= p.lower_open() ? !(v > *p.lower()) : !(v >= *p.lower());
    if (has_hi) bad |= p.upper_open() ? !(v < *p.upper()) : !(v <= *p.upper());
    if (bad) {
      const std::size_t row = i / static_cast<std::size_t>(components) + 1;
      throw InputError(where, key + ": row " + std::to_string(row) + " of " + f.source + ": expected a value" +
                                  p.bounds() + " [" + p.unit() + "], found " + std::to_string(v) + " " +
                                  p.unit() + " (" + p.doc() + ")");
    }
  }
  return f;
}

}  // namespace scree

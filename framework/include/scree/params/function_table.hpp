// A parameter that is a function of time, as a dictionary writes it (OpenFOAM's Function1 in
// spirit): a constant, a table written in the dictionary, or a table read from a CSV file,
// each with the units of its time and its values, read by linear or step interpolation.
//
//   intensity 20;                                   constant (in the parameter's unit)
//   intensity constant 20;                          the same
//   intensity table ((0 0) (3600 20) (7200 0));     rows (t value); value: a vector for a vector
//   intensity                                       parameter, e.g. (0 (0 -0.01))
//   {
//       type            table;                      table | csvFile | constant
//       values          ((0 0) (1 20) (2 0));       (table) or `value 20;` (constant)
//       file            "constant/hyetograph.csv";  (csvFile) relative to the case
//       columns         (time intensity);           (csvFile) time, then each component:
//                                                   zero-based indices or the header's names
//       separator       ",";                        (csvFile) "," ";" or " " (whitespace)
//       timeUnit        h;                          s | min | h | day
//       unit            mm/h;                       one of the units of the parameter's quantity
//       interpolation   linear;                     linear | step (the last row at or before t)
//       outOfBounds     clamp;                      clamp | zero | repeat (before the first and
//   }                                               after the last row)
//
// A CSV file: lines starting with '#' are comments; the first other line is a header when
// any of its fields is not a number (its names can then select the columns). Times must
// increase strictly. Every value is converted to the parameter's SI unit once, here; the
// kernels evaluate the table as time/function_of_time.hpp makes it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"

namespace scree {

class Param;

/// A function of time read from a dictionary, in SI units: rows of (time, components).
struct SCREE_API FunctionTable {
  enum class Interpolation { linear, step };
  enum class OutOfBounds { clamp, zero, repeat };

  std::vector<double> times;   ///< [s], strictly increasing; one row for a constant
  std::vector<double> values;  ///< rows x components, in the parameter's SI unit
  int components = 1;
  Interpolation interpolation = Interpolation::linear;
  OutOfBounds out_of_bounds = OutOfBounds::clamp;
  std::string source;  ///< "a constant", "a table of 3 rows (system/controlDict:12)", ...

  bool constant() const { return times.size() == 1; }
  // Evaluated, on the host as in the kernels, by FunctionOfTime (time/function_of_time.hpp).
};

/// What a parameter's reader may set that a dictionary need not write.
struct FunctionDefaults {
  std::string unit;                   ///< the unit of the numbers when the entry names none ("": the SI unit)
  std::string out_of_bounds = "clamp";  ///< clamp | zero | repeat
};

/// The units a quantity may be written in, with each one's factor to the SI unit `si`
/// (e.g. "m/s": m/s, mm/s, cm/s, mm/min, mm/h, mm/day, m/h, m/day). A unit not in the
/// table accepts only itself.
SCREE_API std::vector<std::pair<std::string, double>> units_of(std::string_view si);

/// Read `e`, the entry of parameter `p`, as a function of time with `components` values a
/// row. Throws InputError naming file, line and key, what was expected and what is valid.
/// `case_dir` empty: a csvFile's file is not opened (checking a dictionary without its case).
SCREE_API FunctionTable read_function_table(const Param& p, const Entry& e, int components,
                                            const std::filesystem::path& case_dir,
                                            const FunctionDefaults& defaults = {});

/// One line for --list-plugins: the forms a function of time may take.
SCREE_API std::string function_forms();

}  // namespace scree

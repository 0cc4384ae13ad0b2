// CsvFile: a CSV file that a function object (or any plugin) writes row by row, and the
// directory checks that go with it.
//
// CSV conventions: one header line naming each column with its unit in brackets
// ("time [s],runout [m],..."), then one row per execution, numbers with 12 significant
// digits, "nan" where a value does not exist. Each row is flushed as it is written, so a
// killed run keeps every finished row. A run that starts at t = 0 replaces old files; a
// run that starts later (a restart) keeps the rows before its start time and appends.
#pragma once

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

/// A number as written in CSV files: %.12g, "nan", "inf", "-inf".
SCREE_API std::string csv_number(double v);
/// A time as used in file names: %.8g ("0.1", "1.25e-05").
SCREE_API std::string time_name(double t);
/// `text` quoted for CSV when it holds a comma, quote or newline.
SCREE_API std::string csv_text(const std::string& text);
/// Split one CSV line at commas (quotes as written by csv_text).
SCREE_API std::vector<std::string> csv_split(const std::string& line);

/// A CSV file written one flushed row at a time (see the conventions above).
class SCREE_API CsvFile {
 public:
  CsvFile() = default;
  /// Open `path` with this header. start_time <= 0: replace the file. Otherwise keep the
  /// rows of an existing file with the same header whose first column (time) is before
  /// start_time, and append after them. Throws std::runtime_error when the file cannot
  /// be written.
  void open(const std::filesystem::path& path, const std::vector<std::string>& header, double start_time);
  /// The same, at the first row: nothing is made before it (a plugin constructed after
  /// this one may still stop the run on a user error, which must leave the case as it
  /// was). Checks now that the directory can be made and written (check_writable_dir,
  /// naming `who`); makes it at the first row (ensure_writable_dir).
  void open_at_first_row(const std::filesystem::path& path, std::vector<std::string> header, double start_time,
                         const std::string& who);
  bool is_open() const { return out_.is_open(); }
  /// Write and flush one row of numbers.
  void row(const std::vector<double>& values);
  /// Write and flush one row of texts (already formatted).
  void row_text(const std::vector<std::string>& cells);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::size_t columns_ = 0;
  std::ofstream out_;
  struct Pending {  // open_at_first_row's file, until its first row
    std::vector<std::string> header;
    double start_time = 0;
    std::string who;
  };
  std::unique_ptr<Pending> pending_;
};

/// Create `dir` (and parents) and check that it is writable; throws std::runtime_error
/// naming `who` and the directory otherwise.
SCREE_API void ensure_writable_dir(const std::filesystem::path& dir, const std::string& who);
/// The same check without creating anything (constructors: a plugin constructed after
/// this one may still stop the run on a user error, which must leave the case as it
/// was): `dir` is a writable directory, or its nearest existing ancestor is. Throws
/// std::runtime_error naming `who` and the directory otherwise. The directory and the
/// files are made at the first execution (ensure_writable_dir).
SCREE_API void check_writable_dir(const std::filesystem::path& dir, const std::string& who);
}  // namespace scree

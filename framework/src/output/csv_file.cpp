// CsvFile and the output directory checks (see csv_file.hpp).
#include "scree/output/csv_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <system_error>

#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree {

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

// ------------------------------------------------------------------ directories

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

}  // namespace scree

// scree-bench-dict: time and peak memory of the dictionary reader on a generated file.
//
//   scree-bench-dict --size 50M                 generate about 50 MB, parse it, report
//   scree-bench-dict --size 50M --shape table   only the big table (or: entries, the
//                                               sub-dictionaries; keys, one dictionary
//                                               of millions of entries; mixed)
//   scree-bench-dict --parse FILE               parse an existing file and report
//
// The generated file is what a large case looks like to the reader: half of it a table
// of (x y) rows in one `( ... )` list, half of it sub-dictionaries of entries (numbers,
// vectors, words, strings). It is written in a temporary file (or --file PATH, kept),
// then read with Dictionary::read_file, exactly as a case file is. The report gives the
// wall time of read_file and the process's peak resident memory, which the generator
// (streamed in small pieces) does not raise: so the peak is the reader's.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "scree/io/dictionary.hpp"

namespace {

namespace fs = std::filesystem;

struct Counts {
  std::size_t entries = 0;
  std::size_t items = 0;
};

void count(const scree::Item& it, Counts& c) {
  ++c.items;
  for (const scree::Item& el : it.list()) count(el, c);
}

void count(const scree::Dictionary& d, Counts& c) {
  for (const scree::Entry& e : d.entries()) {
    ++c.entries;
    if (e.is_dict()) count(e.dict(), c);
    for (const scree::Item& it : e.items()) count(it, c);
  }
}

/// CPU time (user and system) of this process so far, in seconds: unlike the wall time,
/// hardly changed by other work on a shared machine.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

/// Peak resident set size of this process so far, in MiB.
double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

/// A deterministic stream of pseudo-random numbers (the file is the same on every run).
struct Lcg {
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  double next() {  // in [0, 1)
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(s >> 11) * 0x1.0p-53;
  }
};

/// Writes through a buffer of bounded size, counting the bytes.
class Out {
 public:
  explicit Out(const fs::path& p) : f_(std::fopen(p.c_str(), "wb")) {
    if (!f_) throw std::runtime_error("cannot write " + p.string());
  }
  ~Out() {
    if (f_) std::fclose(f_);
  }
  void put(std::string_view s) {
    buf_ += s;
    if (buf_.size() > (1u << 20)) flush();
  }
  void flush() {
    if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
      throw std::runtime_error("write failed");
    written_ += buf_.size();
    buf_.clear();
  }
  std::size_t size() const { return written_ + buf_.size(); }

 private:
  std::FILE* f_;
  std::string buf_;
  std::size_t written_ = 0;
};

std::string num(const char* fmt, double v) {
  char b[48];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

void write_table(Out& o, std::size_t until, Lcg& rng) {
  o.put("// a table: time and value, one row per line\ntable\n(\n");
  for (std::size_t i = 0; o.size() < until; ++i)
    o.put("    (" + num("%.6g", static_cast<double>(i) * 1e-3) + ' ' + num("%.9g", (rng.next() - 0.5) * 2e-2) + ")\n");
  o.put(");\n\n");
}

void write_entries(Out& o, std::size_t until, Lcg& rng) {
  for (std::size_t b = 0; o.size() < until; ++b) {
    o.put("block" + std::to_string(b) + "\n{\n");
    for (int k = 0; k < 64; ++k) {
      const std::string key = "    key" + std::to_string(k);
      switch (k % 4) {
        case 0: o.put(key + "  " + num("%.9g", rng.next() * 1e3) + ";\n"); break;
        case 1:
          o.put(key + "  (" + num("%.6g", rng.next()) + ' ' + num("%.6g", rng.next()) + ' ' +
                num("%.6g", -rng.next()) + ");\n");
          break;
        case 2: o.put(key + "  word" + std::to_string(k) + ";\n"); break;
        default: o.put(key + "  \"a string of some length\";\n"); break;
      }
    }
    o.put("}\n\n");
  }
}

/// One dictionary of many entries (a file written by a program rather than by hand).
void write_keys(Out& o, std::size_t until, Lcg& rng) {
  for (std::size_t k = 0; o.size() < until; ++k)
    o.put("key" + std::to_string(k) + "  " + num("%.9g", rng.next() * 1e3) + ";\n");
}

/// About `bytes` bytes of dictionary in `path`; `shape` is mixed, table, entries or keys.
void generate(const fs::path& path, std::size_t bytes, const std::string& shape) {
  Out o(path);
  Lcg rng;
  o.put("FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n    object bench;\n}\n\n");
  if (shape == "table") {
    write_table(o, bytes, rng);
  } else if (shape == "entries") {
    write_entries(o, bytes, rng);
  } else if (shape == "keys") {
    write_keys(o, bytes, rng);
  } else {
    write_table(o, bytes / 2, rng);
    write_entries(o, bytes, rng);
  }
  o.flush();
}

/// "50M", "200k", "1G" or a plain number of bytes.
std::size_t parse_size(const std::string& s) {
  std::size_t end = 0;
  const double v = std::stod(s, &end);
  double scale = 1;
  if (end < s.size()) {
    switch (s[end]) {
      case 'k': case 'K': scale = 1e3; break;
      case 'm': case 'M': scale = 1e6; break;
      case 'g': case 'G': scale = 1e9; break;
      default: throw std::invalid_argument("bad size '" + s + "' (e.g. 50M, 200k)");
    }
  }
  return static_cast<std::size_t>(v * scale);
}

int usage(const char* argv0) {
  std::cerr << "usage: " << argv0 << " [--size BYTES(k|M|G)] [--shape mixed|table|entries|keys] [--file PATH]\n"
            << "       " << argv0 << " --parse FILE\n"
            << "Generates a dictionary (default 50M, mixed; in a temporary file unless --file),\n"
            << "reads it with Dictionary::read_file, prints the seconds and the peak RSS.\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t size = 50'000'000;
  std::string shape = "mixed";
  fs::path file, parse_only;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--size") size = parse_size(value());
      else if (a == "--shape") shape = value();
      else if (a == "--file") file = value();
      else if (a == "--parse") parse_only = value();
      else return usage(argv[0]);
    }
    if (shape != "mixed" && shape != "table" && shape != "entries" && shape != "keys") return usage(argv[0]);

    const bool temporary = file.empty() && parse_only.empty();
    if (parse_only.empty()) {
      if (temporary) file = fs::temp_directory_path() / ("scree-bench-dict-" + std::to_string(::getpid()) + ".dict");
      generate(file, size, shape);
    } else {
      file = parse_only;
    }
    const double rss_before = peak_rss_mib();
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const scree::Dictionary d = scree::Dictionary::read_file(file);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - cpu0;
    const double rss_peak = peak_rss_mib();
    Counts c;
    count(d, c);
    const auto bytes = fs::file_size(file);
    if (temporary) fs::remove(file);
    std::printf("parsed %llu bytes (%zu entries, %zu items) in %.3f s (CPU %.3f s); peak RSS %.1f MiB "
                "(%.1f MiB before reading)\n",
                static_cast<unsigned long long>(bytes), c.entries, c.items, seconds, cpu, rss_peak, rss_before);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "scree-bench-dict: " << e.what() << '\n';
    return 1;
  }
}

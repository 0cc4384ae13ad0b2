// Shared by the fuzz targets: a scratch directory per process and the check that an
// error a user can cause says where (file:line).
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include "scree/io/dictionary.hpp"

namespace scree::fuzz {

/// $TMPDIR/scree-fuzz-<what>-<pid>: created once, reused by every input, removed at exit.
inline const std::filesystem::path& scratch_dir(const char* what) {
  static const std::filesystem::path dir = [what] {
    auto d = std::filesystem::temp_directory_path() / ("scree-fuzz-" + std::string(what) + "-" +
                                                        std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(nullptr), ec);
    });
    return d;
  }();
  return dir;
}

/// A finding: print it and abort, so that libFuzzer (or the standalone driver) saves the input.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "\n==FUZZ FINDING== %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// Digits at the start of `s` (at least one), removed from it.
inline bool eat_number(std::string_view& s) {
  std::size_t n = 0;
  while (n < s.size() && s[n] >= '0' && s[n] <= '9') ++n;
  if (n == 0) return false;
  s.remove_prefix(n);
  return true;
}

/// An InputError must name a file and (with `need_line`) a line >= 1, and what() must
/// begin with exactly that "file:line[:col]: ".
inline void check_located(const InputError& e, bool need_line) {
  const SourceLocation& w = e.where();
  if (!w.file || w.file->empty()) finding(std::string("an InputError without a file: ") + e.what());
  if (need_line && w.line < 1) finding(std::string("an InputError without a line: ") + e.what());
  std::string_view s = e.what();
  if (s.substr(0, w.file->size()) != *w.file) finding(std::string("what() does not begin with the file: ") + e.what());
  s.remove_prefix(w.file->size());
  if (w.line >= 1) {
    if (s.empty() || s[0] != ':') finding(std::string("what() has no ':line': ") + e.what());
    s.remove_prefix(1);
    if (!eat_number(s)) finding(std::string("what() has no line number: ") + e.what());
    if (w.column >= 1) {
      if (s.empty() || s[0] != ':') finding(std::string("what() has no ':column': ") + e.what());
      s.remove_prefix(1);
      if (!eat_number(s)) finding(std::string("what() has no column number: ") + e.what());
    }
  }
  if (s.substr(0, 2) != ": ") finding(std::string("what() has no ': ' after the location: ") + e.what());
  if (e.message().empty()) finding(std::string("an InputError with an empty message: ") + e.what());
}

}  // namespace scree::fuzz

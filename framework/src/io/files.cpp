// Files for the dictionary reader (files.hpp).

#include "files.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <system_error>
#include <utility>
#include <vector>

namespace scree::reader {

namespace fs = std::filesystem;

std::string special_file_kind(fs::file_type t) {
  switch (t) {
    case fs::file_type::fifo: return "a named pipe (FIFO)";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::block: return "a block device";
    case fs::file_type::character: return "a character device";
    default: return "not a regular file";
  }
}

namespace {

fs::file_type file_type_of_mode(mode_t m) {
  if (S_ISFIFO(m)) return fs::file_type::fifo;
  if (S_ISSOCK(m)) return fs::file_type::socket;
  if (S_ISBLK(m)) return fs::file_type::block;
  if (S_ISCHR(m)) return fs::file_type::character;
  if (S_ISDIR(m)) return fs::file_type::directory;
  return fs::file_type::unknown;
}

}  // namespace

ReadStatus read_text(const fs::path& path, std::string& out, fs::file_type& kind) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec == std::errc::too_many_symbolic_link_levels) return ReadStatus::link_loop;
  if (ec || !fs::exists(st)) return ReadStatus::missing;
  if (fs::is_directory(st)) return ReadStatus::directory;
  if (!fs::is_regular_file(st)) {
    kind = st.type();
    return ReadStatus::not_regular;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return ReadStatus::unreadable;
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat opened {};
  if (::fstat(fd, &opened) != 0) return ReadStatus::unreadable;
  if (!S_ISREG(opened.st_mode)) {
    kind = file_type_of_mode(opened.st_mode);
    return kind == fs::file_type::directory ? ReadStatus::directory : ReadStatus::not_regular;
  }
  std::string text;
  if (opened.st_size > 0) text.reserve(static_cast<std::size_t>(opened.st_size));
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      return ReadStatus::unreadable;
    }
    text.append(buf, static_cast<std::size_t>(n));
  }
  out = std::move(text);
  return ReadStatus::ok;
}

std::string link_chain(const fs::path& path, const std::string& shown) {
  std::vector<fs::path> seen;  // absolute, normal: where each link of the chain is
  std::string chain;
  fs::path at = fs::path(absolute_text(path));
  fs::path name = shown;  // `at` as shown
  for (int step = 0; step < 64; ++step) {
    if (std::find(seen.begin(), seen.end(), at) != seen.end()) return chain + " -> " + name.string();
    std::error_code ec;
    const fs::path target = fs::read_symlink(at, ec);
    if (ec) return step == 0 ? std::string() : chain + " -> " + name.string() + " (a loop in its directories)";
    chain += (step == 0 ? "" : " -> ") + name.string();
    seen.push_back(at);
    name = target.is_absolute() ? target : (name.parent_path() / target).lexically_normal();
    at = target.is_absolute() ? target.lexically_normal() : (at.parent_path() / target).lexically_normal();
  }
  return chain + " -> ...";
}

std::string absolute_text(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal().string();
}

namespace {

fs::path identity_of(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  if (ec || c.empty()) return fs::path(absolute_text(p));
  return c;
}

}  // namespace

const fs::path& OpenFile::identity() {
  if (!canonical) canonical = identity_of(path);
  return *canonical;
}

fs::path library_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&library_dir), &info) && info.dli_fname)
    return fs::absolute(fs::path(info.dli_fname)).parent_path();
  return {};
}

std::vector<fs::path> etc_search_path() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("SCREE_ETC")) {
    const std::string s(env);
    for (std::size_t start = 0; start <= s.size();) {
      const std::size_t end = std::min(s.find(':', start), s.size());
      if (end > start) dirs.emplace_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  if (const fs::path lib = library_dir(); !lib.empty()) dirs.push_back((lib / SCREE_ETC_FROM_LIB).lexically_normal());
  return dirs;
}

}  // namespace scree::reader

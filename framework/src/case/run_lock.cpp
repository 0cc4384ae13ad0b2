// RunLock (see run_lock.hpp).
#include "scree/case/run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <system_error>

namespace scree {

std::optional<RunLock> RunLock::acquire(const std::filesystem::path& case_dir, std::string& holder) {
  const std::filesystem::path file = case_dir / kFileName;
  int fd = -1;
  for (;;) {
    fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw std::runtime_error("cannot create the run's lock " + file.string() + ": " +
                               std::system_category().message(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int why = errno;
      char buf[256] = {};
      const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
      ::close(fd);
      if (why != EWOULDBLOCK)
        throw std::runtime_error("cannot lock " + file.string() + ": " + std::system_category().message(why));
      holder = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string("a process that is starting");
      while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
      return std::nullopt;
    }
    // The holder before us removes the file as it ends (~RunLock): locked after that, ours is
    // a file no longer at the path, and a third run could lock a new one. Lock the one there.
    struct stat held {}, there {};
    if (::fstat(fd, &held) == 0 && ::stat(file.c_str(), &there) == 0 && held.st_ino == there.st_ino &&
        held.st_dev == there.st_dev)
      break;
    ::close(fd);
  }
  // Ours: say who holds it (what a lock left by a killed run said is replaced).
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  char when[64] = {};
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", &utc);
  const std::string text = "PID " + std::to_string(::getpid()) + " on host " + host + ", started " + when + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    // The lock holds all the same; only its description is missing.
  }
  return RunLock(fd, file);
}

RunLock::RunLock(RunLock&& o) noexcept : fd_(o.fd_), file_(std::move(o.file_)) { o.fd_ = -1; }

RunLock& RunLock::operator=(RunLock&& o) noexcept {
  if (this != &o) {
    release();
    fd_ = o.fd_;
    file_ = std::move(o.file_);
    o.fd_ = -1;
  }
  return *this;
}

void RunLock::release() noexcept {
  if (fd_ < 0) return;
  // Removed while still locked, so that a run that ends leaves the case as it found it; a
  // run that opened the file meanwhile finds it gone from the path (acquire) and retries.
  ::unlink(file_.c_str());
  ::close(fd_);
  fd_ = -1;
}

RunLock::~RunLock() { release(); }

}  // namespace scree

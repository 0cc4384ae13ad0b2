// RunLock: one run at a time on a case directory.
//
// Two runs on one case would write the same files, and each one's start-up clean-up would
// delete the other's temporaries. A run therefore holds an exclusive lock on
// <case>/.scree.lock for its whole life (an advisory flock(2) on an open file, which the
// kernel releases when the process ends however it ends: a lock a killed run left behind is
// no lock, and the next run takes it over). The file names the holder (PID, host, start
// time) for the message of a run that finds it taken, and is removed when the run ends, so
// that a run refused for another reason leaves the case as it found it. `--check` reads the
// case only and takes no lock.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "scree/core/config.hpp"

namespace scree {

class SCREE_API RunLock {
 public:
  /// The lock of `case_dir`, or nullopt when another process holds it; `holder` then says
  /// who ("PID <pid> on host <host>, started <UTC date and time>"). Throws
  /// std::runtime_error when the lock file cannot be created (the case is not writable).
  static std::optional<RunLock> acquire(const std::filesystem::path& case_dir, std::string& holder);

  RunLock(RunLock&& o) noexcept;
  RunLock& operator=(RunLock&& o) noexcept;
  RunLock(const RunLock&) = delete;
  ~RunLock();

  static constexpr const char* kFileName = ".scree.lock";

 private:
  RunLock(int fd, std::filesystem::path file) : fd_(fd), file_(std::move(file)) {}
  void release() noexcept;
  int fd_ = -1;
  std::filesystem::path file_;
};

}  // namespace scree

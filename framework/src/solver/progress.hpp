// What a run tells its user while it runs: the progress line, and (scree --profile) the
// time of every kernel phase.
#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

/// The progress line: time, step, steps per second, percentage, elapsed time and ETA. On a
/// terminal it is rewritten in place about 5 times a second; in a log a line every 10 s.
/// The percentage is of the whole run (startTime to endTime); the rate and the ETA are of
/// this process's own steps and time, so that a restarted run does not count the steps of
/// the run it continues as done in its own wall time.
class SCREE_API Progress {
 public:
  Progress(std::ostream& log, bool tty, double start_time, double end_time);
  /// This process's part of the run starts now, at time t [s] and step `step`.
  void start(double t, std::int64_t step);
  void report(double t, std::int64_t step, bool final);

 private:
  std::ostream& log_;
  bool tty_;
  double start_time_, end_time_;
  double from_time_ = 0;
  std::int64_t from_step_ = 0;
  std::chrono::steady_clock::time_point run_start_, last_report_;
};

/// Durations from here on are shown as ">100 days" [s].
inline constexpr double kLongestDuration = 100 * 86400.0;

/// Seconds as m:ss or h:mm:ss ("--:--" when unknown, ">100 days" from kLongestDuration).
SCREE_API std::string format_duration(double seconds);

class Comm;

/// Wall time per named phase of a step (synchronised around each), and the table of it.
/// On several ranks the table has a column per rank (up to 8; beyond, the least, mean and
/// most over the ranks): what each rank spent where, its wait for the slowest included.
class PhaseProfile {
 public:
  void add(const char* name, double seconds);
  /// Collective over `comm`: every rank calls it; the root prints.
  void report(std::ostream& log, std::int64_t steps, Comm& comm) const;

 private:
  std::vector<std::pair<std::string, double>> phases_;
};

}  // namespace scree

// Progress and PhaseProfile (see progress.hpp).
#include "progress.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace scree {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  // An ETA of a run that barely advances can be any huge number, which a conversion to
  // an integer overflows: beyond 100 days the figure only says "never", so it saturates.
  if (seconds >= kLongestDuration) return ">100 days";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

Progress::Progress(std::ostream& log, bool tty, double start_time, double end_time)
    : log_(log), tty_(tty), start_time_(start_time), end_time_(end_time) {
  start(start_time, 0);
}

void Progress::start(double t, std::int64_t step) {
  from_time_ = t;
  from_step_ = step;
  run_start_ = last_report_ = std::chrono::steady_clock::now();
}

void Progress::report(double t, std::int64_t step, bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_report_).count();
  if (!final && !tty_ && since < 10.0) return;  // logs: a line every 10 s
  if (!final && tty_ && since < 0.2) return;
  last_report_ = now;
  const double elapsed = std::chrono::duration<double>(now - run_start_).count();
  const double done = (t - start_time_) / std::max(1e-300, end_time_ - start_time_);
  const double advanced = t - from_time_;  // simulated by this process
  const double eta = advanced > 0 ? elapsed * (end_time_ - t) / advanced : -1;
  const double rate = elapsed > 0 ? static_cast<double>(step - from_step_) / elapsed : 0.0;
  std::ostringstream os;
  os << "t = " << std::setprecision(6) << std::setw(10) << t << " s  step " << std::setw(9) << step << "  "
     << std::setprecision(4) << rate << " steps/s  " << std::fixed
     << std::setprecision(1) << 100 * done << "%  elapsed " << format_duration(elapsed) << "  ETA "
     << format_duration(eta);
  if (tty_)
    log_ << "\r" << os.str() << "   " << (final ? "\n" : "") << std::flush;
  else
    log_ << os.str() << "\n" << std::flush;
}

void PhaseProfile::add(const char* name, double seconds) {
  for (auto& [n, t] : phases_)
    if (n == name) {
      t += seconds;
      return;
    }
  phases_.emplace_back(name, seconds);
}

void PhaseProfile::report(std::ostream& log, std::int64_t steps) const {
  if (phases_.empty()) return;
  double total = 0;
  for (auto& [n, t] : phases_) total += t;
  log << "Profile (synchronised per phase, " << steps << " steps):\n";
  for (auto& [n, t] : phases_)
    log << "  " << std::left << std::setw(44) << n << std::right << std::setw(10) << std::setprecision(4)
        << 1e6 * t / std::max<std::int64_t>(1, steps) << " us/step  " << std::setw(5) << std::setprecision(3)
        << 100 * t / total << " %\n";
}

}  // namespace scree

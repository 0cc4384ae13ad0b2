// Progress and PhaseProfile (see progress.hpp).
#include "progress.hpp"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "scree/comm/comm.hpp"

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

void PhaseProfile::report(std::ostream& out, std::int64_t steps, Comm& comm) const {
  // Formatted apart: the run's own later lines keep the log's formatting.
  std::ostringstream log;
  struct Flush {
    std::ostream& to;
    std::ostringstream& from;
    ~Flush() { to << from.str() << std::flush; }
  } flush{out, log};
  const int R = comm.size();
  const double per_step = 1e6 / static_cast<double>(std::max<std::int64_t>(1, steps));
  if (R == 1) {
    if (phases_.empty()) return;
    double total = 0;
    for (auto& [n, t] : phases_) total += t;
    log << "Profile (synchronised per phase, " << steps << " steps):\n";
    for (auto& [n, t] : phases_)
      log << "  " << std::left << std::setw(44) << n << std::right << std::setw(10) << std::setprecision(4)
          << t * per_step << " us/step  " << std::setw(5) << std::setprecision(3) << 100 * t / total << " %\n";
    return;
  }
  // Every rank's phases as "name\tseconds\n" lines, gathered on the root.
  std::ostringstream mine;
  mine << std::setprecision(17);
  for (auto& [n, t] : phases_) mine << n << '\t' << t << '\n';
  const std::string text = mine.str();
  std::vector<char> all;
  const std::vector<std::size_t> bytes = comm.gather(text.data(), text.size(), all, 0);
  if (comm.rank() != 0) return;
  std::vector<std::string> names;  // in the order the ranks first met them
  std::vector<std::vector<double>> t;  // [phase][rank]
  std::size_t at = 0;
  for (int r = 0; r < R; ++r) {
    std::istringstream in(std::string(all.data() + at, bytes[static_cast<std::size_t>(r)]));
    at += bytes[static_cast<std::size_t>(r)];
    std::string line;
    while (std::getline(in, line)) {
      const auto tab = line.rfind('\t');
      if (tab == std::string::npos) continue;
      const std::string name = line.substr(0, tab);
      std::size_t k = 0;
      while (k < names.size() && names[k] != name) ++k;
      if (k == names.size()) {
        names.push_back(name);
        t.emplace_back(static_cast<std::size_t>(R), 0.0);
      }
      t[k][static_cast<std::size_t>(r)] = std::stod(line.substr(tab + 1));
    }
  }
  if (names.empty()) return;
  const bool each = R <= 8;
  log << "Profile (synchronised per phase, " << steps << " steps, us/step " << (each ? "on each rank" : "least, mean, most over the ranks") << "):\n";
  log << "  " << std::left << std::setw(52) << "phase" << std::right;
  if (each)
    for (int r = 0; r < R; ++r) log << std::setw(10) << ("rank " + std::to_string(r));
  else
    log << std::setw(10) << "least" << std::setw(10) << "mean" << std::setw(10) << "most";
  log << "\n";
  std::vector<double> total(static_cast<std::size_t>(R), 0.0);
  auto row = [&](const std::string& name, const std::vector<double>& v) {
    log << "  " << std::left << std::setw(52) << name << std::right << std::fixed << std::setprecision(1);
    if (each)
      for (double x : v) log << std::setw(10) << x * per_step;
    else {
      double lo = v[0], hi = v[0], mean = 0;
      for (double x : v) lo = std::min(lo, x), hi = std::max(hi, x), mean += x / R;
      log << std::setw(10) << lo * per_step << std::setw(10) << mean * per_step << std::setw(10) << hi * per_step;
    }
    log << std::defaultfloat << "\n";
  };
  for (std::size_t k = 0; k < names.size(); ++k) {
    row(names[k], t[k]);
    for (int r = 0; r < R; ++r) total[static_cast<std::size_t>(r)] += t[k][static_cast<std::size_t>(r)];
  }
  row("all phases", total);
}

}  // namespace scree

// Running an ensemble (scree/ensemble/ensemble.hpp): each member's case is written, checked
// and run by scree as a process of its own, membersAtOnce at a time; members.csv keeps each
// member's state so that a stopped ensemble continues where it was (--restart).
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "scree/case/case.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/case/run_lock.hpp"
#include "scree/ensemble/ensemble.hpp"
#include "scree/exec/memory.hpp"
#include "scree/output/csv_file.hpp"
#include "scree/output/writer.hpp"

namespace fs = std::filesystem;

namespace scree {

namespace {

std::atomic<int> g_signal{0};

enum class State { pending, done, failed, stopped, error };

const char* state_name(State s) {
  switch (s) {
    case State::pending: return "pending";
    case State::done: return "done";
    case State::failed: return "failed";
    case State::stopped: return "stopped";
    case State::error: return "error";
  }
  return "pending";
}

struct MemberRow {
  std::vector<std::string> values;
  State state = State::pending;
  int exit = -1;
  double wall = 0;
};

/// A scree process for a member, its output appended to `log`. It runs in a process group of
/// its own: a Ctrl-C reaches the ensemble, which passes it on once (a member that got it
/// twice would stop at once, without writing the state it reached). It is sent SIGTERM
/// when the ensemble dies (killed without a chance to pass anything on), so that it writes
/// the state it reached and ends, and a later --restart finds it stopped, not running.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(errno));
  if (pid == 0) {  // only async-signal-safe calls until exec
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(128 + SIGTERM);  // the ensemble died before the line above
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd < 0) _exit(3);
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
    execv(argv[0], argv.data());
    _exit(3);
  }
  return pid;
}

int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 3;
}

/// A duration in seconds, to the millisecond.
std::string secs(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", v);
  return b;
}

void write_members(const fs::path& file, const EnsembleSpec& spec, const std::vector<MemberRow>& rows,
                   const std::vector<std::vector<std::optional<double>>>& q) {
  write_file_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << "member";
    for (const auto& p : spec.parameters) out << "," << csv_text(p.name);
    out << ",status,exit,wall [s]";
    for (const auto& s : spec.summary) out << "," << csv_text(s.name);
    out << "\n";
    for (std::size_t k = 0; k < rows.size(); ++k) {
      out << k;
      for (const auto& v : rows[k].values) out << "," << csv_text(v);
      out << "," << state_name(rows[k].state) << "," << (rows[k].exit < 0 ? std::string() : std::to_string(rows[k].exit))
          << "," << (rows[k].wall > 0 ? secs(rows[k].wall) : std::string());
      for (std::size_t i = 0; i < spec.summary.size(); ++i)
        out << "," << (k < q.size() && q[k][i] ? csv_number(*q[k][i]) : std::string());
      out << "\n";
    }
    out.close();
    if (!out) throw std::runtime_error("error writing " + tmp.string() + " (disk full?)");
  });
}

/// The members' rows of an earlier ensemble's members.csv (none when it has none); throws
/// when the ensemble it describes is not this one.
std::vector<MemberRow> read_members(const fs::path& file, const EnsembleSpec& spec) {
  std::vector<MemberRow> rows(static_cast<std::size_t>(spec.members()));
  for (std::int64_t k = 0; k < spec.members(); ++k) rows[static_cast<std::size_t>(k)].values = spec.member_values(k);
  std::ifstream in(file);
  if (!in) return rows;
  std::string line;
  std::getline(in, line);
  const std::size_t np = spec.parameters.size();
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_split(line);
    if (c.size() < np + 4) continue;
    const long long k = std::stoll(c[0]);
    if (k < 0 || k >= spec.members())
      throw std::runtime_error("ensemble/members.csv has member " + c[0] + ", and " + std::string(EnsembleSpec::kFile) +
                               " makes " + std::to_string(spec.members()));
    MemberRow& r = rows[static_cast<std::size_t>(k)];
    for (std::size_t i = 0; i < np; ++i)
      if (c[1 + i] != r.values[i])
        throw std::runtime_error(std::string(EnsembleSpec::kFile) + " changed since the ensemble ran: member " + c[0] +
                                 "'s " + spec.parameters[i].name + " was " + c[1 + i] + ", now " + r.values[i]);
    const std::string& st = c[1 + np];
    r.state = st == "done" ? State::done : st == "failed" ? State::failed : State::pending;
    r.exit = c[2 + np].empty() ? -1 : std::stoi(c[2 + np]);
    r.wall = c[3 + np].empty() ? 0.0 : std::stod(c[3 + np]);
  }
  return rows;
}

void write_summary(const fs::path& dir, const EnsembleSpec& spec, const std::vector<MemberRow>& rows,
                   const std::vector<std::vector<std::optional<double>>>& q, std::ostream& log) {
  if (spec.summary.empty()) return;
  std::vector<std::vector<double>> x(spec.summary.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (std::size_t i = 0; i < spec.summary.size(); ++i)
      if (rows[k].state == State::done && q[k][i]) x[i].push_back(*q[k][i]);
  write_file_atomically(dir / "summary.csv", [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << "quantity,members,mean,standard deviation,min,p5,p25,p50,p75,p95,max\n";
    for (std::size_t i = 0; i < x.size(); ++i) {
      const SampleStats s = sample_stats(x[i]);
      out << csv_text(spec.summary[i].name) << "," << s.n;
      for (double v : {s.mean, s.sd, s.min, s.p05, s.p25, s.p50, s.p75, s.p95, s.max}) out << "," << (s.n ? csv_number(v) : "");
      out << "\n";
      log << "scree: ensemble: " << spec.summary[i].name << " over " << s.n << " members: mean " << csv_number(s.mean)
          << ", standard deviation " << csv_number(s.sd) << ", p5 " << csv_number(s.p05) << ", p50 " << csv_number(s.p50) << ", p95 "
          << csv_number(s.p95) << std::endl;
    }
    out.close();
    if (!out) throw std::runtime_error("error writing " + tmp.string());
  });
  // The empirical exceedance curve: the fraction of the members above each value.
  write_file_atomically(dir / "exceedance.csv", [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << "quantity,value,exceedance probability\n";
    for (std::size_t i = 0; i < x.size(); ++i) {
      std::vector<double> v = x[i];
      std::sort(v.begin(), v.end());
      const double n = static_cast<double>(v.size());
      for (std::size_t j = 0; j < v.size(); ++j) {
        std::size_t above = v.size() - j - 1;
        while (above > 0 && v[v.size() - above] == v[j]) --above;  // ties: none of them above
        out << csv_text(spec.summary[i].name) << "," << csv_number(v[j]) << "," << csv_number(static_cast<double>(above) / n) << "\n";
      }
    }
    out.close();
    if (!out) throw std::runtime_error("error writing " + tmp.string());
  });
}

std::string values_text(const EnsembleSpec& spec, const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + spec.parameters[i].name + " " + v[i];
  return s;
}

}  // namespace

int run_ensemble(const fs::path& case_dir, const EnsembleRunOptions& opt, PluginRuntime& rt) {
  std::ostream& log = std::cout;
  std::ostream& err = std::cerr;
  EnsembleSpec spec;
  try {
    spec = EnsembleSpec::read(case_dir);
  } catch (const InputErrors& e) {
    err << e.what() << "\nscree: " << e.errors().size() << " error(s) in " << (case_dir / EnsembleSpec::kFile).string()
        << "; nothing was run\n";
    return 1;
  } catch (const InputError& e) {
    err << e.what() << "\nscree: nothing was run\n";
    return 1;
  }
  const std::int64_t n = spec.members();
  const fs::path ens = case_dir / "ensemble";
  const bool gpu = opt.device == "cuda";
  const int at_once = static_cast<int>(
      std::min<std::int64_t>(n, spec.members_at_once > 0 ? spec.members_at_once : gpu ? 1 : std::max(1, opt.threads)));
  const int threads = std::max(1, opt.threads / at_once);
  log << "scree: ensemble of " << case_dir.string() << ": " << n << " members (" << spec.parameters.size()
      << " parameter(s)), " << at_once << " at a time" << (gpu ? "" : ", " + std::to_string(threads) + " thread(s) each")
      << std::endl;

  std::optional<RunLock> lock;
  if (!opt.check) {
    std::string holder;
    lock = RunLock::acquire(case_dir, holder);
    if (!lock) {
      err << "scree: case " << case_dir.string() << " is in use by another run (" << holder << "); nothing was run\n";
      return 6;
    }
    if (fs::exists(ens) && !opt.overwrite && !opt.restart) {
      err << "scree: case " << case_dir.string() << " has the results of an earlier ensemble (" << ens.string()
          << "), which this run would replace; nothing was run. Continue it with --restart, replace it with "
             "--overwrite, or move it away\n";
      return 4;
    }
  }

  std::vector<MemberRow> rows;
  try {
    rows = read_members(opt.restart ? ens / "members.csv" : fs::path(), spec);
  } catch (const std::exception& e) {
    err << "scree: " << e.what() << "; nothing was run (--overwrite runs the ensemble as it is now)\n";
    return 1;
  }

  // SIGINT, SIGTERM: passed to the running members (which write the state they reached)
  // or checks; the ensemble then stops with what it has.
  struct sigaction sa {};
  sa.sa_handler = [](int s) { g_signal.store(s); };
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  // The members' cases, written and checked in a temporary place before anything runs or
  // an earlier ensemble is replaced; then written into ensemble/ for the run.
  const fs::path check_dir = fs::temp_directory_path() / ("scree-ensemble-check-" + std::to_string(getpid()));
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{check_dir};
  fs::path where = check_dir;
  auto dir_of = [&](std::int64_t k) { return where / member_dir(case_dir, k).filename(); };
  auto write_members_cases = [&](bool keep_existing) {
    try {
      fs::create_directories(where);
      for (std::int64_t k = 0; k < n; ++k) {
        const fs::path d = dir_of(k);
        if (rows[static_cast<std::size_t>(k)].state == State::done || (keep_existing && fs::exists(d / "system")))
          continue;
        write_member_case(case_dir, spec, k, d);
      }
    } catch (const InputError& e) {
      err << e.what() << "\nscree: nothing was run\n";
      return false;
    } catch (const std::exception& e) {
      err << "scree: " << e.what() << "; nothing was run\n";
      return false;
    }
    return true;
  };
  if (!write_members_cases(false)) return 1;
  std::vector<std::string> base = {opt.scree.string()};
  if (!opt.device.empty()) base.insert(base.end(), {"--device", opt.device});
  base.insert(base.end(), {"--threads", std::to_string(threads)});

  // Run `args_of(k)` for the members in `todo`, at_once at a time; `done(k, exit, wall)` after each.
  auto run_all = [&](const std::vector<std::int64_t>& todo, auto args_of, auto log_of, auto done) {
    std::map<pid_t, std::pair<std::int64_t, std::chrono::steady_clock::time_point>> running;
    std::size_t next = 0;
    int forwarded = 0;
    for (;;) {
      const int sig = g_signal.load();
      if (sig && !forwarded) {
        for (const auto& [pid, m] : running) kill(pid, sig);
        forwarded = sig;
      }
      if (running.empty() && (forwarded || next == todo.size())) break;
      while (!forwarded && next < todo.size() && static_cast<int>(running.size()) < at_once) {
        const std::int64_t k = todo[next++];
        running[spawn(args_of(k), log_of(k))] = {k, std::chrono::steady_clock::now()};
      }
      int status = 0;
      const pid_t pid = waitpid(-1, &status, WNOHANG);
      if (pid <= 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        continue;
      }
      const auto it = running.find(pid);
      if (it == running.end()) continue;
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.second).count();
      const std::int64_t k = it->second.first;
      running.erase(it);
      done(k, exit_code(status), wall);
    }
    return forwarded;
  };

  // Every member checked first: a bad value is reported before anything runs.
  std::vector<std::int64_t> todo;
  for (std::int64_t k = 0; k < n; ++k)
    if (rows[static_cast<std::size_t>(k)].state != State::done) todo.push_back(k);
  std::vector<std::int64_t> bad;
  const int sig_check = run_all(
      todo, [&](std::int64_t k) {
        auto a = base;
        a.insert(a.end(), {"--case", dir_of(k).string(), "--check"});
        return a;
      },
      [&](std::int64_t k) { return dir_of(k) / ".check.log"; },
      [&](std::int64_t k, int code, double) {
        if (code != 0) bad.push_back(k);
      });
  if (sig_check) return 128 + sig_check;
  std::sort(bad.begin(), bad.end());
  for (std::int64_t k : bad) {
    std::ifstream in(dir_of(k) / ".check.log");
    std::stringstream ss;
    ss << in.rdbuf();
    // The member's messages name the place it was checked in: say where it will be.
    std::string text = ss.str();
    const std::string from = dir_of(k).string(), to = member_dir(case_dir, k).string();
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
    err << "scree: ensemble member " << k << " (" << values_text(spec, rows[static_cast<std::size_t>(k)].values)
        << "), " << to << ":\n" << text;
  }
  for (std::int64_t k : todo) fs::remove(dir_of(k) / ".check.log");
  if (!bad.empty()) {
    err << "scree: " << bad.size() << " of " << todo.size() << " members have errors (above); their values are set by";
    for (std::size_t i = 0; i < spec.parameters.size(); ++i)
      err << (i ? ", " : " ") << spec.parameters[i].name << " at " << spec.parameters[i].where.str();
    err << " (in " << case_dir.string() << "); nothing was run\n";
    return 1;
  }
  // The members that run at once share the machine: the largest at_once of them must fit
  // in the free memory together (each member's own check compared it with all of it).
  {
    const Device device =
        gpu || (opt.device.empty() && mem::cuda_compiled() && mem::cuda_available()) ? Device::cuda : Device::cpu;
    std::vector<std::pair<double, std::int64_t>> host, dev;
    try {
      for (std::int64_t k : todo) {
        const Case c = Case::read(dir_of(k), rt);
        const MemoryEstimate e = estimate_memory(c, rt.registry(), device, true);
        host.emplace_back(e.host_bytes(), k);
        dev.emplace_back(e.device_bytes(), k);
      }
    } catch (const std::exception& e) {
      err << "scree: ensemble: " << e.what() << "\n";
      return 1;
    }
    for (auto* v : {&host, &dev}) {
      std::sort(v->rbegin(), v->rend());
      const bool is_dev = v == &dev;
      if (v->empty() || (is_dev && device != Device::cuda)) continue;
      double need = 0;
      for (int i = 0; i < at_once && i < static_cast<int>(v->size()); ++i) need += (*v)[static_cast<std::size_t>(i)].first;
      const mem::Available a = mem::available(is_dev ? Device::cuda : Device::cpu);
      if (!a.known || need <= static_cast<double>(a.bytes)) continue;
      int fits = 0;
      for (double sum = 0; fits < static_cast<int>(v->size()) && sum + (*v)[static_cast<std::size_t>(fits)].first <= static_cast<double>(a.bytes);)
        sum += (*v)[static_cast<std::size_t>(fits++)].first;
      err << (case_dir / EnsembleSpec::kFile).string() << ": membersAtOnce: " << at_once
          << " members at once need about " << mem::format_bytes(need) << " of " << (is_dev ? "GPU" : "host")
          << " memory (the largest, member " << v->front().second << ", " << mem::format_bytes(v->front().first)
          << "), more than the " << mem::format_bytes(static_cast<double>(a.bytes)) << " free (" << a.source << "): "
          << (fits > 0 ? "membersAtOnce " + std::to_string(fits) + " fits" : std::string("not one member fits"))
          << "; nothing was run\n";
      return 1;
    }
  }
  if (opt.check) {
    log << "scree: ensemble of " << case_dir.string() << ": every member's case is valid (" << n << " members)\n";
    return 0;
  }
  fs::remove_all(check_dir);
  if (opt.overwrite) fs::remove_all(ens);
  where = ens;
  if (!write_members_cases(opt.restart)) return 1;

  std::vector<std::vector<std::optional<double>>> q(rows.size(), std::vector<std::optional<double>>(spec.summary.size()));
  auto read_q = [&](std::int64_t k) {
    for (std::size_t i = 0; i < spec.summary.size(); ++i) {
      std::string why;
      q[static_cast<std::size_t>(k)][i] = read_quantity(dir_of(k), spec.summary[i], why);
      if (!q[static_cast<std::size_t>(k)][i])
        log << "scree: ensemble: member " << k << ": no " << spec.summary[i].name << " (" << why << ")" << std::endl;
    }
  };
  for (std::int64_t k = 0; k < n; ++k)
    if (rows[static_cast<std::size_t>(k)].state == State::done) read_q(k);
  write_members(ens / "members.csv", spec, rows, q);

  std::size_t finished = n - todo.size(), failed = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const int sig = run_all(
      todo,
      [&](std::int64_t k) {
        auto a = base;
        a.insert(a.end(), {"--case", dir_of(k).string()});
        const bool has_ckpt = fs::exists(dir_of(k) / "checkpoints") && !fs::is_empty(dir_of(k) / "checkpoints");
        a.push_back(opt.restart && has_ckpt ? "--restart" : "--overwrite");
        return a;
      },
      [&](std::int64_t k) { return dir_of(k) / "log.scree"; },
      [&](std::int64_t k, int code, double wall) {
        MemberRow& r = rows[static_cast<std::size_t>(k)];
        r.exit = code;
        r.wall += wall;
        r.state = code == 0 ? State::done : code == 5 ? State::failed : code >= 128 ? State::stopped : State::error;
        if (r.state == State::done) read_q(k);
        finished += r.state == State::done;
        failed += r.state == State::failed || r.state == State::error;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const std::size_t ended = finished + failed - (n - todo.size());
        log << "scree: ensemble: member " << k << " " << state_name(r.state) << " (exit " << code << ") in "
            << secs(wall) << " s; " << finished << " of " << n << " done" << (failed ? ", " + std::to_string(failed) + " failed" : "")
            << ", elapsed " << secs(elapsed) << " s";
        if (ended > 0 && ended < todo.size())
          log << ", about " << secs(elapsed / static_cast<double>(ended) * static_cast<double>(todo.size() - ended)) << " s to go";
        log << std::endl;
        if (r.state == State::failed || r.state == State::error)
          log << "scree: ensemble: member " << k << " (" << values_text(spec, r.values) << ") went wrong: its diagnosis is in "
              << (dir_of(k) / "log.scree").string() << std::endl;
        write_members(ens / "members.csv", spec, rows, q);
      });
  write_members(ens / "members.csv", spec, rows, q);
  write_summary(ens, spec, rows, q, log);
  if (sig) {
    log << "scree: ensemble stopped by signal " << sig << ": the running members wrote the state they reached; "
        << "continue with --restart" << std::endl;
    return 128 + sig;
  }
  if (failed) {
    err << "scree: ensemble: " << failed << " of " << n << " members went wrong (ensemble/members.csv; each one's "
        << "diagnosis in its log.scree); the summary is over the " << finished << " that finished\n";
    return 5;
  }
  log << "scree: ensemble done: " << n << " members in " << secs(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count())
      << " s; " << (ens / "members.csv").string() << (spec.summary.empty() ? "" : ", summary.csv, exceedance.csv") << std::endl;
  return 0;
}

}  // namespace scree

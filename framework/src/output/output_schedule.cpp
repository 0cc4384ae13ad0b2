// OutputSchedule (see output_schedule.hpp).
#include "output_schedule.hpp"

#include <algorithm>
#include <cmath>

namespace scree {
namespace {
/// Tolerance of "t has reached a scheduled time" [s].
double time_eps(double t) { return 1e-9 * std::max(1.0, std::fabs(t)) + 1e-12; }
}  // namespace

OutputSchedule::OutputSchedule(std::vector<std::unique_ptr<Writer>> writers, std::vector<Function> functions,
                               bool by_steps, double write_interval, double start_time)
    : writers_(std::move(writers)) {
  write_schedule_.control = by_steps ? Scheduled::Control::timeStep : Scheduled::Control::runTime;
  write_schedule_.interval = write_interval;
  write_schedule_.next_time = start_time;
  write_schedule_.next_step = 0;
  for (auto& w : writers_) wants_grid_ |= w->wants_grid();
  for (Function& f : functions) {
    functions_.push_back(std::move(f.object));
    reduces_.push_back(f.reduces);
    Scheduled s;
    s.control = f.control == Function::Control::timeStep  ? Scheduled::Control::timeStep
                : f.control == Function::Control::runTime ? Scheduled::Control::runTime
                                                          : Scheduled::Control::writeTime;
    s.interval = f.interval;
    s.next_time = start_time;
    s.next_step = 0;
    function_schedule_.push_back(s);
  }
  thread_ = std::make_unique<OutputThread>();
}

OutputSchedule::~OutputSchedule() { thread_.reset(); }

void OutputSchedule::next_event(double t, std::int64_t step, double& t_event, std::int64_t& step_event) const {
  auto consider = [&](const Scheduled& s) {
    if (s.control == Scheduled::Control::timeStep) {
      const std::int64_t due = s.next_step - step;
      if (due > 0 && (step_event < 0 || due < step_event)) step_event = due;
    } else if (s.control == Scheduled::Control::runTime && s.next_time > t) {
      t_event = std::min(t_event, s.next_time);
    }
  };
  if (!writers_.empty()) consider(write_schedule_);
  for (auto& s : function_schedule_) consider(s);
  if (!empty()) {
    // Function objects on writeTime follow the write schedule.
    if (write_schedule_.control == Scheduled::Control::timeStep) {
      const std::int64_t due = write_schedule_.next_step - step;
      if (due > 0 && (step_event < 0 || due < step_event)) step_event = due;
    } else if (write_schedule_.next_time > t) {
      t_event = std::min(t_event, write_schedule_.next_time);
    }
  }
}

OutputSchedule::Due OutputSchedule::due(double t, std::int64_t step, bool force_all) const {
  const double eps = time_eps(t);
  auto is_due = [&](const Scheduled& s, bool is_write) -> bool {
    // A function object on writeTime runs by the writers' clock.
    const bool follows_writes = !is_write && s.control == Scheduled::Control::writeTime;
    const Scheduled& clock = follows_writes ? write_schedule_ : s;
    if (clock.control == Scheduled::Control::timeStep) return step >= clock.next_step;
    return t >= clock.next_time - eps;
  };
  Due d;
  d.write_time = force_all || is_due(write_schedule_, true);
  d.write = !writers_.empty() && d.write_time;
  for (std::size_t i = 0; i < functions_.size(); ++i)
    if (force_all || is_due(function_schedule_[i], false)) d.functions.push_back(i);
  d.with_grid = wants_grid_ && d.write;
  return d;
}

std::vector<Writer*> OutputSchedule::piece_writers() const {
  std::vector<Writer*> ws;
  for (auto& w : writers_)
    if (w->writes_pieces()) ws.push_back(w.get());
  return ws;
}

bool OutputSchedule::gathers(const Due& d) const {
  for (auto i : d.functions)
    if (!reducing(i)) return true;
  if (!d.write) return false;
  return std::any_of(writers_.begin(), writers_.end(), [&](auto& w) { return !decomposed_ || !w->writes_pieces(); });
}

void OutputSchedule::submit(const Due& d, std::shared_ptr<Snapshot> snap,
                            std::vector<std::function<void(BodySnapshot&)>> finish) {
  std::vector<Writer*> ws;
  if (d.write)
    for (auto& w : writers_)
      if (!decomposed_ || !w->writes_pieces()) ws.push_back(w.get());
  std::vector<FunctionObject*> fs;
  for (auto i : d.functions)
    if (!reducing(i)) fs.push_back(functions_[i].get());
  thread_->submit([snap, finish = std::move(finish), ws, fs] {
    for (std::size_t i = 0; i < finish.size(); ++i) {
      const std::string material = snap->bodies[i].material;
      finish[i](snap->bodies[i]);
      snap->bodies[i].material = material;
    }
    for (auto* w : ws) w->write(*snap);
    for (auto* f : fs) f->execute(*snap);
  });
}

void OutputSchedule::bump(Scheduled& s, double t, std::int64_t step) const {
  if (s.control == Scheduled::Control::timeStep) {
    const auto iv = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::llround(s.interval)));
    while (s.next_step <= step) s.next_step += iv;
  } else {
    const double eps = time_eps(t);
    while (s.next_time <= t + eps) s.next_time += s.interval;
  }
}

void OutputSchedule::done(const Due& d, double t, std::int64_t step) {
  if (d.write_time) bump(write_schedule_, t, step);
  for (auto i : d.functions)
    if (function_schedule_[i].control != Scheduled::Control::writeTime) bump(function_schedule_[i], t, step);
}

std::vector<double> OutputSchedule::state() const {
  std::vector<double> s{write_schedule_.next_time, static_cast<double>(write_schedule_.next_step)};
  for (const Scheduled& f : function_schedule_) {
    s.push_back(f.next_time);
    s.push_back(static_cast<double>(f.next_step));
  }
  return s;
}

bool OutputSchedule::restore(const std::vector<double>& s) {
  if (s.size() < 2) return false;
  write_schedule_.next_time = s[0];
  write_schedule_.next_step = static_cast<std::int64_t>(s[1]);
  if (s.size() != 2 + 2 * function_schedule_.size()) return false;
  for (std::size_t i = 0; i < function_schedule_.size(); ++i) {
    function_schedule_[i].next_time = s[2 + 2 * i];
    function_schedule_[i].next_step = static_cast<std::int64_t>(s[3 + 2 * i]);
  }
  return true;
}

void OutputSchedule::finish() {
  thread_->drain();
  for (auto& w : writers_) w->finish();
  for (auto& f : functions_) f->finish();
}

}  // namespace scree

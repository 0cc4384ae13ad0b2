// Simulation: dispatches to Solver<2> or Solver<3> by the case's dimension.
#include "scree/solver/simulation.hpp"

#include <atomic>
#include <iostream>
#include <variant>

#include "scree/case/setup_check.hpp"
#include "solver.hpp"

namespace scree {

namespace {
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "request_stop must be async-signal-safe");
}  // namespace

void request_stop(int signal) noexcept { g_stop_signal.store(signal, std::memory_order_relaxed); }
int stop_requested() noexcept { return g_stop_signal.load(std::memory_order_relaxed); }

struct Simulation::Impl {
  std::variant<std::unique_ptr<Solver<2>>, std::unique_ptr<Solver<3>>> solver;
  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit([&](auto& s) -> decltype(auto) { return f(*s); }, solver);
  }
};

Simulation::Simulation(const Case& c, PluginRuntime& rt, const RunOptions& o) : impl_(std::make_unique<Impl>()) {
  if (o.check_setup) {
    // What the setup below would reject, all of it with file:line, before it allocates
    // or writes anything (the same checks as scree --check).
    SetupReport report = check_setup(c, rt, o.output, o.device);
    std::ostream& log = o.log ? *o.log : std::cout;
    for (const InputError& w : report.warnings) log << "warning: " << w.what() << "\n";
    if (!report.errors.empty()) throw InputErrors(std::move(report.errors));
  }
  if (c.dimension() == 3)
    impl_->solver = std::make_unique<Solver<3>>(c, rt, o);
  else
    impl_->solver = std::make_unique<Solver<2>>(c, rt, o);
}
Simulation::~Simulation() = default;

int Simulation::dimension() const { return impl_->solver.index() == 0 ? 2 : 3; }
RunStats Simulation::run() {
  return impl_->visit([](auto& s) { return s.run(); });
}
void Simulation::advance_to(double t, bool with_output) {
  impl_->visit([&](auto& s) { s.advance_to(t, with_output); });
}
void Simulation::run_steps(std::int64_t n) {
  impl_->visit([&](auto& s) { s.run_steps(n); });
}
Snapshot Simulation::snapshot(bool with_grid) {
  return impl_->visit([&](auto& s) { return s.snapshot(with_grid); });
}
void Simulation::set_velocities(std::size_t body, const std::vector<double>& v) {
  impl_->visit([&](auto& s) { s.set_velocities(body, v); });
}
double Simulation::time() const {
  return std::visit([](auto& s) { return s->time(); }, impl_->solver);
}
std::int64_t Simulation::steps() const {
  return std::visit([](auto& s) { return s->steps(); }, impl_->solver);
}
RunStats Simulation::stats() const {
  return std::visit([](auto& s) { return s->stats(); }, impl_->solver);
}

}  // namespace scree

// shakingTable: the selected nodes move with a shaken table, no-slip. The table moves along
// the unit direction e either sinusoidally,
//   v(t) = V sin(2 pi f (t - t0)) e,   V = 2 pi f A,   for t0 <= t < t1,
// so that its displacement A (1 - cos(2 pi f (t - t0))) starts from rest at t0 without a
// jump in velocity (a jump would ring the model's natural modes) and swings between 0 and
// 2A; or with an acceleration record a(tau), tau = t - t0 (a table or a CSV file: a
// function of time, time/function_of_time.hpp), whose velocity is its exact integral
//   v(t) = e int_{tau_0}^{tau} a(s) ds,   for t0 <= t < t1,
// zero before the record's first time tau_0 and, after its last, the velocity at its end
// (outOfBounds zero: the table stops accelerating). A record whose integral does not
// return to zero leaves the table moving: correct its baseline before use, as for any
// shaking-table input. Before t0 and after t1 the nodes are left alone (add a `fixed`
// condition for a table at rest). A slope or embankment model shaken at its base, as on
// the 1g shaking tables of physical modelling.
//
//   table { type shakingTable; face yMin; amplitude 0.01; frequency 2; direction (1 0); }
//   table { type shakingTable; face yMin; direction (1 0);
//           acceleration { type csvFile; file "constant/kobe.csv"; unit g; } }
//
// This condition is the example of a node law that is a plugin's own: its law is the
// struct below, run by NodeLawCondition (scree/boundary/node_law.hpp) as its own kernel
// after every grid update. Copy it for any law of your own.
#pragma once

#include <cmath>

#include "scree/boundary/node_law.hpp"
#include "scree/core/constants.hpp"
#include "scree/plugin/context.hpp"
#include "scree/time/function_of_time.hpp"

namespace scree::boundary {

struct ShakingTableLaw {
  Real e[3] = {0, 0, 0};  ///< unit direction of shaking
  Real speed = 0;         ///< peak velocity V = 2 pi f A [m/s] (sinusoidal)
  Real omega = 0;         ///< angular frequency 2 pi f [rad/s] (sinusoidal)
  Real t0 = 0, t1 = 0;    ///< the window of shaking [s]
  int recorded = 0;       ///< 1: the velocity is the integral of `acceleration`
  TimeTable acceleration;  ///< the record a(t - t0) [m/s^2]

  template <int D>
  SCREE_HD void apply(Real* v, const Real*, Real t) const {
    if (t < t0 || t >= t1) return;
    const Real s = recorded ? acceleration.integral(t - t0) : speed * sin(omega * (t - t0));
    for (int d = 0; d < D; ++d) v[d] = s * e[d];
  }
};

class ShakingTable final : public NodeLawCondition<ShakingTableLaw> {
 public:
  static constexpr const char* type_name = "shakingTable";
  static ParamSpec spec() {
    ParamSpec s(type_name,
                "nodes move with a shaken table along e: sinusoidally, v = 2 pi f A sin(2 pi f (t - t0)) e, or with "
                "the velocity of an acceleration record, v = e int a(t - t0) dt");
    Region::declare(s);
    s.scalar("amplitude", "m", "displacement amplitude A (the table swings between 0 and 2A)").positive().optional();
    s.scalar("frequency", "Hz", "shaking frequency f").positive().optional();
    s.function("acceleration", "m/s^2",
               "acceleration record a(t - t0) along e (instead of amplitude and frequency; after its last row the "
               "table keeps the velocity it has reached)")
        .optional();
    s.vector("direction", "-", "direction of shaking e (normalised)").size(-1);
    s.scalar("startTime", "s", "shaking starts at t0").default_value(0.0);
    s.scalar("endTime", "s", "shaking stops at t1").default_value(kUnbounded);
    s.check([](const Dictionary& d, std::vector<InputError>& errors) {
      const bool sine = d.has("amplitude") || d.has("frequency"), record = d.has("acceleration");
      if (record && sine)
        errors.emplace_back(d.at("acceleration").where(),
                            "acceleration: give either an acceleration record or amplitude and frequency, not both");
      else if (!record && !(d.has("amplitude") && d.has("frequency")))
        errors.emplace_back(d.where(), "shakingTable '" + d.name() +
                                           "': expected amplitude and frequency (a sinusoidal table) or acceleration "
                                           "(a record)");
    });
    return s;
  }
  ShakingTable(const ParamReader& r, const SolverContext& ctx)
      : NodeLawCondition(r, ctx, make_law(r)),
        record_(r.has("acceleration") ? FunctionOfTime(r.function("acceleration", 1, ctx.case_dir, {"", "zero"}))
                                      : FunctionOfTime()) {}

 protected:
  ShakingTableLaw on(const Exec& ex) const override {
    ShakingTableLaw l = law();
    if (l.recorded) l.acceleration = record_.on(ex);
    return l;
  }

 private:
  static ShakingTableLaw make_law(const ParamReader& r) {
    ShakingTableLaw l;
    const auto e = r.scalars("direction");
    Real len = 0;
    for (Real c : e) len += c * c;
    len = std::sqrt(len);
    if (len == 0) throw InputError(r.entry("direction").where(), "direction: must not be zero");
    for (std::size_t d = 0; d < e.size() && d < 3; ++d) l.e[d] = e[d] / len;
    l.recorded = r.has("acceleration") ? 1 : 0;
    if (!l.recorded) {
      l.omega = 2 * kPi * r.scalar("frequency");
      l.speed = l.omega * r.scalar("amplitude");
    }
    l.t0 = r.scalar("startTime");
    l.t1 = r.scalar("endTime");
    return l;
  }

  FunctionOfTime record_;
};

}  // namespace scree::boundary

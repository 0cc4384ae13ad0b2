// shakingTable: the selected nodes move with a table shaken sinusoidally, no-slip: the
// table's velocity is
//   v(t) = V sin(2 pi f (t - t0)) e,   V = 2 pi f A,   for t0 <= t < t1
// along the unit direction e, so that its displacement A (1 - cos(2 pi f (t - t0))) starts
// from rest at t0 without a jump in velocity (a jump would ring the model's natural modes)
// and swings between 0 and 2A. Before t0 and after t1 the nodes are left alone (add a
// `fixed` condition for a table at rest). A slope or embankment model shaken at its base,
// as on the 1g shaking tables of physical modelling.
//
//   table { type shakingTable; face yMin; amplitude 0.01; frequency 2; direction (1 0); }
//
// This condition is the example of a node law that is a plugin's own: its law is the
// struct below, run by NodeLawCondition (scree/boundary/node_law.hpp) as its own kernel
// after every grid update. Copy it for any law of your own.
#pragma once

#include <cmath>

#include "scree/boundary/node_law.hpp"
#include "scree/core/constants.hpp"

namespace scree::boundary {

struct ShakingTableLaw {
  Real e[3] = {0, 0, 0};  ///< unit direction of shaking
  Real speed = 0;         ///< peak velocity V = 2 pi f A [m/s]
  Real omega = 0;         ///< angular frequency 2 pi f [rad/s]
  Real t0 = 0, t1 = 0;    ///< the window of shaking [s]

  template <int D>
  SCREE_HD void apply(Real* v, const Real*, Real t) const {
    if (t < t0 || t >= t1) return;
    const Real s = speed * sin(omega * (t - t0));
    for (int d = 0; d < D; ++d) v[d] = s * e[d];
  }
};

class ShakingTable final : public NodeLawCondition<ShakingTableLaw> {
 public:
  static constexpr const char* type_name = "shakingTable";
  static ParamSpec spec() {
    ParamSpec s(type_name, "nodes move with a sinusoidally shaken table: v = 2 pi f A sin(2 pi f (t - t0)) e");
    Region::declare(s);
    s.scalar("amplitude", "m", "displacement amplitude A (the table swings between 0 and 2A)").positive();
    s.scalar("frequency", "Hz", "shaking frequency f").positive();
    s.vector("direction", "-", "direction of shaking e (normalised)").size(-1);
    s.scalar("startTime", "s", "shaking starts at t0").default_value(0.0);
    s.scalar("endTime", "s", "shaking stops at t1").default_value(kUnbounded);
    return s;
  }
  ShakingTable(const ParamReader& r, const SolverContext& ctx) : NodeLawCondition(r, ctx, law(r)) {}

 private:
  static ShakingTableLaw law(const ParamReader& r) {
    ShakingTableLaw l;
    const auto e = r.scalars("direction");
    Real len = 0;
    for (Real c : e) len += c * c;
    len = std::sqrt(len);
    if (len == 0) throw InputError(r.entry("direction").where(), "direction: must not be zero");
    for (std::size_t d = 0; d < e.size() && d < 3; ++d) l.e[d] = e[d] / len;
    l.omega = 2 * kPi * r.scalar("frequency");
    l.speed = l.omega * r.scalar("amplitude");
    l.t0 = r.scalar("startTime");
    l.t1 = r.scalar("endTime");
    return l;
  }
};

}  // namespace scree::boundary

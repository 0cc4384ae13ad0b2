// neoHookean: a third-party material plugin built out of tree against the installed
// Scree SDK (the test tests/sdk/CMakeLists.txt does exactly what a user would do).
//
// Hyperelastic compressible neo-Hookean solid (Bonet & Wood), written in the rate form
// Scree's materials receive: the Kirchhoff stress tau = mu (b - I) + lambda ln J I is
// tracked through the left Cauchy-Green tensor b, updated from the strain increment and
// spin as b <- Q b Q^T + deps b + b deps (first order), sigma = tau / J.
#pragma once

#include <cmath>

#include "scree/material/material.hpp"

namespace sdk_example {

using scree::Real;
using scree::Sym3;

struct NeoHookean {
  static constexpr const char* type_name = "neoHookean";
  struct Params {
    Real mu, lambda, rho;
  };
  struct State {
    Sym3 b;  ///< left Cauchy-Green tensor
    Real J;  ///< volume ratio
  };
  static scree::ParamSpec spec() {
    scree::ParamSpec s(type_name, "compressible neo-Hookean solid (out-of-tree example plugin)");
    s.scalar("shearModulus", "Pa", "mu").positive();
    s.scalar("lameLambda", "Pa", "lambda").positive();
    s.scalar("rho", "kg/m^3", "mass density").positive();
    return s;
  }
  static Params read(const scree::ParamReader& r) {
    return {r.scalar("shearModulus"), r.scalar("lameLambda"), r.scalar("rho")};
  }
  static Real density(const Params& p) { return p.rho; }
  static State initial_state(const Params&, Sym3&) { return {Sym3::identity(), 1.0}; }
  SCREE_HD static void update(const Params& p, State& s, Sym3& sigma, const scree::StrainIncrement& inc) {
    Sym3 b = scree::corotate(s.b, inc.spin);
    // b += deps b + b deps (symmetric product, first order in the increment)
    Sym3 db;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        Real v = 0;
        for (int k = 0; k < 3; ++k) v += inc.deps(i, k) * b(k, j) + b(i, k) * inc.deps(k, j);
        const int idx = i == j ? i : (i + j == 1 ? 3 : (i + j == 3 ? 4 : 5));
        db[idx] = v;
      }
    s.b = b + db;
    s.J = inc.J;
    const Real lnJ = log(s.J);
    sigma = (p.mu * (s.b - Sym3::identity()) + p.lambda * lnJ * Sym3::identity()) * (1 / s.J);
  }
  SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3&, Real rho, Real) {
    return sqrt((p.lambda + 2 * p.mu) / (rho * s.J));
  }
  static void describe(scree::OutputFields<NeoHookean>& out) {
    out.state("volumeRatio", &State::J, "-", "J = V / V0");
    out.state("leftCauchyGreen", &State::b, "-", "b = F F^T");
  }
};

}  // namespace sdk_example

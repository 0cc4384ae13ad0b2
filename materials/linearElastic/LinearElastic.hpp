// linearElastic: isotropic linear elasticity (Hooke's law) in rate form.
//
//   sigma <- corotate(sigma, W dt) + lambda tr(deps) I + 2 G deps
//   lambda = E nu / ((1 + nu)(1 - 2 nu)),  G = E / (2 (1 + nu))
//
// Stress is tension positive [Pa]; the co-rotation (Hughes-Winget, objective) is applied
// by the framework before update(). The P-wave speed sqrt((lambda + 2G)/rho) sets the
// CFL time step. This is the reference example of a material plugin: copy this folder
// to add one.
#pragma once

#include <cmath>

#include "scree/material/material.hpp"

namespace scree::materials {

struct LinearElastic {
  static constexpr const char* type_name = "linearElastic";

  struct Params {
    Real E;       ///< Young's modulus [Pa]
    Real nu;      ///< Poisson's ratio [-]
    Real rho;     ///< mass density [kg/m^3]
    Real lambda;  ///< first Lame constant [Pa] (derived)
    Real G;       ///< shear modulus [Pa] (derived)
  };
  struct State {};  // no internal variables

  static ParamSpec spec() {
    ParamSpec s(type_name, "Isotropic linear elasticity (Hooke's law), objective rate form");
    s.scalar("E", "Pa", "Young's modulus").positive();
    s.scalar("nu", "-", "Poisson's ratio").range(-1.0, 0.5).open_min().open_max();
    s.scalar("rho", "kg/m^3", "mass density").positive();
    return s;
  }
  static Params read(const ParamReader& r) {
    Params p{};
    p.E = r.scalar("E");
    p.nu = r.scalar("nu");
    p.rho = r.scalar("rho");
    p.lambda = p.E * p.nu / ((1 + p.nu) * (1 - 2 * p.nu));
    p.G = p.E / (2 * (1 + p.nu));
    return p;
  }
  static Real density(const Params& p) { return p.rho; }
  static State initial_state(const Params&, Sym3&) { return {}; }

  SCREE_HD static void update(const Params& p, State&, Sym3& sigma, const StrainIncrement& inc) {
    const Real tr = inc.deps.trace();
    for (int i = 0; i < 3; ++i) sigma[i] += p.lambda * tr + 2 * p.G * inc.deps[i];
    for (int i = 3; i < 6; ++i) sigma[i] += 2 * p.G * inc.deps[i];
  }
  SCREE_HD static Real wave_speed(const Params& p, const State&, const Sym3&, Real rho, Real) {
    return sqrt((p.lambda + 2 * p.G) / rho);
  }
  /// Output: the elastic energy per volume, 1/2 sigma : C^-1 : sigma =
  /// p^2/(2K) + s:s/(4G) (K = lambda + 2G/3; the energy budget's stored term).
  static void describe(OutputFields<LinearElastic>& out) {
    out.derived("elasticEnergy", "J/m^3", "elastic energy stored per volume, 1/2 sigma : C^-1 : sigma",
                [](const Params& p, const State&, const Sym3& sig) {
                  const Real K = p.lambda + 2 * p.G / 3, pr = pressure(sig);
                  const Sym3 sd = deviator(sig);
                  return pr * pr / (2 * K) + ddot(sd, sd) / (4 * p.G);
                });
  }
};

}  // namespace scree::materials

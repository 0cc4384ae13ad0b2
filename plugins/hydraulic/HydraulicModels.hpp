// Retention curves and relative permeabilities of two-phase bodies
// (scree/porous/hydraulic_model.hpp). Suction s = -p_w > 0 [Pa]; S_l the degree of
// saturation; S_e = (S_l - S_min) / (S_max - S_min).
#pragma once

#include <cmath>
#include <string_view>

#include "scree/params/spec.hpp"
#include "scree/porous/hydraulic_model.hpp"

namespace scree::hydraulic {

/// van Genuchten (1980), in the form of the rainfall-infiltration MPM we implement:
///   S_l(s) = S_min + (S_max - S_min) [1 + (s / p0)^(1 / (1 - lambda))]^(-lambda),  s > 0,
///   S_l = S_max for s <= 0.
/// In van Genuchten's notation n_vg = 1 / (1 - lambda), m = 1 - 1/n_vg = lambda and
/// alpha = 1 / p0 (PLAXIS: g_a = gamma_w / p0, g_n = n_vg, g_c = -lambda).
/// dS_l/ds = -(S_max - S_min) lambda n_vg / p0 (s/p0)^(n_vg - 1) [1 + (s/p0)^n_vg]^(-lambda - 1).
class VanGenuchten final : public RetentionModel {
 public:
  static constexpr const char* type_name = "vanGenuchten";
  static ParamSpec spec() {
    ParamSpec s(type_name, "van Genuchten retention curve S_l = S_min + (S_max - S_min) [1 + (s/p0)^(1/(1-lambda))]^-lambda");
    s.scalar("p0", "Pa", "suction scale p0 (air-entry-like pressure; alpha = 1/p0)").positive();
    s.scalar("lambda", "-", "shape exponent lambda = m = 1 - 1/n_vg").range(0, 1).open_min().open_max();
    s.scalar("Smin", "-", "residual degree of saturation S_min").range(0, 1).open_max();
    s.scalar("Smax", "-", "degree of saturation at zero suction S_max").range(0, 1).open_min();
    s.check([](const Dictionary& d, std::vector<InputError>& errors) {
      if (d.has("Smin") && d.has("Smax") && !(d.get_scalar("Smin") < d.get_scalar("Smax")))
        errors.emplace_back(d.at("Smin").where(), "Smin: must be smaller than Smax (" +
                                                      d.at("Smax").where().str() + ")");
    });
    return s;
  }
  explicit VanGenuchten(const ParamReader& r)
      : p0_(r.scalar("p0")), lambda_(r.scalar("lambda")), smin_(r.scalar("Smin")), smax_(r.scalar("Smax")) {}

  double saturation(double s) const override {
    if (s <= 0) return smax_;
    const double nv = 1 / (1 - lambda_);
    return smin_ + (smax_ - smin_) * std::pow(1 + std::pow(s / p0_, nv), -lambda_);
  }
  double dsaturation(double s) const override {
    if (s <= 0) return 0;
    const double nv = 1 / (1 - lambda_), x = s / p0_;
    return -(smax_ - smin_) * lambda_ * nv / p0_ * std::pow(x, nv - 1) * std::pow(1 + std::pow(x, nv), -lambda_ - 1);
  }
  double s_min() const override { return smin_; }
  double s_max() const override { return smax_; }
  double suction_scale() const override { return p0_; }
  double parameter(std::string_view name) const override {
    if (name == "p0") return p0_;
    if (name == "lambda") return lambda_;
    if (name == "Smin") return smin_;
    if (name == "Smax") return smax_;
    return std::nan("");
  }

 private:
  double p0_, lambda_, smin_, smax_;
};

/// Mualem (1976) with van Genuchten's closed form (van Genuchten 1980, eq. 8):
///   k_rel = S_e^(1/2) [1 - (1 - S_e^(1/m))^m]^2,
/// with m the retention curve's parameter `lambda` (vanGenuchten's, its m) unless given. The
/// floor keeps k_rel >= floor: at S_e -> 0 Mualem's k_rel -> 0 and the drag -> infinity; the
/// implicit drag copes with any value, the floor only keeps the coefficient finite. 1e-12
/// (the default) is below any flow it could carry (K_sat 1e-3 m/s: 1e-15 m/s).
class MualemVanGenuchten final : public PermeabilityModel {
 public:
  static constexpr const char* type_name = "mualemVanGenuchten";
  static ParamSpec spec() {
    ParamSpec s(type_name, "Mualem-van Genuchten relative permeability k_rel = Se^0.5 [1 - (1 - Se^(1/m))^m]^2");
    s.scalar("m", "-", "exponent m (default: the retention curve's, vanGenuchten's lambda)")
        .range(0, 1)
        .open_min()
        .open_max()
        .optional();
    s.scalar("floor", "-", "smallest k_rel").default_value(1e-12).range(0, 1).open_min();
    return s;
  }
  explicit MualemVanGenuchten(const ParamReader& r)
      : m_(r.has("m") ? r.scalar("m") : std::nan("")), floor_(r.scalar("floor")) {}
  std::string incompatible(const RetentionModel& ret) const override {
    if (std::isnan(m_) && std::isnan(ret.parameter("lambda")))
      return "m: the retention curve has no van Genuchten exponent (a parameter lambda) to take it from; give m";
    return {};
  }
  double relative(double se, const RetentionModel& ret) const override {
    const double m = std::isnan(m_) ? ret.parameter("lambda") : m_;  // incompatible() rules out NaN
    if (se <= 0) return floor_;
    if (se >= 1) return 1;
    const double k = std::sqrt(se) * std::pow(1 - std::pow(1 - std::pow(se, 1 / m), m), 2);
    return std::max(floor_, k);
  }

 private:
  double m_, floor_;
};

/// k_rel = S_e^a (Brooks & Corey / Averjanov), a = 3 by default.
class PowerLaw final : public PermeabilityModel {
 public:
  static constexpr const char* type_name = "powerLaw";
  static ParamSpec spec() {
    ParamSpec s(type_name, "relative permeability k_rel = max(floor, Se^exponent)");
    s.scalar("exponent", "-", "exponent a").default_value(3.0).positive();
    s.scalar("floor", "-", "smallest k_rel").default_value(1e-12).range(0, 1).open_min();
    return s;
  }
  explicit PowerLaw(const ParamReader& r) : a_(r.scalar("exponent")), floor_(r.scalar("floor")) {}
  double relative(double se, const RetentionModel&) const override {
    return std::max(floor_, std::pow(std::min(1.0, std::max(0.0, se)), a_));
  }

 private:
  double a_, floor_;
};

}  // namespace scree::hydraulic

// Element-test driver: drives one material point through a loading program and reports
// stresses in the geomechanics convention (compression positive).
//
// The driver works on an ElementPoint: a material point that can go back to the state it had
// at the start of an increment (for the Newton iterations of mixed stress/strain control).
// Two adapters are provided:
//   ElementPointOf<M>      a material struct M used directly (tests; always restorable)
//   ErasedElementPoint     a scree::PointMaterial made by the plugin registry; restorable when
//                          PointMaterial offers clone() or set_state() (detected at compile
//                          time). Otherwise mixed control falls back to an elastic-stiffness
//                          feedback without iterations, and says so on stderr.
//
// Loading programs (y vertical/axial, x-y the shear plane, z out of plane; the material sees the
// full 3D tensor in all of them: the triaxial ones are 3D states, the others plane strain):
//   undrainedSimpleShear  constant volume: L = [[0, gamma_dot, 0], 0, 0]  (deps_xy = gamma_dot dt/2,
//                         spin W_xy = gamma_dot dt/2 unless spin is off)
//   drainedSimpleShear    the same with the vertical stress held (unknown eps_yy, Newton)
//   drainedTriaxial       axial (y) strain rate prescribed; lateral (x, z) strains unknown with
//                         constant cell pressure or constant mean stress (Newton)
//   drainedTrueTriaxial   3D: axial (y) strain rate prescribed; lateral (x, z) strains unknown with
//                         constant mean stress and constant b = (sigma_2 - sigma_3)/(sigma_1 - sigma_3)
//                         (sigma_1 = sigma_yy, sigma_2 = sigma_zz, sigma_3 = sigma_xx, compression
//                         positive): b = 0 triaxial compression, b = 1 triaxial extension, between
//                         them a fixed intermediate Lode angle (Newton)
//   undrainedTriaxial     isochoric: eps_xx = eps_zz = -eps_yy/2
//   isotropicCompression  eps_xx = eps_yy = eps_zz
// The rate history is piecewise linear in time (segments of constant rate or constant
// acceleration); each increment uses the rate at its mid-point, so strains are exact.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "scree/material/material.hpp"

namespace scree::element {

// ---------------------------------------------------------------- the material point

class ElementPoint {
 public:
  virtual ~ElementPoint() = default;
  virtual std::string type_name() const = 0;
  virtual void initialise(Sym3& sigma) = 0;
  virtual void update(Sym3& sigma, const StrainIncrement& inc) = 0;
  virtual Real density() const = 0;
  virtual Real wave_speed(const Sym3& sigma, Real cell_size) const = 0;
  virtual const std::vector<OutputField>& output_fields() const = 0;
  virtual void evaluate(const OutputField& f, const Sym3& sigma, Real* out) const = 0;
  /// Whether checkpoint()/restore() work.
  virtual bool restorable() const = 0;
  virtual void checkpoint() = 0;
  virtual void restore() = 0;
};

/// A material struct used directly (header-only; what the unit tests use).
template <class M>
class ElementPointOf final : public ElementPoint {
 public:
  explicit ElementPointOf(const typename M::Params& p) : m_(p), saved_(p) {}
  std::string type_name() const override { return M::type_name; }
  void initialise(Sym3& sigma) override { m_.initialise(sigma); }
  void update(Sym3& sigma, const StrainIncrement& inc) override { m_.update(sigma, inc); }
  Real density() const override { return m_.density(); }
  Real wave_speed(const Sym3& sigma, Real h) const override { return m_.wave_speed(sigma, h); }
  const std::vector<OutputField>& output_fields() const override { return m_.output_fields(); }
  void evaluate(const OutputField& f, const Sym3& sigma, Real* out) const override { m_.evaluate(f, sigma, out); }
  bool restorable() const override { return true; }
  void checkpoint() override { saved_ = m_; }
  void restore() override { m_ = saved_; }
  const PointMaterialOf<M>& material() const { return m_; }

 private:
  PointMaterialOf<M> m_, saved_;
};

template <class P>
concept HasClone = requires(const P& p) {
  { p.clone() } -> std::convertible_to<std::unique_ptr<P>>;
};
template <class P>
concept HasSetState = requires(P& p, const std::vector<Real>& s) { p.set_state(s); };

/// A type-erased PointMaterial (from the plugin registry).
template <class P = PointMaterial>
class ErasedElementPointT final : public ElementPoint {
 public:
  explicit ErasedElementPointT(std::unique_ptr<P> m) : m_(std::move(m)) {}
  std::string type_name() const override { return m_->type_name(); }
  void initialise(Sym3& sigma) override { m_->initialise(sigma); }
  void update(Sym3& sigma, const StrainIncrement& inc) override { m_->update(sigma, inc); }
  Real density() const override { return m_->density(); }
  Real wave_speed(const Sym3& sigma, Real h) const override { return m_->wave_speed(sigma, h); }
  const std::vector<OutputField>& output_fields() const override { return m_->output_fields(); }
  void evaluate(const OutputField& f, const Sym3& sigma, Real* out) const override { m_->evaluate(f, sigma, out); }
  bool restorable() const override { return HasClone<P> || HasSetState<P>; }
  void checkpoint() override {
    if constexpr (HasClone<P>) {
      saved_ = m_->clone();
    } else if constexpr (HasSetState<P>) {
      saved_state_ = m_->state();
    }
  }
  void restore() override {
    if constexpr (HasClone<P>) {
      m_ = saved_->clone();
    } else if constexpr (HasSetState<P>) {
      m_->set_state(saved_state_);
    }
  }

 private:
  std::unique_ptr<P> m_, saved_;
  std::vector<Real> saved_state_;
};
using ErasedElementPoint = ErasedElementPointT<>;

// ---------------------------------------------------------------- the loading program

enum class Loading {
  undrainedSimpleShear,
  drainedSimpleShear,
  drainedTriaxial,
  undrainedTriaxial,
  isotropicCompression,
  drainedTrueTriaxial
};
enum class TriaxialControl { constantCellPressure, constantMeanStress };

inline const char* to_string(Loading l) {
  switch (l) {
    case Loading::undrainedSimpleShear: return "undrainedSimpleShear";
    case Loading::drainedSimpleShear: return "drainedSimpleShear";
    case Loading::drainedTriaxial: return "drainedTriaxial";
    case Loading::undrainedTriaxial: return "undrainedTriaxial";
    case Loading::isotropicCompression: return "isotropicCompression";
    case Loading::drainedTrueTriaxial: return "drainedTrueTriaxial";
  }
  return "?";
}

/// A piece of the rate history: rate(t) = rate0 + acceleration (t - t_start).
struct Segment {
  Real duration = 0;      ///< [s]
  Real rate = 0;          ///< rate at the start of the segment [1/s] (if rate_given)
  bool rate_given = false;  ///< false: continue from the end rate of the previous segment (0 first)
  Real acceleration = 0;  ///< [1/s^2]
};

struct Program {
  Loading loading = Loading::undrainedSimpleShear;
  TriaxialControl control = TriaxialControl::constantCellPressure;
  std::vector<Segment> segments;
  Real dt = 1e-4;               ///< time step [s]
  Real output_interval = 0;     ///< [s]; <= 0: every increment
  Real output_per_decade = 0;   ///< > 0: output times log-spaced (this many per decade of time)
  bool spin = true;             ///< simple shear: apply the spin increment (objective rotation)
  Sym3 sigma0 = Sym3::zero();   ///< initial stress, tension positive [Pa]
  Real newton_tolerance = 1e-10;  ///< relative residual of the stress conditions
  /// drainedTrueTriaxial: b = (sigma_2 - sigma_3)/(sigma_1 - sigma_3) held, with sigma_1 = sigma_yy,
  /// sigma_2 = sigma_zz, sigma_3 = sigma_xx (compression positive) [-], in [0, 1]
  Real b = 0;
  int newton_max_iterations = 25;

  Real duration() const {
    Real t = 0;
    for (const auto& s : segments) t += s.duration;
    return t;
  }
  /// The rate at time t (piecewise linear).
  Real rate_at(Real t) const {
    Real t0 = 0, r = 0;
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const Segment& s = segments[i];
      const Real r0 = s.rate_given ? s.rate : r;
      if (t < t0 + s.duration || i + 1 == segments.size()) return r0 + s.acceleration * (t - t0);
      r = r0 + s.acceleration * s.duration;
      t0 += s.duration;
    }
    return r;
  }
};

// ---------------------------------------------------------------- one row of results

struct Row {
  Real time = 0, shear_strain = 0, shear_rate = 0, loading_rate = 0, axial_strain = 0, volumetric_strain = 0;
  Sym3 sigma = Sym3::zero();   ///< total stress, tension positive
  Sym3 sigma_f = Sym3::zero(); ///< frictional part, tension positive
  Real void_ratio = NAN, granular_temperature = 0;
  std::vector<Real> extra;     ///< the material's other scalar outputs (names in Result)
};

struct Result {
  std::vector<std::string> extra_names;
  std::vector<Row> rows;
  long increments = 0;
  long newton_failures = 0;  ///< increments whose stress conditions did not converge
  Real max_residual = 0;     ///< largest final residual of the stress conditions [Pa]
};

namespace detail {

/// Tension-positive component -> compression positive (0 - s avoids writing "-0").
inline Real neg(Real s) { return Real(0) - s; }

struct FieldMap {
  const OutputField* fstress = nullptr;
  const OutputField* e = nullptr;
  const OutputField* T = nullptr;
  std::vector<const OutputField*> extra;
};

inline FieldMap map_fields(const ElementPoint& m, std::vector<std::string>& names) {
  FieldMap fm;
  for (const OutputField& f : m.output_fields()) {
    if (f.name == "frictionalStress" && f.components == 6) {
      fm.fstress = &f;
    } else if (f.name == "voidRatio" && f.components == 1) {
      fm.e = &f;
    } else if (f.name == "granularTemperature" && f.components == 1) {
      fm.T = &f;
    } else if (f.components == 1) {
      fm.extra.push_back(&f);
      names.push_back(f.name);
    }
  }
  return fm;
}

inline Row make_row(const ElementPoint& m, const FieldMap& fm, Real t, const Sym3& sig, const Sym3& eps,
                    Real shear_rate, Real rate) {
  Row r;
  r.time = t;
  r.shear_strain = 2 * eps[3];
  r.shear_rate = shear_rate;
  r.loading_rate = rate;
  r.axial_strain = neg(eps[1]);
  r.volumetric_strain = neg(eps.trace());
  r.sigma = sig;
  if (fm.fstress) {
    Real v[6];
    m.evaluate(*fm.fstress, sig, v);
    for (int c = 0; c < 6; ++c) r.sigma_f[c] = v[c];
  } else if (fm.T) {
    r.sigma_f = Sym3::zero();  // purely collisional
  } else {
    r.sigma_f = sig;  // purely frictional
  }
  if (fm.e) m.evaluate(*fm.e, sig, &r.void_ratio);
  if (fm.T) m.evaluate(*fm.T, sig, &r.granular_temperature);
  r.extra.resize(fm.extra.size());
  for (std::size_t i = 0; i < fm.extra.size(); ++i) m.evaluate(*fm.extra[i], sig, &r.extra[i]);
  return r;
}

/// Strain-controlled components of one increment and the unknown (stress-controlled) ones.
struct IncrementPlan {
  Sym3 known = Sym3::zero();  ///< prescribed strain increment (unknown components zero)
  Spin3 spin = Spin3::zero();
  int unknown[2] = {-1, -1};  ///< Voigt indices of unknown strain components
  int n_unknown = 0;
};

inline IncrementPlan plan(const Program& P, Real rate, Real dt) {
  IncrementPlan ip;
  switch (P.loading) {
    case Loading::undrainedSimpleShear:
    case Loading::drainedSimpleShear:
      ip.known[3] = Real(0.5) * rate * dt;
      if (P.spin) ip.spin.xy = Real(0.5) * rate * dt;
      if (P.loading == Loading::drainedSimpleShear) {
        ip.unknown[0] = 1;
        ip.n_unknown = 1;
      }
      break;
    case Loading::drainedTriaxial:
    case Loading::drainedTrueTriaxial:
      ip.known[1] = -rate * dt;
      ip.unknown[0] = 0;
      ip.unknown[1] = 2;
      ip.n_unknown = 2;
      break;
    case Loading::undrainedTriaxial:
      ip.known[1] = -rate * dt;
      ip.known[0] = ip.known[2] = Real(0.5) * rate * dt;
      break;
    case Loading::isotropicCompression:
      ip.known[0] = ip.known[1] = ip.known[2] = -rate * dt / 3;
      break;
  }
  return ip;
}

/// Residuals of the stress conditions (Pa), for the mixed-control loadings.
inline Eigen::VectorXd residual(const Program& P, const Sym3& s0, const Sym3& s) {
  Eigen::VectorXd r;
  switch (P.loading) {
    case Loading::drainedSimpleShear:
      r.resize(1);
      r(0) = s[1] - s0[1];  // vertical stress held
      break;
    case Loading::drainedTriaxial:
      r.resize(2);
      if (P.control == TriaxialControl::constantCellPressure) {
        r(0) = s[0] - s0[0];
        r(1) = s[2] - s0[2];
      } else {
        r(0) = s[0] - s[2];
        r(1) = pressure(s) - pressure(s0);
      }
      break;
    case Loading::drainedTrueTriaxial:
      // p held, and (sigma_zz - sigma_xx) = b (sigma_yy - sigma_xx): linear in the stress, the
      // same in either sign convention
      r.resize(2);
      r(0) = pressure(s) - pressure(s0);
      r(1) = (s[2] - s[0]) - P.b * (s[1] - s[0]);
      break;
    default: r.resize(0);
  }
  return r;
}

}  // namespace detail

/// Run the program on the material point. `on_row` (optional) sees each output row as it is
/// made (for streaming CSV); all rows are also returned unless keep_rows is false.
inline Result run(ElementPoint& m, const Program& P, const std::function<void(const Row&)>& on_row = {},
                  bool keep_rows = true) {
  Result res;
  const detail::FieldMap fm = detail::map_fields(m, res.extra_names);
  Sym3 sig = P.sigma0;
  m.initialise(sig);
  const Sym3 sig_ref = sig;  // the stress conditions hold the initial values
  Sym3 eps = Sym3::zero();
  const Real T_end = P.duration();
  const bool shear = P.loading == Loading::undrainedSimpleShear || P.loading == Loading::drainedSimpleShear;
  auto emit = [&](Real t, Real rate) {
    Row r = detail::make_row(m, fm, t, sig, eps, shear ? rate : 0, rate);
    if (on_row) on_row(r);
    if (keep_rows) res.rows.push_back(std::move(r));
  };
  emit(0, P.rate_at(0));
  if (!(T_end > 0) || !(P.dt > 0)) return res;
  const long N = static_cast<long>(std::ceil(T_end / P.dt - 1e-9));
  Real next_out = P.output_interval > 0 ? P.output_interval : 0;
  const bool log_out = P.output_per_decade > 0;
  const Real log_factor = log_out ? std::pow(Real(10), 1 / P.output_per_decade) : 1;
  if (log_out) next_out = P.dt;
  Eigen::VectorXd x_prev;  // last increment's unknown strains (Newton guess)
  Real dt_prev = P.dt;
  bool warned = false;
  const Real scale = std::max({norm(sig_ref), Real(1)});
  Real t = 0;
  for (long k = 0; k < N; ++k) {
    const Real dt = std::min(P.dt, T_end - t);
    if (!(dt > 0)) break;
    const Real rate = P.rate_at(t + Real(0.5) * dt);
    const detail::IncrementPlan ip = detail::plan(P, rate, dt);
    StrainIncrement inc;
    inc.deps = ip.known;
    inc.spin = ip.spin;
    inc.dt = dt;
    inc.J = std::exp((eps + ip.known).trace());
    if (ip.n_unknown == 0) {
      m.update(sig, inc);
    } else {
      const int nu = ip.n_unknown;
      Eigen::VectorXd x = Eigen::VectorXd::Zero(nu);
      if (x_prev.size() == nu) x = x_prev * (dt / dt_prev);
      auto deps_of = [&](const Eigen::VectorXd& xx) {
        Sym3 d = ip.known;
        for (int j = 0; j < nu; ++j) d[ip.unknown[j]] = xx(j);
        return d;
      };
      const Real tol = P.newton_tolerance * scale;
      Eigen::VectorXd r;
      if (m.restorable()) {
        const Sym3 sig0 = sig;
        m.checkpoint();
        auto eval = [&](const Eigen::VectorXd& xx, Sym3& s_out) {
          m.restore();
          s_out = sig0;
          StrainIncrement in2 = inc;
          in2.deps = deps_of(xx);
          in2.J = std::exp((eps + in2.deps).trace());
          m.update(s_out, in2);
          return detail::residual(P, sig_ref, s_out);
        };
        Sym3 s_try;
        r = eval(x, s_try);
        Eigen::MatrixXd J(nu, nu);
        bool have_J = false;
        for (int it = 0; it < P.newton_max_iterations && r.norm() > tol; ++it) {
          if (!have_J || it % 4 == 3) {  // Jacobian by forward differences
            const Real h = std::max(Real(1e-7) * std::max(norm(ip.known), x.norm()), Real(1e-13));
            for (int j = 0; j < nu; ++j) {
              Eigen::VectorXd xh = x;
              xh(j) += h;
              Sym3 s_h;
              J.col(j) = (eval(xh, s_h) - r) / h;
            }
            have_J = true;
          }
          const Eigen::VectorXd dx = J.colPivHouseholderQr().solve(-r);
          if (!dx.allFinite()) break;
          x += dx;
          r = eval(x, s_try);
        }
        // the material now holds the state of the last eval(x)
        sig = s_try;
        inc.deps = deps_of(x);
      } else {
        // No way back to the start of the increment: one prediction per increment with the
        // current elastic stiffness (from the P-wave modulus, nu = 1/4), which is stiffer than
        // the elastoplastic tangent, so the residual left over shrinks without oscillating and
        // is corrected in the next increment.
        if (!warned) {
          std::cerr << "scree-element: warning: this PointMaterial cannot restore its state (no clone() or "
                       "set_state()); mixed control uses elastic feedback without iterations\n";
          warned = true;
        }
        const Real c = m.wave_speed(sig, 1e30);
        const Real Mmod = std::max(m.density() * c * c, Real(1));
        auto elastic = [&](const Sym3& d) {
          Sym3 ds = d * (2 * Mmod / 3);
          for (int a = 0; a < 3; ++a) ds[a] += Mmod / 3 * d.trace();
          return ds;
        };
        Eigen::MatrixXd J(nu, nu);
        const Eigen::VectorXd rs = detail::residual(P, sig_ref, sig);
        for (int j = 0; j < nu; ++j) {
          Sym3 d = Sym3::zero();
          d[ip.unknown[j]] = 1;
          J.col(j) = detail::residual(P, sig_ref, sig + elastic(d)) - rs;
        }
        const Eigen::VectorXd rk = detail::residual(P, sig_ref, sig + elastic(ip.known));
        x = J.colPivHouseholderQr().solve(-rk);
        if (!x.allFinite()) x.setZero();
        inc.deps = deps_of(x);
        inc.J = std::exp((eps + inc.deps).trace());
        m.update(sig, inc);
        r = detail::residual(P, sig_ref, sig);
      }
      res.max_residual = std::max(res.max_residual, Real(r.norm()));
      if (r.norm() > 1e3 * tol) ++res.newton_failures;
      x_prev = x;
      dt_prev = dt;
    }
    eps += inc.deps;
    t = (k + 1 == N) ? T_end : t + dt;
    ++res.increments;
    const bool last = k + 1 == N;
    if (log_out) {
      if (last || t >= next_out * (1 - 1e-9)) {
        emit(t, rate);
        while (next_out <= t * (1 + 1e-9)) next_out *= log_factor;
      }
    } else if (P.output_interval <= 0 || last || t >= next_out - 1e-12 * T_end) {
      emit(t, rate);
      if (P.output_interval > 0)
        while (next_out <= t + 1e-12 * T_end) next_out += P.output_interval;
    }
  }
  return res;
}

// ---------------------------------------------------------------- CSV

/// The header: a comment block stating the conventions, then the column names.
inline void write_csv_header(std::ostream& os, const ElementPoint& m, const Program& P,
                             const std::vector<std::string>& extra_names, const std::string& source = "") {
  os << "# scree-element: " << to_string(P.loading) << " of material '" << m.type_name() << "'";
  if (!source.empty()) os << " (" << source << ")";
  os << "\n# units: Pa, s, 1/s, m^2/s^2. Stresses COMPRESSION POSITIVE: sigma_v = -sigma_yy (vertical/axial, y),\n"
        "# sigma_h = -sigma_xx, tau = sigma_xy (shear stress in the direction of the applied shear),\n"
        "# p = -tr(sigma)/3, q = sqrt(3/2 s:s). Strains: shear_strain = 2 eps_xy, axial_strain = -eps_yy,\n"
        "# volumetric_strain = -tr(eps) (compression positive, sums of the increments). _f: frictional part,\n"
        "# _col: collisional part (sigma - sigma_f); K_col = q_col/(q_col + q_f). loading_rate: the program's\n"
        "# rate (shear rate, axial or volumetric strain rate, compression positive).\n";
  os << "time,shear_strain,shear_rate,loading_rate,axial_strain,volumetric_strain,sigma_v,sigma_h,tau,p,q,"
        "void_ratio,granular_temperature,sigma_v_f,tau_f,sigma_v_col,tau_col,p_f,q_f,p_col,q_col,K_col";
  for (const auto& n : extra_names) os << "," << n;
  if (P.loading == Loading::drainedTrueTriaxial) os << ",sigma_z,sin3theta";
  os << "\n";
}

/// sin(3 theta) of a stress, compression-positive convention: (3 sqrt3/2) J3(-s)/J2^{3/2}, +1 in
/// triaxial compression, -1 in triaxial extension (the Lode angle of materials/simsand/README.md).
inline Real lode_sin3theta(const Sym3& sigma) {
  const Sym3 s = deviator(sigma * Real(-1));
  const Real J2 = Real(0.5) * ddot(s, s);
  const Real J3 = s[0] * (s[1] * s[2] - s[4] * s[4]) - s[3] * (s[3] * s[2] - s[4] * s[5]) +
                  s[5] * (s[3] * s[4] - s[1] * s[5]);
  return J2 > 0 ? std::clamp(Real(2.598076211353316) * J3 / (J2 * std::sqrt(J2)), Real(-1), Real(1)) : Real(0);
}

/// One row; `three_d` (drainedTrueTriaxial) adds sigma_z = -sigma_zz and sin3theta at the end.
inline void write_csv_row(std::ostream& os, const Row& r, bool three_d = false) {
  const Sym3 sc = r.sigma - r.sigma_f;
  const Real qf = deviatoric_stress(r.sigma_f), qc = deviatoric_stress(sc);
  const Real Kcol = qf + qc > 0 ? qc / (qf + qc) : 0;
  const Real v[] = {r.time,
                    r.shear_strain,
                    r.shear_rate,
                    r.loading_rate,
                    r.axial_strain,
                    r.volumetric_strain,
                    detail::neg(r.sigma[1]),
                    detail::neg(r.sigma[0]),
                    r.sigma[3],
                    pressure(r.sigma) + 0,
                    deviatoric_stress(r.sigma),
                    r.void_ratio,
                    r.granular_temperature,
                    detail::neg(r.sigma_f[1]),
                    r.sigma_f[3],
                    detail::neg(sc[1]),
                    sc[3],
                    pressure(r.sigma_f) + 0,
                    qf,
                    pressure(sc) + 0,
                    qc,
                    Kcol};
  char buf[64];
  bool first = true;
  for (Real x : v) {
    std::snprintf(buf, sizeof buf, "%.10g", x + Real(0));
    os << (first ? "" : ",") << buf;
    first = false;
  }
  for (Real x : r.extra) {
    std::snprintf(buf, sizeof buf, "%.10g", x + Real(0));
    os << "," << buf;
  }
  if (three_d) {
    for (Real x : {detail::neg(r.sigma[2]), lode_sin3theta(r.sigma)}) {
      std::snprintf(buf, sizeof buf, "%.10g", x + Real(0));
      os << "," << buf;
    }
  }
  os << "\n";
}

}  // namespace scree::element

// scree-richards core: retention models, the Celia et al. (1990) modified Picard scheme,
// the run loop and its CSV output. Conventions and units: richards1d.hpp.
#include "richards1d.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

namespace scree::richards1d {

// =======================================================================================
// Soil
// =======================================================================================
//
// van Genuchten (1980), written with the suction s = -p_w = -rho_w g h [Pa]:
//   S(s) = S_min + (S_max - S_min) [1 + (s/p0)^n_vG]^(-m),  n_vG = 1/(1 - lambda), m = lambda
// for s > 0 and S = S_max for s <= 0. This is van Genuchten's retention curve
// S_e = [1 + (alpha_vG |h|)^n]^(-m) with alpha_vG = rho_w g / p0 [1/m], n = n_vG and
// m = lambda = 1 - 1/n_vG: exactly the restriction m = 1 - 1/n under which Mualem's (1976)
// model has van Genuchten's closed form
//   k_rel(S_e) = S_e^(1/2) [1 - (1 - S_e^(1/m))^m]^2
// with S_e = (S - S_min)/(S_max - S_min). Here S_e^(1/m) = 1/(1 + x^n), x = s/p0, so
// 1 - S_e^(1/m) = x^n/(1 + x^n), evaluated in that form (no cancellation near S_e = 1).
//
// Gardner (1958) exponential model, as used by Srivastava & Yeh (1991):
//   K = K_sat exp(alpha h),  theta = theta_r + (theta_s - theta_r) exp(alpha h)   (h < 0)
// i.e. S_e = k_rel = exp(alpha h), theta_r = n S_min, theta_s = n S_max.

double Soil::effective_saturation(double h) const {
  if (h >= 0) return 1.0;
  if (retention == Retention::gardner) return std::exp(alpha * h);
  const double x = -rho_w * g * h / p0;  // s/p0
  return std::pow(1.0 + std::pow(x, n_vg()), -lambda);
}

double Soil::saturation(double h) const { return S_min + (S_max - S_min) * effective_saturation(h); }

double Soil::dS_dh(double h) const {
  if (h >= 0) return 0.0;
  if (retention == Retention::gardner) return (S_max - S_min) * alpha * std::exp(alpha * h);
  // dS/dh = (S_max - S_min) m n x^(n-1) (1 + x^n)^(-m-1) dx/dh (-1), dx/dh = -rho_w g/p0
  const double n = n_vg(), x = -rho_w * g * h / p0;
  return (S_max - S_min) * lambda * n * std::pow(x, n - 1.0) * std::pow(1.0 + std::pow(x, n), -lambda - 1.0) *
         (rho_w * g / p0);
}

double Soil::k_rel_of_Se(double Se) const {
  if (Se >= 1.0) return 1.0;
  if (Se <= 0.0) return 0.0;
  if (retention == Retention::gardner) return Se;
  const double m = lambda;
  const double b = 1.0 - std::pow(1.0 - std::pow(Se, 1.0 / m), m);
  return std::sqrt(Se) * b * b;
}

double Soil::k_rel(double h) const {
  double kr;
  if (h >= 0) {
    kr = 1.0;
  } else if (retention == Retention::gardner) {
    kr = std::exp(alpha * h);
  } else {
    const double n = n_vg(), m = lambda, x = -rho_w * g * h / p0;
    const double xn = std::pow(x, n);
    const double Se = std::pow(1.0 + xn, -m);
    const double b = 1.0 - std::pow(xn / (1.0 + xn), m);  // 1 - (1 - S_e^(1/m))^m
    kr = std::sqrt(Se) * b * b;
  }
  return std::max(kr, kr_min);
}

double Soil::stored_water(double h) const {
  const double S = saturation(h);
  return porosity * S + S_s * S * h;
}

double Soil::capacity(double h) const {
  const double S = saturation(h), dS = dS_dh(h);
  return porosity * dS + S_s * (S + h * dS);
}

double Soil::stored_water(double h, double eps) const {
  const double S = saturation(h);
  return S * (porosity - eps) + S_s * S * h;
}

double Soil::capacity(double h, double eps) const {
  // d/dh of S (n0 - eps(h)) + S_s S h at fixed total stress, with
  // eps = (dsigma - (S p_w - S_0 p_w0))/E_oed, p_w = rho_w g h: deps/dh = -rho_w g (S + h dS/dh)/E_oed.
  const double S = saturation(h), dS = dS_dh(h), dSp = S + h * dS;
  return dS * (porosity - eps) + S * rho_w * g * dSp / E_oed + S_s * dSp;
}

double Soil::saturation_for_flux(double q) const {
  if (!(q > 0 && q < K_sat)) throw std::invalid_argument("saturation_for_flux: needs 0 < q < K_sat");
  // k_rel(S_e) is increasing: bisection on S_e in (0, 1).
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (K_sat * k_rel_of_Se(mid) < q ? lo : hi) = mid;
  }
  return S_min + (S_max - S_min) * 0.5 * (lo + hi);
}

std::vector<double> steady_flux_profile(const Soil& soil, double q, double h_base, const std::vector<double>& z) {
  // Steady Darcy flux q downward: K (dh/dz + 1) = q, so dh/dz = q/K(h) - 1.
  auto f = [&](double h) { return q / soil.conductivity(h) - 1.0; };
  std::vector<double> h(z.size());
  h[0] = h_base;
  constexpr int sub = 64;
  for (std::size_t i = 1; i < z.size(); ++i) {
    const double dz = (z[i] - z[i - 1]) / sub;
    double y = h[i - 1];
    for (int k = 0; k < sub; ++k) {
      const double k1 = f(y), k2 = f(y + 0.5 * dz * k1), k3 = f(y + 0.5 * dz * k2), k4 = f(y + dz * k3);
      y += dz / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    h[i] = y;
  }
  return h;
}

std::vector<double> steady_state(const Settings& s, const std::vector<double>& z) {
  if (s.bottom != BottomCondition::head) return {};
  const Soil& soil = s.soil;
  const double hb = s.bottom_head;
  // The surface head of the steady profile grows with the flux q: bracket the q that gives
  // h(L) = target, then bisect.
  auto shoot = [&](double target) -> std::vector<double> {
    auto top = [&](double q) {
      const double hL = steady_flux_profile(soil, q, hb, z).back();
      return std::isfinite(hL) ? hL : -std::numeric_limits<double>::infinity();
    };
    double lo = 0, hi = soil.K_sat;
    for (int k = 0; top(lo) > target; ++k) {  // upward flow (evaporation) needed
      if (k > 60) return {};
      lo = lo == 0 ? -soil.K_sat : 2 * lo;
    }
    for (int k = 0; top(hi) < target; ++k) {
      if (k > 60) return {};
      hi *= 2;
    }
    for (int k = 0; k < 100 && hi - lo > 1e-15 * soil.K_sat; ++k) {
      const double mid = 0.5 * (lo + hi);
      (top(mid) < target ? lo : hi) = mid;
    }
    return steady_flux_profile(soil, 0.5 * (lo + hi), hb, z);
  };
  if (s.top == TopCondition::head) return shoot(s.top_head);
  std::vector<double> h = steady_flux_profile(soil, s.top_flux, hb, z);
  if (!(h.back() > s.ponding_head)) return h;
  return shoot(s.ponding_head);
}

double front_elevation(const std::vector<double>& z, const std::vector<double>& S, const std::vector<double>& S0,
                       const std::vector<double>& T) {
  constexpr double round_off = 1e-12;
  const std::size_t N = z.size() - 1;
  auto wettable = [&](std::size_t j) { return T[j] - S0[j] > round_off; };
  auto excess = [&](std::size_t j) { return S[j] - 0.5 * (S0[j] + T[j]); };
  if (!wettable(N) || excess(N) < 0) return z[N];
  double f_above = excess(N);
  for (std::size_t j = N; j-- > 0;) {
    if (!wettable(j)) return z[j];
    const double f = excess(j);
    if (f < 0) return z[j] + (z[j + 1] - z[j]) * (-f) / (f_above - f);
    f_above = f;
  }
  return z[0];
}

// =======================================================================================
// Column
// =======================================================================================

Column::Column(Settings s) : s_(std::move(s)) {
  const int N = s_.cells;
  if (N < 2) throw std::invalid_argument("Column: needs at least 2 cells");
  z_.resize(N + 1);
  for (int i = 0; i <= N; ++i) z_[i] = s_.height * i / N;
  std::vector<double> h(N + 1);
  switch (s_.initial) {
    case InitialCondition::hydrostatic:
      for (int i = 0; i <= N; ++i) h[i] = s_.water_table - z_[i];
      break;
    case InitialCondition::uniform:
      std::fill(h.begin(), h.end(), s_.initial_head);
      break;
    case InitialCondition::steadyFlux:
      h = steady_flux_profile(s_.soil, s_.initial_flux, s_.bottom_head, z_);
      break;
  }
  if (const auto hs = steady_state(s_, z_); !hs.empty()) {
    S_inf_.resize(hs.size());
    for (std::size_t i = 0; i < hs.size(); ++i) S_inf_[i] = s_.soil.saturation(hs[i]);
  }
  Kf_.assign(N, 0.0);
  a_.assign(N + 1, 0.0);
  b_ = c_ = r_ = delta_ = a_;
  set_initial_head(std::move(h));
}

void Column::set_initial_head(std::vector<double> h) {
  if (h.size() != z_.size()) throw std::invalid_argument("set_initial_head: one value per node");
  h_ = std::move(h);
  h_old_ = h_;
  W_old_.resize(h_.size());
  S0_.resize(h_.size());
  Sp0_.resize(h_.size());
  for (std::size_t i = 0; i < h_.size(); ++i) {
    W_old_[i] = s_.soil.stored_water(h_[i]);  // eps = 0, dsigma = 0 at t = 0
    S0_[i] = s_.soil.saturation(h_[i]);
    Sp0_[i] = s_.soil.rho_w * s_.soil.g * S0_[i] * h_[i];
  }
  W0_ = W_ = W_old_;
  eps_.assign(h_.size(), 0.0);
  dsig_.assign(h_.size(), 0.0);
  rate_.assign(h_.size(), 0.0);
  rate_valid_ = false;
  t_ = 0;
  dt_ = std::min(s_.dt_initial, s_.dt_max);
  ponded_ = false;
  q_in_ = q_out_ = 0;
  bal_ = Balance{};
  bal_.storage0 = bal_.storage = storage();
  cnt_ = Counters{};
}

std::vector<double> Column::saturation() const {
  std::vector<double> S(h_.size());
  for (std::size_t i = 0; i < h_.size(); ++i) S[i] = s_.soil.saturation(h_[i]);
  return S;
}

double Column::storage() const {
  double W = 0;
  for (int i = 0; i <= s_.cells; ++i) W += cell(i) * W_[i];
  return W;
}

double Column::interface_K(double Ka, double Kb) const {
  // Celia et al. (1990) use the arithmetic mean; the geometric mean is offered for
  // comparisons. Either is consistent (first order in the jump of K across a cell).
  return s_.mean == ConductivityMean::arithmetic ? 0.5 * (Ka + Kb) : std::sqrt(Ka * Kb);
}

// ---------------------------------------------------------------------------------------
// Skeleton storage (Settings::soil.E_oed > 0)
// ---------------------------------------------------------------------------------------
// The two-phase MPM's liquid mass balance (framework/include/scree/porous/two_phase.hpp:
// incompressible grains, liquid bulk modulus K_l, p_w compression positive)
//   (n S/K_l + n dS/dp_w) dp_w/dt = -(S div v_s + dq/dz)
// with Bishop's effective stress (chi = S, compression positive) sigma' = sigma - S p_w and an
// oedometric, small-strain, quasi-static skeleton: the compressive strain rate is
// deps/dt = (dsigma/dt - d(S p_w)/dt)/E_oed and div v_s = -deps/dt, so
//   [n S/K_l + n dS/dp_w + S (S + p_w dS/dp_w)/E_oed] dp_w/dt = -dq/dz + S (dsigma/dt)/E_oed.
// Conservative form. In the solid's reference frame (Z, the initial elevation) a unit of
// reference volume holds n J S of water (J = 1 - eps its volume; the grains' volume
// (1 - n) J = 1 - n0 is conserved, so n J = n0 - eps exactly), and with the liquid's
// compressibility, at the reference density,
//   W = S (n0 - eps) + S_s S h,    eps = (dsigma - (S p_w - S_0 p_w0))/E_oed            (*)
// (eps and the stress change dsigma since t = 0; S_0 p_w0 the initial state, where the
// skeleton is in equilibrium under the initial stress: eps = 0). dW/dt = -dq/dZ is the
// balance above: dW/dt = (n dS/dh + S_s (S + h dS/dh)) dh/dt - S deps/dt, and
// -S deps/dt = S rho_w g (S + h dS/dh)/E_oed dh/dt - S (dsigma/dt)/E_oed. The scheme
// conserves W (the residual of the Picard iteration is the balance of W), so the water
// balance, stored water including the skeleton's, closes as in the rigid case.
// The total vertical stress is the weight above (quasi-static, no inertia); per unit
// reference area the grains' weight never changes and the water's is rho_w g W, so
//   dsigma(Z) = rho_w g integral_Z^L (W - W(t=0)) dZ'
// (the solid density drops out). On the grid: the nodes above z_i and the upper half of node
// i's own cell (none for the surface node, all of the base node's half cell):
//   dsigma_i = rho_w g [ sum_{j>i} V_j (W_j - W0_j) + c_i (W_i - W0_i) ],  c_i = dz/2 (i < N), 0 (i = N)
// so that dsigma_0 = rho_w g (storage - storage(0)). Evaluated from the surface down, (*) is
// linear in W_i at given h_i and dsigma from above: W_i is solved for exactly, and W is a
// function of the head profile alone (no lag in the residual, so the balance still closes).
// The Picard matrix takes the local capacity dW_i/dh_i at fixed stress (Soil::capacity(h, eps));
// the dependence of W_i on the heads above (the weight) is left out of the matrix: lagged
// by one iteration. With water_load off dsigma = 0 (the skeleton responds to S p_w only).
// Neglected (README, "Skeleton storage"): the change of the geometry (gradients in the
// current length, the surface's rise), the porosity's effect on K, inertia.
void Column::stored_water(const std::vector<double>& h, std::vector<double>& W) {
  const Soil& soil = s_.soil;
  const int N = s_.cells;
  if (!soil.deformable()) {
    for (int i = 0; i <= N; ++i) W[i] = soil.stored_water(h[i]);
    return;
  }
  const double E = soil.E_oed, rg = soil.rho_w * soil.g;
  double above = 0;  // rho_w g sum_{j>i} V_j (W_j - W0_j) [Pa]
  for (int i = N; i >= 0; --i) {
    const double S = soil.saturation(h[i]), dSp = rg * S * h[i] - Sp0_[i];
    const double c = soil.water_load && i < N ? rg * 0.5 * dz() : 0.0;  // [Pa] per unit of W
    // W = S n0 - S (above + c (W - W0) - dSp)/E + S_s S h, solved for W:
    W[i] = (S * soil.porosity - S * (above - c * W0_[i] - dSp) / E + soil.S_s * S * h[i]) / (1.0 + S * c / E);
    dsig_[i] = above + c * (W[i] - W0_[i]);
    eps_[i] = (dsig_[i] - dSp) / E;
    if (soil.water_load) above += rg * cell(i) * (W[i] - W0_[i]);
  }
}

double Column::capacity(int i) const {
  return s_.soil.deformable() ? s_.soil.capacity(h_[i], eps_[i]) : s_.soil.capacity(h_[i]);
}

// One backward-Euler step of length dt from (h_old_, W_old_): the modified Picard
// iteration of Celia, Bouloutas & Zarba (1990). Each node i has the cell V_i (dz, or dz/2 at
// the ends) and the balance of the mixed form
//   V_i (W_i^{n+1} - W_i^n)/dt = q_{i-1/2} - q_{i+1/2},  q_{i+1/2} = -K_{i+1/2} ((h_{i+1}-h_i)/dz + 1)
// (their finite-difference scheme, with a lumped half cell at the end nodes). At Picard
// level m, W^{n+1,m+1} is expanded about h^{n+1,m},
//   W^{n+1,m+1} = W^{n+1,m} + C^{n+1,m} delta^m,   C = dW/dh,   delta^m = h^{n+1,m+1} - h^{n+1,m},
// and K is frozen at level m, which leaves one tridiagonal system per iteration for delta:
//   [V_i C_i/dt + (K_{i-1/2} + K_{i+1/2})/dz] delta_i - K_{i-1/2}/dz delta_{i-1} - K_{i+1/2}/dz delta_{i+1}
//     = -V_i (W(h_i^m) - W_i^n)/dt + q_{i-1/2}(h^m) - q_{i+1/2}(h^m).
// The right-hand side is the residual of the mixed form, so a converged solution conserves
// W exactly up to the truncation of the expansion (second order in delta; the fluxes
// telescope). Converged when max |delta| < picard_tolerance.
bool Column::picard(double dt, int& iterations) {
  const int N = s_.cells;
  const double dz = this->dz();
  const Soil& soil = s_.soil;
  const bool bottom_head = s_.bottom == BottomCondition::head;
  const bool top_head = top_is_head();
  // First iterate: h^n, or with a rate from the last step the explicit extrapolation
  // h^n + dt (h^n - h^{n-1})/dt_{n-1} (fewer iterations while the solution is smooth).
  h_ = h_old_;
  if (rate_valid_)
    for (std::size_t i = 0; i < h_.size(); ++i) h_[i] += dt * rate_[i];
  if (bottom_head) h_[0] = s_.bottom_head;
  if (top_head) h_[N] = s_.top == TopCondition::head ? s_.top_head : s_.ponding_head;
  const int lo = bottom_head ? 1 : 0, hi = top_head ? N - 1 : N;
  std::vector<double>& rhs = r_;
  std::vector<double> Kn(N + 1), flux(N);
  for (iterations = 1; iterations <= s_.picard_max_iterations; ++iterations) {
    ++cnt_.iterations;
    for (int i = 0; i <= N; ++i) Kn[i] = soil.conductivity(h_[i]);
    for (int i = 0; i < N; ++i) {
      Kf_[i] = interface_K(Kn[i], Kn[i + 1]);
      flux[i] = -Kf_[i] * ((h_[i + 1] - h_[i]) / dz + 1.0);  // q_{i+1/2}, upward positive
    }
    Kbase_ = Kn[0];
    stored_water(h_, W_);
    // Boundary fluxes (upward positive) for nodes whose balance is solved.
    const double q_base = s_.bottom == BottomCondition::freeDrainage ? -Kn[0] : 0.0;  // noFlux: 0
    const double q_top = -s_.top_flux;  // flux top, not ponded
    for (int i = lo; i <= hi; ++i) {
      const double V = cell(i);
      const double q_below = i == 0 ? q_base : flux[i - 1];
      const double q_above = i == N ? q_top : flux[i];
      double diag = V * capacity(i) / dt;
      a_[i] = c_[i] = 0.0;
      if (i > 0) {
        diag += Kf_[i - 1] / dz;
        if (i - 1 >= lo) a_[i] = -Kf_[i - 1] / dz;
      }
      if (i < N) {
        diag += Kf_[i] / dz;
        if (i + 1 <= hi) c_[i] = -Kf_[i] / dz;
      }
      b_[i] = diag;
      rhs[i] = -V * (W_[i] - W_old_[i]) / dt + q_below - q_above;
    }
    // Thomas algorithm (the matrix is symmetric and diagonally dominant: no pivoting).
    for (int i = lo + 1; i <= hi; ++i) {
      if (!(std::abs(b_[i - 1]) > 0)) return false;
      const double w = a_[i] / b_[i - 1];
      b_[i] -= w * c_[i - 1];
      rhs[i] -= w * rhs[i - 1];
    }
    if (!(std::abs(b_[hi]) > 0)) return false;
    delta_[hi] = rhs[hi] / b_[hi];
    for (int i = hi - 1; i >= lo; --i) delta_[i] = (rhs[i] - c_[i] * delta_[i + 1]) / b_[i];
    double dmax = 0;
    for (int i = lo; i <= hi; ++i) {
      h_[i] += delta_[i];
      dmax = std::max(dmax, std::abs(delta_[i]));
    }
    if (!std::isfinite(dmax)) return false;
    if (dmax < s_.picard_tolerance) {
      stored_water(h_, W_);  // of the converged heads: the boundary fluxes and the balance use it
      return true;
    }
  }
  --iterations;
  return false;
}

// After a converged step: the boundary fluxes, with the conductivities of the last
// iteration and the converged heads (the fluxes the last linear system balanced), and the
// water balance. A head boundary's flux is what its node's balance needs:
//   base:    q_{-1/2}  = V_0 (W_0^{n+1} - W_0^n)/dt + q_{1/2}
//   surface: q_{N+1/2} = q_{N-1/2} - V_N (W_N^{n+1} - W_N^n)/dt
void Column::account(double dt) {
  const double dz = this->dz();
  const auto flux = [&](int i) { return -Kf_[i] * ((h_[i + 1] - h_[i]) / dz + 1.0); };
  double q_base = 0, q_top = 0;  // upward positive
  switch (s_.bottom) {
    case BottomCondition::head: q_base = cell(0) * (W_[0] - W_old_[0]) / dt + flux(0); break;
    case BottomCondition::noFlux: q_base = 0; break;
    case BottomCondition::freeDrainage: q_base = -Kbase_; break;
  }
  q_top = top_is_head() ? surface_flux_under_head(dt) : -s_.top_flux;
  q_in_ = -q_top;
  q_out_ = -q_base;
  bal_.inflow += q_in_ * dt;
  bal_.outflow += q_out_ * dt;
  if (s_.top == TopCondition::flux) {
    bal_.applied += s_.top_flux * dt;
    if (ponded_) bal_.runoff += (s_.top_flux - q_in_) * dt;
  }
  bal_.storage = storage();
}

double Column::surface_flux_under_head(double dt) const {
  const int N = s_.cells;
  const double q_below = -Kf_[N - 1] * ((h_[N] - h_[N - 1]) / dz() + 1.0);
  return q_below - cell(N) * (W_[N] - W_old_[N]) / dt;  // upward positive
}

void Column::step(double t_limit) {
  const int N = s_.cells;
  const double remaining = t_limit - t_;
  if (!(remaining > 0)) return;
  const bool ponded_at_start = ponded_;
  bool switched = false, force = false;
  for (;;) {
    // Land exactly on t_limit; stretch by up to 1% rather than leave a sliver.
    const double proposed = std::min(dt_, s_.dt_max);
    const double dt = proposed >= 0.99 * remaining ? remaining : proposed;
    int it = 0;
    const bool ok = picard(dt, it);
    bool cut = !ok;
    if (ok && s_.top == TopCondition::flux && !force) {
      // The top switches between the prescribed flux and ponding: flux while the surface
      // stays at or below the ponding head, ponded (h = ponding_head) while the soil takes
      // at least the applied flux. Checked on the converged step; after a switch the step
      // is repeated. Wanting to switch back after that means the switch lies inside the
      // step: the step is cut, down to dt_min, where the ponded solution is kept.
      const bool want = ponded_ ? (-surface_flux_under_head(dt) > s_.top_flux) : (h_[N] > s_.ponding_head);
      if (want) {
        if (!switched) {
          ponded_ = !ponded_;
          switched = true;
          continue;
        }
        if (dt > s_.dt_min) {
          ponded_ = ponded_at_start;
          switched = false;
          cut = true;
        } else if (!ponded_) {
          ponded_ = force = true;
          continue;
        }
      }
    }
    // Time-error control. The local truncation error of backward Euler is (dt^2/2) h'' ;
    // estimated from the change of the rate between this step and the last one,
    //   e_i = (dt/2) |(h_i^{n+1} - h_i^n)/dt - (h_i^n - h_i^{n-1})/dt_{n-1}|,
    // over the nodes whose head is solved for. A step with max e_i > time_tolerance is
    // repeated with dt * max(0.2, 0.9 sqrt(time_tolerance / max e_i)), the size at which the
    // second-order estimate would meet the bound; an accepted step proposes the same for the
    // next one. No estimate on the first step and on the step after a switch of the top
    // condition (the rate has a kink there).
    double dt_error = std::numeric_limits<double>::infinity();
    if (!cut && s_.time_tolerance > 0 && rate_valid_ && ponded_ == ponded_at_start) {
      const int lo = s_.bottom == BottomCondition::head ? 1 : 0, hi = top_is_head() ? N - 1 : N;
      double e = 0;
      for (int i = lo; i <= hi; ++i) e = std::max(e, 0.5 * dt * std::abs((h_[i] - h_old_[i]) / dt - rate_[i]));
      const double factor = e > 0 ? 0.9 * std::sqrt(s_.time_tolerance / e) : kUnbounded;
      if (e > s_.time_tolerance && dt > s_.dt_min) {
        ++cnt_.error_rejected;
        dt_ = std::max(dt * std::max(0.2, factor), s_.dt_min);
        ponded_ = ponded_at_start;
        switched = false;
        continue;
      }
      dt_error = dt < proposed && factor >= 1 ? proposed : dt * factor;
    }
    if (cut) {
      if (!ok) ++cnt_.rejected;
      if (dt <= s_.dt_min) {
        std::ostringstream m;
        m << "Picard iteration failed at t = " << t_ << " s with dt = " << dt << " s (dtMin " << s_.dt_min
          << " s, " << it << " iterations, tolerance " << s_.picard_tolerance << " m)";
        if (s_.soil.S_s == 0 && !s_.soil.deformable()) m << "; a saturated column without a head boundary needs specificStorage > 0";
        throw std::runtime_error(m.str());
      }
      dt_ = std::max(dt * s_.dt_cut, s_.dt_min);
      continue;
    }
    // Accept.
    if (ponded_ != ponded_at_start) ++cnt_.switches;
    account(dt);
    t_ = dt == remaining ? t_limit : t_ + dt;
    for (int i = 0; i <= N; ++i) rate_[i] = (h_[i] - h_old_[i]) / dt;
    rate_valid_ = ponded_ == ponded_at_start;
    h_old_ = h_;
    W_old_ = W_;
    ++cnt_.steps;
    cnt_.max_iterations = std::max<long>(cnt_.max_iterations, it);
    // Step-size control on the iteration count. A step shortened to land on t_limit does
    // not grow the next one (its size says nothing about how hard the problem is).
    if (it >= s_.slow_iterations)
      dt_ = std::max(dt * s_.dt_shrink, s_.dt_min);
    else if (it <= s_.fast_iterations && dt >= proposed)
      dt_ = std::min(proposed * s_.dt_grow, s_.dt_max);
    dt_ = std::max(std::min(dt_, dt_error), s_.dt_min);
    return;
  }
}

void Column::advance_to(double t_end) {
  while (t_ < t_end) step(t_end);
}

double Column::front_elevation() const {
  return richards1d::front_elevation(z_, saturation(), S0_,
                                     std::vector<double>(z_.size(), s_.soil.saturation(h_.back())));
}

double Column::front_elevation_steady() const {
  if (S_inf_.empty()) return std::numeric_limits<double>::quiet_NaN();
  return richards1d::front_elevation(z_, saturation(), S0_, S_inf_);
}

// =======================================================================================
// A run and its output
// =======================================================================================

namespace {

std::ofstream open_csv(const std::filesystem::path& p) {
  std::ofstream f(p);
  if (!f) throw std::runtime_error("cannot write " + p.string());
  f << std::setprecision(10);
  return f;
}

}  // namespace

RunSummary run(const Settings& s, const std::filesystem::path& out, std::ostream* log) {
  const auto wall0 = std::chrono::steady_clock::now();
  std::filesystem::create_directories(out);
  Column col(s);
  const double dz = s.height / s.cells;

  auto profiles = open_csv(out / "profiles.csv");
  profiles << "# scree-richards head profiles. z [m] elevation (up), h [m] pressure head, p_w = rho_w g h [Pa],\n"
              "# S [-] saturation, theta = n S [-], k_rel [-], K = K_sat k_rel [m/s]\n";
  auto surface = open_csv(out / "surface.csv");
  surface << "# scree-richards water balance. Rates [m/s] are averages since the previous row, downward positive;\n"
             "# cumulative amounts and storage [m] of water per unit area; storage = integral of theta + S_s S h dz;\n"
             "# balance_error = (cum_inflow - cum_outflow) - (storage - storage(0)); surface_h [m]; ponded: 1 while\n"
             "# the surface holds the ponding head under a flux top\n"
             "time,applied_rate,infiltration_rate,outflow_rate,cum_applied,cum_inflow,cum_outflow,cum_runoff,"
             "storage,balance_error,surface_h,ponded\n";
  auto front = open_csv(out / "front.csv");
  front << "# scree-richards wetting front [m]. z_front: scanning down from the surface, the first elevation where\n"
           "# S < (S_0(z) + S_surface)/2, S_0 the initial saturation, linear between nodes; z_front_steady: the same\n"
           "# with the steady state S_inf(z) of the boundary conditions in place of S_surface (nan: none); the scan\n"
           "# stops at the first node whose target does not exceed S_0 (nothing to wet there); depth = L - z_front\n"
           "time,z_front,depth,z_front_steady,S_surface\n";

  const bool deformable = s.soil.deformable();
  if (deformable)
    profiles << "# deformable skeleton (E_oed = " << s.soil.E_oed << " Pa): theta = (n0 - eps) S the water per unit\n"
             << "# reference volume; eps [-] the compressive volumetric strain since t = 0, n = 1 - (1 - n0)/(1 - eps)\n"
             << "# the porosity, dsigma [Pa] the change of the total vertical stress (compression positive)\n";
  profiles << "time,z,h,p_w,S,theta,k_rel,K" << (deformable ? ",eps,n,dsigma" : "") << '\n';
  auto write_profile = [&] {
    const auto& h = col.head();
    for (std::size_t i = 0; i < h.size(); ++i) {
      const double S = s.soil.saturation(h[i]), kr = s.soil.k_rel(h[i]);
      const double eps = col.strain()[i];
      profiles << col.time() << ',' << col.z()[i] << ',' << h[i] << ',' << s.soil.rho_w * s.soil.g * h[i] << ','
               << S << ',' << (s.soil.porosity - eps) * S << ',' << kr << ',' << s.soil.K_sat * kr;
      if (deformable)
        profiles << ',' << eps << ',' << 1.0 - (1.0 - s.soil.porosity) / (1.0 - eps) << ',' << col.stress_change()[i];
      profiles << '\n';
    }
  };
  Balance prev = col.balance();
  double t_row = 0;
  auto write_history = [&] {
    const Balance& b = col.balance();
    const double t = col.time(), span = t - t_row;
    auto rate = [&](double now, double before) { return span > 0 ? (now - before) / span : 0.0; };
    surface << t << ',' << rate(b.applied, prev.applied) << ',' << rate(b.inflow, prev.inflow) << ','
            << rate(b.outflow, prev.outflow) << ',' << b.applied << ',' << b.inflow << ',' << b.outflow << ','
            << b.runoff << ',' << b.storage << ',' << b.error() << ',' << col.head().back() << ','
            << (col.ponded() ? 1 : 0) << '\n';
    const double zf = col.front_elevation();
    front << t << ',' << zf << ',' << s.height - zf << ',' << col.front_elevation_steady() << ','
          << s.soil.saturation(col.head().back()) << '\n';
    prev = b;
    t_row = t;
  };

  RunSummary sum;
  for (double zp : {0.75 * s.height, 0.5 * s.height, 0.25 * s.height, dz}) sum.front_passages.push_back({zp});
  double t_prev = 0, zf_prev = col.front_elevation(), zs_prev = col.front_elevation_steady();
  auto track_front = [&] {
    const double t = col.time(), zf = col.front_elevation(), zs = col.front_elevation_steady();
    auto passage = [&](double& tp, double zp, double z_before, double z_now) {
      if (tp < 0 && z_now <= zp)  // linear in time within the step
        tp = z_before > zp ? t_prev + (t - t_prev) * (z_before - zp) / (z_before - z_now) : t;
    };
    for (auto& p : sum.front_passages) {
      passage(p.t, p.z, zf_prev, zf);
      if (!std::isnan(zs)) passage(p.t_steady, p.z, zs_prev, zs);
    }
    if (sum.first_ponding_time < 0 && col.ponded()) sum.first_ponding_time = t;
    t_prev = t, zf_prev = zf, zs_prev = zs;
  };

  std::vector<double> ptimes = s.profile_times;
  std::sort(ptimes.begin(), ptimes.end());
  std::size_t next_profile = 0;
  if (next_profile < ptimes.size() && ptimes[next_profile] <= 0) {
    write_profile();
    ++next_profile;
  }
  write_history();
  long next_history = 1;
  double last_report = 0;
  while (col.time() < s.end_time) {
    double target = s.end_time;
    if (next_profile < ptimes.size()) target = std::min(target, ptimes[next_profile]);
    if (s.history_interval > 0) target = std::min(target, next_history * s.history_interval);
    col.step(target);
    track_front();
    const double t = col.time();
    if (s.history_interval <= 0 || t >= next_history * s.history_interval || t >= s.end_time) {
      write_history();
      if (s.history_interval > 0)
        while (next_history * s.history_interval <= t) ++next_history;
    }
    while (next_profile < ptimes.size() && ptimes[next_profile] <= t) {
      write_profile();
      ++next_profile;
    }
    if (log && t - last_report >= 0.1 * s.end_time) {
      *log << "  t = " << std::setw(10) << t << " s  dt = " << std::setw(10) << col.dt_next()
           << " s  front z = " << col.front_elevation() << " m  steps " << col.counters().steps << '\n';
      last_report = t;
    }
  }
  sum.balance = col.balance();
  sum.counters = col.counters();
  sum.end_time = col.time();
  sum.front_final = col.front_elevation();
  sum.front_steady_final = col.front_elevation_steady();
  sum.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (log) {
    const Balance& b = sum.balance;
    const double scale = std::max({std::abs(b.inflow), std::abs(b.outflow), std::abs(b.storage - b.storage0), 1e-300});
    *log << std::setprecision(6) << "done: t = " << sum.end_time << " s, " << sum.counters.steps << " steps ("
         << sum.counters.rejected << " Picard failures, " << sum.counters.error_rejected
         << " repeated for the time error), " << sum.counters.iterations << " Picard iterations (at most "
         << sum.counters.max_iterations << " in a step), " << sum.counters.switches << " top switches, "
         << sum.wall_seconds << " s wall\n"
         << "water [m]: inflow " << b.inflow << ", outflow " << b.outflow << ", storage change "
         << b.storage - b.storage0 << ", runoff " << b.runoff << ", balance error " << b.error() << " ("
         << b.error() / scale << " relative)\n";
    if (sum.first_ponding_time >= 0) *log << "surface first ponded at t = " << sum.first_ponding_time << " s\n";
    auto when = [](double t) { return t >= 0 ? "t = " + std::to_string(t) + " s" : std::string("not reached"); };
    *log << "front (z_front | z_front_steady) at\n";
    for (const auto& p : sum.front_passages)
      *log << "  z <= " << std::setw(8) << p.z << " m: " << std::setw(16) << when(p.t) << " | "
           << (col.steady_saturation().empty() ? std::string("-") : when(p.t_steady)) << '\n';
    *log << "front at the end: z = " << sum.front_final << " m | " << sum.front_steady_final << " m\n";
  }
  return sum;
}

}  // namespace scree::richards1d

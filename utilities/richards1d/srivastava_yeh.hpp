// The analytic solution of Srivastava & Yeh (1991, Water Resour. Res. 27(5):753-762) for
// 1D transient infiltration towards a water table through a homogeneous soil with
// Gardner's (1958) exponential functions:
//   K(h) = K_s exp(alpha h),   theta(h) = theta_r + (theta_s - theta_r) exp(alpha h),
// so that Richards' equation d(theta)/dt = d/dz [K (dh/dz + 1)] becomes linear in
// K* = K/K_s:  dK*/dt* = d2K*/dz*2 + dK*/dz*.
//
// Problem (z upward from the water table, SI units):
//   h(0, t) = h_r (here 0: the water table at the base), column height L;
//   infiltration rate q_A [m/s] (downward) for t < 0, steady: the initial profile;
//   infiltration rate q_B for t > 0 at z = L: K (dh/dz + 1) = q_B.
// Dimensionless variables (eq. 4): z* = alpha z, L* = alpha L, q_A* = q_A/K_s,
// q_B* = q_B/K_s, t* = alpha K_s t / (theta_s - theta_r).
// Initial condition (eq. 6a):  K*(z*, 0) = q_A* - (q_A* - exp(alpha h_r)) exp(-z*)
// Eigenvalues (eq. 10): the positive roots lambda_n of  tan(lambda L*) + 2 lambda = 0
// Solution (eq. 12a):
//   K*(z*, t*) = q_B* - (q_B* - exp(alpha h_r)) exp(-z*)
//                - 4 (q_B* - q_A*) exp((L* - z*)/2) exp(-t*/4)
//                  sum_n  sin(lambda_n z*) sin(lambda_n L*) exp(-lambda_n^2 t*) / (1 + L*/2 + 2 lambda_n^2 L*)
// Flux at the water table (eq. 12b), downward positive:
//   q(0, t)/K_s = q_B* - 4 (q_B* - q_A*) exp(L*/2) exp(-t*/4)
//                 sum_n  lambda_n sin(lambda_n L*) exp(-lambda_n^2 t*) / (1 + L*/2 + 2 lambda_n^2 L*)
// and h = ln(K*)/alpha.
//
// The series, derived independently here as a check: with u = K* - K*_steady(q_B) and
// u = exp(-z*/2 - t*/4) w, w_t = w_zz, w(0) = 0, w_z + w/2 = 0 at L*: eigenfunctions
// sin(lambda z*) with tan(lambda L*) = -2 lambda, norm L*/2 + 1/(1 + 4 lambda^2); the initial
// w = 2 (q_A* - q_B*) sinh(z*/2) has coefficients 4 (q_A* - q_B*) exp(L*/2) sin(lambda L*) /
// (1 + L*/2 + 2 lambda^2 L*), which is eq. 12a. The unit test checks it reproduces eq. 6a
// at t = 0.
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace scree::richards1d::srivastava_yeh {

struct Problem {
  double L = 1;        // column height [m]
  double alpha = 1;    // Gardner alpha [1/m]
  double K_s = 1e-5;   // [m/s]
  double theta_s = 0.4, theta_r = 0.06;  // [-]
  double q_A = 0;      // initial steady infiltration rate [m/s], downward
  double q_B = 0;      // infiltration rate for t > 0 [m/s], downward
  double h_r = 0;      // head at the base [m]
};

class Solution {
 public:
  /// `terms`: eigenvalues kept; the series is summed until exp(-lambda_n^2 t*) < 1e-17
  /// and stops with an error when that needs more (small t* needs many).
  explicit Solution(const Problem& p, int terms = 20000) : p_(p) {
    const double Ls = p.alpha * p.L;
    lambda_.reserve(terms);
    // lambda_n lies in ((n - 1/2) pi/L*, n pi/L*), where tan(lambda L*) < 0; bisection on
    // g = sin(lambda L*) + 2 lambda cos(lambda L*), which has no poles and changes sign there.
    const double pi = std::numbers::pi;
    auto g = [&](double l) { return std::sin(l * Ls) + 2 * l * std::cos(l * Ls); };
    for (int n = 1; n <= terms; ++n) {
      double lo = (n - 0.5) * pi / Ls, hi = n * pi / Ls;
      const double glo = g(lo);
      for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((g(mid) > 0) == (glo > 0) ? lo : hi) = mid;
      }
      lambda_.push_back(0.5 * (lo + hi));
    }
  }

  double t_star(double t) const { return p_.alpha * p_.K_s * t / (p_.theta_s - p_.theta_r); }

  /// K* = K/K_s at elevation z [m] and time t [s] (eq. 12a; eq. 6a at t = 0 as its limit).
  double K_star(double z, double t) const {
    const double zs = p_.alpha * z, Ls = p_.alpha * p_.L, ts = t_star(t);
    const double qA = p_.q_A / p_.K_s, qB = p_.q_B / p_.K_s, Kr = std::exp(p_.alpha * p_.h_r);
    double sum = 0;
    bool converged = ts == 0;  // at t = 0 every term is summed
    for (double l : lambda_) {
      const double decay = std::exp(-l * l * ts);
      sum += std::sin(l * zs) * std::sin(l * Ls) * decay / (1 + Ls / 2 + 2 * l * l * Ls);
      if (ts > 0 && decay < 1e-17) {
        converged = true;
        break;
      }
    }
    if (!converged) throw std::runtime_error("srivastava_yeh: more series terms needed at this time");
    return qB - (qB - Kr) * std::exp(-zs) - 4 * (qB - qA) * std::exp((Ls - zs) / 2 - ts / 4) * sum;
  }

  /// Pressure head h [m].
  double head(double z, double t) const { return std::log(K_star(z, t)) / p_.alpha; }

  /// Eq. 6a: the initial (steady, q_A) profile's K*.
  double K_star_initial(double z) const {
    const double qA = p_.q_A / p_.K_s;
    return qA - (qA - std::exp(p_.alpha * p_.h_r)) * std::exp(-p_.alpha * z);
  }

  /// Eq. 12b: the flux through the water table [m/s], downward positive.
  double base_flux(double t) const {
    const double Ls = p_.alpha * p_.L, ts = t_star(t);
    const double qA = p_.q_A / p_.K_s, qB = p_.q_B / p_.K_s;
    double sum = 0;
    for (double l : lambda_) {
      const double decay = std::exp(-l * l * ts);
      sum += l * std::sin(l * Ls) * decay / (1 + Ls / 2 + 2 * l * l * Ls);
      if (decay < 1e-17) break;
    }
    return p_.K_s * (qB - 4 * (qB - qA) * std::exp(Ls / 2 - ts / 4) * sum);
  }

  const std::vector<double>& eigenvalues() const { return lambda_; }

 private:
  Problem p_;
  std::vector<double> lambda_;
};

}  // namespace scree::richards1d::srivastava_yeh

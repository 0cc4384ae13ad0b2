// A parameter that varies in time, on either backend: the table a dictionary gives
// (params/function_table.hpp: a constant, a table, a CSV file), evaluated in the kernels at
// the step's time, which lives on the device (a chunk of steps runs without the host).
//
//   In a plugin's spec:     s.function("intensity", "m/s", "rain intensity").non_negative();
//   At construction:        intensity_ = FunctionOfTime(r.function("intensity", 1, ctx.case_dir));
//   In the launch:          Kernel{intensity_.on(ex), ...}
//   In the kernel:          const Real I = k.intensity(t);
//
// boundary/rainfall (a hyetograph) and boundary/shakingTable (an acceleration record,
// integrated exactly into the table's velocity) are the examples to copy.
#pragma once

#include <cmath>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/exec/memory.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/params/function_table.hpp"

namespace scree {

/// A function of time as the kernels read it: n rows (t_i, v_i) of C components and the
/// running integral A_i = int_{t_0}^{t_i} v dt, on the backend that runs the kernels.
struct TimeTable {
  const Real* t = nullptr;     ///< n times [s], strictly increasing
  const Real* v = nullptr;     ///< n x C values
  const Real* area = nullptr;  ///< n x C running integrals from t_0
  int n = 0;
  int components = 1;
  int step = 0;  ///< 1: the last row at or before t (no interpolation)
  int out = 0;   ///< 0 clamp, 1 zero, 2 repeat (FunctionTable::OutOfBounds)

  /// Component c at time `time`.
  SCREE_HD Real operator()(Real time, int c = 0) const {
    if (n == 1) return v[c];
    int lo = 0;
    Real tau = 0;
    if (!locate(time, lo, tau)) return out == 1 ? Real(0) : v[lo * components + c];
    if (step || lo == n - 1) return v[lo * components + c];
    const Real w = tau / (t[lo + 1] - t[lo]);
    return v[lo * components + c] + w * (v[(lo + 1) * components + c] - v[lo * components + c]);
  }

  /// int_{t_0}^{time} of component c, exact for the table's interpolation (a constant:
  /// from time 0). Before t_0 it is the clamped value times (time - t_0), or zero; after the
  /// last row the integral goes on at the clamped value, or stops (zero); `repeat` adds
  /// the integral of every whole period.
  SCREE_HD Real integral(Real time, int c = 0) const {
    if (n == 1) return v[c] * time;
    const Real period = t[n - 1] - t[0];
    const Real whole = area[(n - 1) * components + c];
    Real cycles = 0;
    if (out == 2) {
      cycles = floor((time - t[0]) / period);
      time -= cycles * period;
    }
    if (time < t[0]) return out == 1 ? Real(0) : v[c] * (time - t[0]);
    if (time >= t[n - 1]) return cycles * whole + whole + (out == 0 ? v[(n - 1) * components + c] * (time - t[n - 1]) : Real(0));
    int lo = 0;
    Real tau = 0;
    locate(time, lo, tau);
    const Real a = v[lo * components + c];
    Real s = area[lo * components + c] + a * tau;
    if (!step) s += Real(0.5) * (v[(lo + 1) * components + c] - a) / (t[lo + 1] - t[lo]) * tau * tau;
    return cycles * whole + s;
  }

 private:
  /// The row lo with t_lo <= time < t_{lo+1} (lo = n - 1 at the last row) and tau = time -
  /// t_lo; false outside [t_0, t_{n-1}] (then lo is the clamped row), after `repeat` folds
  /// the time into the table's span.
  SCREE_HD bool locate(Real& time, int& lo, Real& tau) const {
    if (out == 2) {
      const Real period = t[n - 1] - t[0];
      time = t[0] + fmod(time - t[0], period);
      if (time < t[0]) time += period;
    }
    if (time < t[0]) {
      lo = 0;
      return false;
    }
    if (time > t[n - 1]) {
      lo = n - 1;
      return false;
    }
    int hi = n - 1;
    lo = 0;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      if (t[mid] <= time)
        lo = mid;
      else
        hi = mid;
    }
    if (time >= t[hi]) lo = hi;
    tau = time - t[lo];
    return true;
  }
};

/// The owner of a function of time: the table on the host, copied once to the backend of
/// the first launch that asks for it (before any capture of the step in a graph).
class FunctionOfTime {
 public:
  FunctionOfTime() : FunctionOfTime(constant(0)) {}
  explicit FunctionOfTime(const FunctionTable& f) : source_(f.source) {
    const std::size_t n = f.times.size(), C = static_cast<std::size_t>(f.components);
    host_.resize(n * (1 + 2 * C));
    for (std::size_t i = 0; i < n; ++i) host_[i] = static_cast<Real>(f.times[i]);
    for (std::size_t i = 0; i < n * C; ++i) host_[n + i] = static_cast<Real>(f.values[i]);
    view_.n = static_cast<int>(n);
    view_.components = f.components;
    view_.step = f.interpolation == FunctionTable::Interpolation::step ? 1 : 0;
    view_.out = f.out_of_bounds == FunctionTable::OutOfBounds::zero     ? 1
                : f.out_of_bounds == FunctionTable::OutOfBounds::repeat ? 2
                                                                        : 0;
    // The running integral, row by row, of the interpolation the table is read with.
    Real* area = host_.data() + n + n * C;
    for (std::size_t c = 0; c < C; ++c) area[c] = 0;
    for (std::size_t i = 1; i < n; ++i)
      for (std::size_t c = 0; c < C; ++c) {
        const Real dt = host_[i] - host_[i - 1], a = host_[n + (i - 1) * C + c], b = host_[n + i * C + c];
        area[i * C + c] = area[(i - 1) * C + c] + (view_.step ? a * dt : Real(0.5) * (a + b) * dt);
      }
  }
  static FunctionTable constant(double value) {
    FunctionTable f;
    f.times = {0};
    f.values = {value};
    f.source = "a constant";
    return f;
  }

  bool is_constant() const { return view_.n == 1; }
  int components() const { return view_.components; }
  const std::string& source() const { return source_; }
  /// The view on the host (setup, checks and logs evaluate with the kernels' arithmetic).
  TimeTable host() const { return with(host_.data()); }
  Real operator()(Real t, int c = 0) const { return host()(t, c); }
  Real integral(Real t, int c = 0) const { return host().integral(t, c); }
  /// The first and last time of the table.
  Real first_time() const { return host_[0]; }
  Real last_time() const { return host_[static_cast<std::size_t>(view_.n) - 1]; }

  /// The view on `ex`'s backend.
  TimeTable on(const Exec& ex) const {
    if (backend_.size() != host_.size()) {
      backend_.resize(host_.size(), ex.device);
      backend_.copy_from_host(host_);
    }
    return with(backend_.data());
  }

 private:
  TimeTable with(const Real* base) const {
    TimeTable v = view_;
    const std::size_t n = static_cast<std::size_t>(view_.n), C = static_cast<std::size_t>(view_.components);
    v.t = base;
    v.v = base + n;
    v.area = base + n + n * C;
    return v;
  }

  std::vector<Real> host_;  // times, values, running integrals
  TimeTable view_;
  std::string source_;
  mutable Buffer<Real> backend_;
};

}  // namespace scree

// Hydraulic models of a two-phase body: the retention curve S_l(s) and the relative
// permeability k_rel(S_e), as plugins (kinds `retention` and `permeability`).
//
// A model is plain host C++ (a researcher writes the formula and its derivative); the core
// tabulates it once per body into a HydraulicTable that the kernels interpolate, so that a
// new model needs no kernel of its own and no recompilation of the materials.
//
// Conventions: pore-liquid pressure p_w is compression positive [Pa]; suction s = -p_w
// when p_w < 0 (the pore air is at atmospheric pressure, p_a = 0); S_l in [S_min, S_max];
// the effective saturation S_e = (S_l - S_min) / (S_max - S_min).
//
//   struct MyRetention : RetentionModel {
//     static constexpr const char* type_name = "myRetention";
//     static ParamSpec spec();
//     explicit MyRetention(const ParamReader& r);
//     double saturation(double s) const override;       // S_l(s)
//     double dsaturation(double s) const override;      // dS_l/ds (<= 0)
//   };
//   SCREE_PLUGIN(r) { r.add_retention<MyRetention>(); }
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "scree/core/config.hpp"
#include "scree/exec/memory.hpp"

namespace scree {

class SCREE_API RetentionModel {
 public:
  virtual ~RetentionModel();
  /// Degree of liquid saturation at suction s >= 0 [Pa].
  virtual double saturation(double suction) const = 0;
  /// dS_l/ds [1/Pa] (non-positive).
  virtual double dsaturation(double suction) const = 0;
  virtual double s_min() const = 0;  ///< residual saturation S_min
  virtual double s_max() const = 0;  ///< S_l at zero suction, S_max
  /// The suction scale of the curve [Pa] (the table spans 1e-4 to 1e6 of it).
  virtual double suction_scale() const = 0;
  /// The curve's parameter of that name, as its dictionary spells it (vanGenuchten's
  /// "lambda"), or NaN where it has none: a permeability model may take its shape from the
  /// curve it is given (PermeabilityModel::relative, incompatible).
  virtual double parameter(std::string_view name) const {
    (void)name;
    return std::numeric_limits<double>::quiet_NaN();
  }
};

class SCREE_API PermeabilityModel {
 public:
  virtual ~PermeabilityModel();
  /// Relative permeability at effective saturation Se in [0, 1], given the retention
  /// curve (a model may take its shape from it).
  virtual double relative(double se, const RetentionModel& retention) const = 0;
  /// Empty if the model works with this retention curve, else what is missing (reported
  /// at the permeability's entry before anything runs).
  virtual std::string incompatible(const RetentionModel& retention) const {
    (void)retention;
    return {};
  }
};

/// The retention and permeability curves tabulated for the kernels (device pointers).
/// Saturation and its derivative on a grid uniform in u = ln(1 + s / s_ref), kSuction
/// entries from s = 0 to s = 1e6 s_ref; k_rel on a grid uniform in S_e. Linear
/// interpolation: with 2048 entries, the relative error of S_l of a van Genuchten curve
/// is below 1e-5 (measured in the unit test), far inside the model's own accuracy.
struct HydraulicTable {
  static constexpr int kSuction = 2048;
  static constexpr int kPermeability = 2048;
  const Real* sat = nullptr;   ///< S_l(s_i)
  const Real* dsat = nullptr;  ///< dS_l/ds (s_i) [1/Pa]
  const Real* krel = nullptr;  ///< k_rel(Se_j)
  Real s_ref = 1;              ///< suction scale [Pa]
  Real du = 1;                 ///< spacing in u
  Real s_min = 0, s_max = 1;   ///< residual and maximum saturation
  int saturated = 0;           ///< S_l = S_max and k_rel = 1 for any suction (no table)

  /// Position in the suction table of pore pressure p (compression positive).
  SCREE_INLINE void locate(Real p, int& i, Real& f) const {
    const Real s = p < 0 ? -p : Real(0);
    const Real u = log1p(s / s_ref) / du;
    if (!(u < Real(kSuction - 1))) {
      i = kSuction - 2;
      f = 1;
      return;
    }
    i = static_cast<int>(u);
    f = u - i;
  }
  /// S_l at pore pressure p [Pa].
  SCREE_INLINE Real saturation(Real p) const {
    if (saturated || p >= 0) return s_max;
    int i;
    Real f;
    locate(p, i, f);
    return sat[i] + f * (sat[i + 1] - sat[i]);
  }
  /// dS_l/dp = -dS_l/ds [1/Pa] (non-negative): the retention curve's storage term.
  SCREE_INLINE Real dsaturation_dp(Real p) const {
    if (saturated || p >= 0) return 0;
    int i;
    Real f;
    locate(p, i, f);
    return -(dsat[i] + f * (dsat[i + 1] - dsat[i]));
  }
  /// k_rel at saturation S.
  SCREE_INLINE Real relative_permeability(Real S) const {
    if (saturated) return 1;
    Real se = (S - s_min) / (s_max - s_min);
    se = se < 0 ? Real(0) : (se > 1 ? Real(1) : se);
    const Real u = se * (kPermeability - 1);
    int j = static_cast<int>(u);
    if (j >= kPermeability - 1) return krel[kPermeability - 1];
    const Real f = u - j;
    return krel[j] + f * (krel[j + 1] - krel[j]);
  }
};

/// The table's storage (host side builds it, the backend keeps it).
class SCREE_API HydraulicTableStorage {
 public:
  /// Tabulate `ret` and `perm` (null: saturated, S_l = 1, k_rel = 1) on `device`.
  HydraulicTableStorage(const RetentionModel* ret, const PermeabilityModel* perm, Device device);
  const HydraulicTable& table() const { return table_; }

 private:
  Buffer<Real> data_;
  HydraulicTable table_;
};

}  // namespace scree

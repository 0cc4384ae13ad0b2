// waterBalance: the pore liquid's mass balance of two-phase bodies (porous/two_phase.hpp).
//
//   functions { water { type waterBalance; executeControl timeStep; executeInterval 100; } }
//
// Per execution, over the selected two-phase bodies:
//   W      = sum over points of rho_l (1 + p_w / K_l) n S_l V   (stored liquid mass)
//            rho_l, K_l: the body's scalars liquidDensity, liquidBulkModulus; p_w, n, S_l,
//            V: the point fields porePressure, porosity, saturation, volume
//   dW     = W - W(first row)
//   I_s, I_p = sum of the bodies' scalars liquidInflowSurface, liquidInflowPrescribed
//            (cumulative since t = 0)
//   error  = dW - (I_s - I_s(first row)) - (I_p - I_p(first row))
//   relative error = error / max(|dW|, |I_s + I_p - inflow(first row)|, tiny),
//            tiny = 1e-12 |W| (or the smallest normal number when W = 0)
//   rain, rainNotTaken = the scalars liquidRainOffered, liquidRainNotTaken (cumulative since
//            t = 0): the rain that fell onto the surface under rainfall conditions, and of it
//            what the surface did not take (ponded or run off; boundary/rainfall). The rain
//            taken, rain - rainNotTaken, is part of I_s.
//   ponded = sum over points of the field pond: the water standing on the surface now
//            (rainfall's pondingDepth), outside the soil and so not in W
//   runOff = the scalar liquidRunOff (cumulative): the water that left the surface; the
//            surface's own balance is rainNotTaken = ponded + runOff.
// Masses per metre of thickness in 2D (kg/m), kg in 3D. A restart takes the first row of
// the kept file as the reference.
//
// Bodies: default every body of the snapshot that is two-phase (has the scalar
// liquidDensity); an error when there is none, or when a body named in `bodies` is not
// two-phase.
//
// Output: postProcessing/<name>/waterBalance.csv, one row per execution, flushed at once.
#pragma once

#include <cstdint>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class WaterBalance final : public FunctionObject {
 public:
  static constexpr const char* type_name = "waterBalance";
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  WaterBalance(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  struct Totals {
    double stored = 0;             ///< W [kg/m]
    double inflow_surface = 0;     ///< I_s [kg/m]
    double inflow_prescribed = 0;  ///< I_p [kg/m]
    double rain = 0, rain_not_taken = 0;  ///< [kg/m]
    double ponded = 0, run_off = 0;       ///< [kg/m]
  };
  /// W and the inflows of `s` (std::runtime_error naming the entry for a body that is
  /// not two-phase); W over every rank's points (collective).
  Totals evaluate(const Snapshot& s) const;

 private:
  std::string who_;
  std::vector<std::string> bodies_;
  Ranks ranks_;
  CsvFile csv_;
  bool have_reference_ = false;
  Totals reference_;
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
};

}  // namespace scree::fo

// runOut: front and deposit tracker for granular flows (column collapse, dam break).
//
//   functions { front { type runOut; origin (0 0); direction (1 0); frontQuantile 1; } }
//
// Over the selected bodies (default all), at every execution:
//   runout    furthest particle centre along `direction`, measured from `origin`:
//             max_p (x_p - origin).direction, or the frontQuantile quantile of these
//             distances (0.999: the particle beyond which only 0.1 % of the particles lie,
//             which ignores a few particles that have separated from the mass)
//   height    highest particle centre along `up` (default: against gravity) measured
//             from `origin`, optionally only over particles whose distance along
//             `direction` lies in `heightWindow (a b)` (e.g. the deposit height at the
//             wall); heightQuantile as for the front
//   kinetic_energy  sum 1/2 m |v|^2 (J per metre of thickness in 2D)
//   max_speed, the mass-weighted mean velocity (= centre-of-mass velocity), total mass
// Positions are particle centres: the material edge lies up to half a particle spacing
// beyond. Column collapse: with the column against the left wall at x = 0, origin (0 0)
// gives d_inf (the front measured from the wall) and H_inf directly.
//
// Output: <case>/postProcessing/<name>/runOut.csv, one row per execution.
#pragma once

#include <cstdint>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class RunOut final : public FunctionObject {
 public:
  static constexpr const char* type_name = "runOut";
  static ParamSpec spec();
  RunOut(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  /// The values of one row (exposed for tests).
  struct Result {
    double runout = 0, height = 0, kinetic_energy = 0, max_speed = 0, mass = 0;
    Vec3 mean_velocity{0, 0, 0};
    std::int64_t particles = 0;
  };
  Result evaluate(const Snapshot& s) const;

 private:
  std::string who_;
  int dimension_;
  std::vector<std::string> bodies_;
  Vec3 origin_, direction_, up_;
  double front_quantile_, height_quantile_;
  bool window_ = false;
  double window_lo_ = 0, window_hi_ = 0;
  CsvFile csv_;
  std::int64_t last_step_ = -1;
};

}  // namespace scree::fo

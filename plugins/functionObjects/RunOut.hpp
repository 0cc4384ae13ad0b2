// runOut: front and deposit tracker for granular flows (column collapse, dam break), in
// 2D and 3D.
//
//   functions { front { type runOut; origin (0 0); direction (1 0); frontQuantile 1; } }
//   functions { front { type runOut; radial { centre (0.5 0 0.5); axis (0 1 0);
//                                            directions ((1 0 0) (0 0 1)); } } }
//
// Over the selected bodies (default all), at every execution:
//   runout    along a direction (the default mode): the furthest particle centre along
//             `direction` (normalised; default +x), measured from `origin` (default the
//             coordinate origin): max_p (x_p - origin).direction, or the frontQuantile
//             quantile of these distances (0.999: the particle beyond which only 0.1 % of
//             the particles lie, which ignores a few particles that have separated from
//             the mass). In 3D the direction may be any vector, e.g. a diagonal (1 1 0).
//             Radial mode (`radial { centre; axis; }`, an axisymmetric collapse): the
//             distance of the particle centres from the axis through `centre` along
//             `axis` (default: against gravity), the same quantile of it. With
//             `directions (d1 d2 ...)` also one front per direction: over the particles
//             whose offset from the axis lies within `sectorHalfAngle` (degrees, default
//             15) of d_i (projected on the plane normal to the axis), the quantile of the
//             offsets' component along d_i; extra columns runout_+x [m], ... (nan for an
//             empty sector).
//   height    highest particle centre along `up` (default: against gravity) measured
//             from `origin`, optionally only over particles whose distance along
//             `direction` lies in `heightWindow (a b)` (e.g. the deposit height at the
//             wall); heightQuantile as for the front. Radial mode: along `axis` from
//             `centre`, the window on the distance from the axis.
//   kinetic_energy  sum 1/2 m |v|^2 (J per metre of thickness in 2D, J in 3D)
//   max_speed, the mass-weighted mean velocity (= centre-of-mass velocity), total mass
// The quantiles count particles (every mode the same): q-quantile = the k-th smallest
// with k = ceil(q n).
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
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  RunOut(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  /// The values of one row (exposed for tests), over every rank's points (collective).
  struct Result {
    double runout = 0, height = 0, kinetic_energy = 0, max_speed = 0, mass = 0;
    Vec3 mean_velocity{0, 0, 0};
    std::int64_t particles = 0;
    std::vector<double> sector_runout;  ///< radial mode: one front per direction
  };
  Result evaluate(const Snapshot& s) const;

 private:
  std::string who_;
  int dimension_;
  std::vector<std::string> bodies_;
  Vec3 origin_, direction_, up_;
  double front_quantile_, height_quantile_;
  Ranks ranks_;
  bool window_ = false;
  // Radial mode: distances from the axis through centre_ along axis_ (a unit vector);
  // sector fronts along sector_dirs_ (unit vectors normal to the axis), cos of the
  // half-angle in sector_cos_.
  bool radial_ = false;
  Vec3 centre_{0, 0, 0}, axis_{0, 0, 0};
  std::vector<Vec3> sector_dirs_;
  double sector_cos_ = 1;
  double window_lo_ = 0, window_hi_ = 0;
  CsvFile csv_;
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
};

}  // namespace scree::fo

// surfaceProfile: the free surface of the selected bodies at each execution: a profile
// along a line (2D, or a section in 3D) or a height field over the horizontal plane (3D).
//
//   functions { profile { type surfaceProfile; binWidth 0.005; executeControl runTime;
//                         executeInterval 0.1; } }
//
// Heights are particle centres measured along `up` (default: against gravity; +y in 2D,
// +z in 3D without gravity) from `origin` (default: the coordinate origin).
//
// Profile (2D; 3D with `direction`): the distance along `direction` (default +x) from
// origin is cut into bins of width binWidth (default: the grid cell size), anchored at
// origin (bin k holds distances in [k w, (k+1) w)); the height of a bin is the highest
// particle centre in it. Bins run from the first to the last bin holding a particle, or
// over the fixed `range (a b)`; an empty bin has height nan. In 3D this is a section:
// with `width`, only particles at most width/2 from the vertical plane through origin
// that holds `direction` count (default: all, i.e. the envelope seen from the side).
// Column collapse: the deposit profile h(x) for a figure such as Lube et al.'s.
// Output columns: distance [m] (bin centre), height [m], particles [-].
//
// Height field (3D without `direction`): the horizontal plane is the plane normal to
// `up`; its axes are the two grid axes other than the one closest to `up` (x and y when
// up is +z, x and z when up is +y), projected on that plane. Square bins of binWidth
// anchored at origin; the bins cover the rectangle from the first to the last occupied
// bin on each axis, or the fixed `range (a1 b1 a2 b2)` (coordinates along the two axes);
// an empty bin has height nan and 0 particles. Output columns: the two axes' coordinates
// of the bin centre (e.g. x [m], y [m]: positions, origin included), height [m],
// particles [-]; rows with the first axis varying fastest.
//
// Output: postProcessing/<name>/<time>.csv per execution (time with 8 significant
// digits, e.g. 0.25.csv). Each file is written atomically. A run from t = 0 first removes
// the time files of an earlier run in that folder.
#pragma once

#include <cstdint>
#include <filesystem>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class SurfaceProfile final : public FunctionObject {
 public:
  static constexpr const char* type_name = "surfaceProfile";
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  SurfaceProfile(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  struct Bin {
    double centre = 0, height = 0;
    std::int64_t particles = 0;
  };
  /// The profile (2D, or a 3D section), over every rank's points (collective).
  std::vector<Bin> evaluate(const Snapshot& s) const;

  /// One bin of the height field (3D without direction): centre coordinates along the two
  /// horizontal axes.
  struct Cell {
    double a = 0, b = 0, height = 0;
    std::int64_t particles = 0;
  };
  std::vector<Cell> evaluate_field(const Snapshot& s) const;  ///< over every rank's points (collective)
  bool height_field() const { return field_; }

 private:
  /// Each bin's height and count over the ranks (one rank: as they are).
  template <class B>
  void combine(std::vector<B>& bins) const;

  std::string who_;
  std::filesystem::path dir_;
  std::vector<std::string> bodies_;
  Ranks ranks_;
  Vec3 origin_, direction_, up_;
  double width_;
  bool fixed_range_ = false;
  double lo_ = 0, hi_ = 0;
  // 3D section: the lateral direction (normal to direction and up) and the band's half-width.
  bool band_ = false;
  Vec3 lateral_{0, 0, 0};
  double half_band_ = 0;
  // 3D height field: the horizontal axes, their names, the fixed range on each.
  bool field_ = false;
  Vec3 axis_a_{0, 0, 0}, axis_b_{0, 0, 0};
  std::string name_a_, name_b_;
  double lo_b_ = 0, hi_b_ = 0;
  double start_time_ = 0;
  bool prepared_ = false;  ///< the directory made (first execution)
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
};

}  // namespace scree::fo

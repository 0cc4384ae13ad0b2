// surfaceProfile: the free-surface profile of the selected bodies at each execution.
//
//   functions { profile { type surfaceProfile; binWidth 0.005; executeControl runTime;
//                         executeInterval 0.1; } }
//
// Positions are measured from `origin`: the distance along `direction` (default +x) is
// cut into bins of width binWidth (default: the grid cell size), anchored at origin
// (bin k holds distances in [k w, (k+1) w)); the height of a bin is the highest particle
// centre in it along `up` (default: against gravity). Bins run from the first to the last
// bin holding a particle, or over the fixed `range (a b)`; an empty bin has height nan.
// Column collapse: the deposit profile h(x) for a figure such as Lube et al.'s.
//
// Output: postProcessing/<name>/<time>.csv per execution (time with 8 significant
// digits, e.g. 0.25.csv), columns distance [m] (bin centre), height [m], particles [-].
// Each file is written atomically. A run from t = 0 first removes the time files of an
// earlier run in that folder.
#pragma once

#include <cstdint>
#include <filesystem>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class SurfaceProfile final : public FunctionObject {
 public:
  static constexpr const char* type_name = "surfaceProfile";
  static ParamSpec spec();
  SurfaceProfile(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  struct Bin {
    double centre = 0, height = 0;
    std::int64_t particles = 0;
  };
  std::vector<Bin> evaluate(const Snapshot& s) const;

 private:
  std::string who_;
  std::filesystem::path dir_;
  std::vector<std::string> bodies_;
  Vec3 origin_, direction_, up_;
  double width_;
  bool fixed_range_ = false;
  double lo_ = 0, hi_ = 0;
  std::int64_t last_step_ = -1;
};

}  // namespace scree::fo

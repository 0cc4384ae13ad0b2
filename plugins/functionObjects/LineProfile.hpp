// lineProfile: profiles of particle fields along a line segment, one file per execution.
//
//   functions { pw { type lineProfile; start (0.5 0); end (0.5 1); width 0.02; binWidth 0.01;
//                    fields (porePressure saturation suction); executeControl runTime;
//                    executeInterval 60; } }
//
// The segment from `start` to `end` (length L) is cut into bins along it: `bins N` of
// width L/N, or bins of width `binWidth` anchored at start (bin k holds distances along
// the line in [k w, (k+1) w); the last bin ends at L and may be shorter), default
// binWidth: the grid cell size. A point (particle centre) belongs to the band when its
// distance along the line is in [0, L] and its distance from the line is at most
// width/2 (`width`: the band's full width, default the grid cell size). The value of a
// field in a bin is the arithmetic mean over the band's points in that bin (nan for an
// empty bin; over the points of the bodies that have the field when several bodies are
// selected).
//
// Output: postProcessing/<name>/<time>.csv per execution (time with 8 significant
// digits), columns distance [m] (bin centre along the line), x y [z] [m] (the bin
// centre's position), points [-], then each field's mean with its unit, vectors and
// tensors expanded per component (as particleProbes). Written atomically; a run from
// t = 0 first removes the <number>.csv files of an earlier run in that folder. With
// `longFormat true`, also postProcessing/<name>/lineProfile.csv: every profile in one
// file, one row per (time, bin), `time [s]` first, rows flushed per execution (the
// common CSV rules: a restart keeps the rows before its start time).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class LineProfile final : public FunctionObject {
 public:
  static constexpr const char* type_name = "lineProfile";
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  LineProfile(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  struct Column {
    std::string field;
    int component = 0;
    std::string header;  ///< "porePressure [Pa]", "liquidVelocity_x [m/s]"
  };
  struct Profile {
    std::vector<double> distance;              ///< bin centres along the line [m]
    std::vector<Vec3> position;                ///< bin centres [m]
    std::vector<std::int64_t> points;          ///< band points per bin
    std::vector<std::vector<double>> mean;     ///< [column][bin]
  };
  /// The columns (decided at the first execution from the snapshot's bodies) and the
  /// profile of `s` over every rank's points (collective). Throws std::runtime_error for
  /// an unknown field.
  Profile evaluate(const Snapshot& s);
  const std::vector<Column>& columns() const { return columns_; }
  std::size_t bin_count() const { return edges_.size() - 1; }

 private:
  void decide_columns(const Snapshot& s);
  std::vector<std::string> header(bool with_time) const;

  std::string who_;
  std::filesystem::path dir_;
  int dimension_;
  double start_time_;
  std::vector<std::string> bodies_;
  Ranks ranks_;
  Vec3 start_, end_, direction_{1, 0, 0};
  double length_ = 0, half_width_ = 0;
  std::vector<double> edges_;  ///< bin edges along the line, edges_[0] = 0, back() = length
  bool all_fields_ = true;
  std::vector<std::string> fields_;
  bool columns_decided_ = false;
  std::vector<Column> columns_;
  bool long_format_ = false;
  CsvFile long_csv_;
  bool prepared_ = false;  ///< the directory made (first execution)
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
};

}  // namespace scree::fo

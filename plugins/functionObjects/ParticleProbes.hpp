// particleProbes: the history of chosen particles (Lagrangian probes).
//
//   functions {
//     probes { type particleProbes; points ((0.05 0.09) (0.1 0.05)); names (top middle);
//              fields (pressure granularTemperature collisionalFraction); }
//   }
//
// At the first execution (normally t = 0) each probe picks the particle of the selected
// bodies whose position *at that time* is nearest its point (ties: the smallest particle id),
// and from then on follows that particle by its id (ids are stable; the particle's
// index in the arrays may change when the solver reorders particles). The choice is
// written to postProcessing/<name>/selection.csv (probe, point, particle id, body,
// position, distance) and reused when a run restarts from a later time.
//
// Output: postProcessing/<name>/<probe>.csv per probe: time, the particle's position
// (x y [z]) and the requested fields (default: every field of the particle's body),
// expanded per component: vectors name_x name_y [name_z], symmetric tensors name_xx
// name_yy name_zz name_xy [name_yz name_zx] (in 2D the out-of-plane shear components,
// always zero, are left out; zz is kept: plane strain).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class ParticleProbes final : public FunctionObject {
 public:
  static constexpr const char* type_name = "particleProbes";
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  ParticleProbes(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  /// The particle id each probe follows (-1 before the first execution).
  std::vector<std::int64_t> tracked_ids() const;

 private:
  struct Column {
    std::string field;
    int component;
  };
  struct Probe {
    std::string name;
    Vec3 point{0, 0, 0};
    std::int64_t id = -1;
    std::vector<Column> columns;  // decided at the probe's first row
    CsvFile csv;
    bool missing_reported = false;
  };
  /// Each probe's particle: the nearest over every rank's points (collective).
  void pick(const Snapshot& s);
  /// The probes' particles gathered from every rank, as a snapshot on the root (collective).
  Snapshot followed(const Snapshot& s) const;
  void write_rows(const Snapshot& s);
  bool load_selection();
  void save_selection(const Snapshot& s) const;
  void open_probe(Probe& p, const BodySnapshot& b);

  std::string who_;
  std::filesystem::path dir_;
  int dimension_;
  double start_time_;
  std::vector<std::string> bodies_;
  Ranks ranks_;
  bool all_fields_ = true;
  std::vector<std::string> fields_;
  std::vector<Probe> probes_;
  bool picked_ = false;
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
};

}  // namespace scree::fo

// energies: kinetic, gravitational potential and their sum over the selected bodies.
//
//   functions { energy { type energies; executeControl timeStep; executeInterval 100; } }
//
//   kinetic    sum 1/2 m |v|^2
//   potential  sum -m g.(x - origin)  (g from constant/g; zero at `origin`)
//   total      kinetic + potential
// Energies are per metre of thickness in 2D (J/m), in J in 3D. The elastic energy
// stored in the material and the work of boundary conditions are not included: the drop
// of `total` over a run is the energy dissipated (friction, damping, numerical) minus the
// elastic energy stored.
//
// Output: postProcessing/<name>/energies.csv, one row per execution.
#pragma once

#include <cstdint>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class Energies final : public FunctionObject {
 public:
  static constexpr const char* type_name = "energies";
  static ParamSpec spec();
  Energies(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;

  struct Result {
    double kinetic = 0, potential = 0;
    double total() const { return kinetic + potential; }
  };
  Result evaluate(const Snapshot& s) const;

 private:
  std::string who_;
  std::vector<std::string> bodies_;
  Vec3 origin_, gravity_{0, 0, 0};
  CsvFile csv_;
  std::int64_t last_step_ = -1;
};

}  // namespace scree::fo

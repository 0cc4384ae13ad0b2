// energies: kinetic and gravitational potential energy of the selected bodies and, with
// `budget yes`, the whole energy budget of the run (Feng et al. 2025, Appendix B).
//
//   functions { energy { type energies; executeControl runTime; executeInterval 0.01; budget yes; } }
//
//   kinetic    sum 1/2 m |v|^2
//   potential  sum -m g.(x - origin)  (g from constant/g; zero at `origin`)
//   total      kinetic + potential
//
// With `budget yes` the kernels keep an energy ledger (StepControl::energy, cumulative since
// t = 0 over every body) and the rows add, in the same unit:
//
//   elastic       sum V w_e, the elastic energy stored (the material's output field
//                 elasticEnergy [J/m^3]; 0 for a material without one)
//   granular      sum 3/2 m T, the energy of the granular temperature (eq. 27; the field
//                 granularTemperature, 0 without one)
//   stressWork    W = sum over steps and points of V (sigma^n + sigma^{n+1})/2 : deps (the
//                 trapezoidal rule, exact for a linear elastic increment): the work done on
//                 the material
//   collisional   D_col = sum V Gamma dt, the collisional dissipation (eq. 28; the material's
//                 collisional_dissipation)
//   plastic       D_p = W - (elastic - elastic_0) - (granular - granular_0) - D_col: the stress
//                 work that is neither stored nor dissipated by collisions, i.e. the frictional
//                 (plastic) dissipation. Derived, not measured: it carries the error of the
//                 elastic estimate (hypoelastic laws have no exact stored energy)
//   picLoss       kinetic energy the FLIP/PIC blend took from the points (mpmSchemes picRate /
//                 picFraction)
//   dampingLoss   work of the local damping force on the nodes (impulse times the step's mean
//                 nodal velocity)
//   wallLoss      kinetic energy the walls (fixed, slip, friction, ...) took from the points:
//                 each point's new velocity against the one the nodes would have given it
//                 without their walls (USF, USL); with MUSL, on the nodes (the kinetic energy a
//                 wall removes from v^k, the work of its reaction at the integration)
//   residual      (kinetic + potential + W + picLoss + dampingLoss + wallLoss) minus its value at
//                 the first row: energy the discretisation created (> 0) or lost (< 0) beyond
//                 the named terms (the grid-particle transfers, the explicit integration)
//   residualFraction   residual / |potential at the first row| (origin as given)
//
// The balance: kinetic + potential + elastic + granular + plastic + collisional + picLoss +
// dampingLoss + wallLoss = its value at the first row + residual. What is not counted: work
// of boundary plugins with node laws of their own (shakingTable, ...), the pore liquid of
// two-phase bodies (its drag and flow) -- these go into the residual.
//
// Energies are per metre of thickness in 2D (J/m), in J in 3D. A restart continues the
// ledger from the checkpoint and takes the first row's values from the rows it keeps.
//
// Output: postProcessing/<name>/energies.csv, one row per execution.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "FoCommon.hpp"
#include "scree/output/function_object.hpp"

namespace scree::fo {

class Energies final : public FunctionObject {
 public:
  static constexpr const char* type_name = "energies";
  static constexpr bool reduces_over_ranks = true;
  static ParamSpec spec();
  Energies(const ParamReader& r, const SolverContext& ctx);
  void execute(const Snapshot& s) override;
  bool needs_energy_ledger() const override { return budget_; }

  struct Result {
    double kinetic = 0, potential = 0;
    double elastic = 0, granular = 0;  ///< stored in the material (budget only)
    double total() const { return kinetic + potential; }
  };
  /// Over every rank's points (collective).
  Result evaluate(const Snapshot& s) const;

  /// The budget's columns of a snapshot's row (budget yes), in the header's order after
  /// total: against the first row `first` (Result and balance).
  static std::vector<double> budget(const Result& r, const EnergyLedger& e, const Result& first,
                                    double first_balance);

 private:
  std::string who_;
  std::vector<std::string> bodies_;
  Vec3 origin_, gravity_{0, 0, 0};
  bool budget_ = false;
  Ranks ranks_;
  CsvFile csv_;
  std::int64_t last_step_ = -1;
  LostPoints lost_;  ///< points that left the grid: left out, counted in lostPoints.csv
  /// The first row's values (budget): from the first execution, or on a restart from the
  /// rows kept in the CSV file.
  std::optional<Result> first_;
  double first_balance_ = 0;
};

}  // namespace scree::fo

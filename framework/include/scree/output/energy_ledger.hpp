// The energy ledger: energies the kernels add up as they go (StepControl::energy, cumulative
// since t = 0 over every body and every rank), in J (J/m of thickness in 2D), for the energy
// budget of the function object `energies` (`budget yes`; plugins/functionObjects/Energies.hpp
// says how the budget closes; Feng et al. 2025, Appendix B).
//
// The terms are an open set, named here once: a new term is a row of EnergyTerm and
// kEnergyTermInfo and the kernel that books it (atomic_add into StepControl::energy[term]).
// The clock carries it, the checkpoint keeps it, a decomposed run sums it over the ranks, the
// snapshot hands it out and `energies` writes it as a column, all by iterating over the table.
#pragma once

#include "scree/core/config.hpp"

namespace scree {

enum EnergyTerm : int {
  kEnergyStressWork = 0,   ///< sum over steps and points of V (sigma^n + sigma^{n+1})/2 : deps (trapezoidal)
  kEnergyCollisional = 1,  ///< collisional dissipation, sum V Gamma dt (material hook collisional_dissipation)
  kEnergyPic = 2,          ///< kinetic energy the FLIP/PIC blend removed from the points (>= 0 when it damps)
  kEnergyDamping = 3,      ///< kinetic energy the local damping removed from the nodes
  kEnergyWalls = 4,        ///< kinetic energy the walls (wall_law.hpp) removed from the nodes
  kEnergyTerms = 5,
};

/// A term's column name in `energies` and its place in the balance: a sink is mechanical
/// energy taken from the points (kinetic + potential + every sink is conserved up to the
/// discretisation's residual); a term that is not a sink is a share of one (the collisional
/// dissipation is part of the stress work).
struct EnergyTermInfo {
  const char* name;
  bool sink;
};
inline constexpr EnergyTermInfo kEnergyTermInfo[kEnergyTerms] = {
    {"stressWork", true}, {"collisional", false}, {"picLoss", true}, {"dampingLoss", true}, {"wallLoss", true}};

/// The ledger at a snapshot's time. Kept only when a function object asks for it
/// (FunctionObject::needs_energy_ledger); `kept` says whether it was.
struct EnergyLedger {
  bool kept = false;
  Real term[kEnergyTerms] = {};

  Real operator[](EnergyTerm t) const { return term[t]; }
  /// kinetic + potential + every sink, added in the table's order.
  Real balance(Real kinetic, Real potential) const {
    Real b = kinetic + potential;
    for (int t = 0; t < kEnergyTerms; ++t)
      if (kEnergyTermInfo[t].sink) b += term[t];
    return b;
  }
};

}  // namespace scree

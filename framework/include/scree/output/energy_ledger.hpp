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

/// The ledger as the kernels keep it (StepControl::energy). Many warps add to each term in
/// every pass, and atomics on one address serialise: each term is kept as kEnergySlots
/// partial sums, each slot a cache line of its own, a warp adding to the slot of its index
/// (at); the term is the sum of its slots in slot order (total). A run on one CPU thread
/// adds to slot 0 alone, so its totals are its running sums as they were added.
inline constexpr int kEnergySlots = 16;
struct alignas(64) EnergySlot {
  Real term[8];
};
static_assert(kEnergyTerms <= 8, "an EnergySlot holds every term");
struct EnergySlots {
  EnergySlot slot[kEnergySlots];

  /// The terms of the slot of warp `warp` (exec/parallel.hpp: warp_index).
  SCREE_INLINE Real* at(unsigned warp) { return slot[warp % kEnergySlots].term; }
  Real total(int t) const {
    Real s = 0;
    for (int k = 0; k < kEnergySlots; ++k) s += slot[k].term[t];
    return s;
  }
  /// Term t as the single value v (in slot 0).
  void set(int t, Real v) {
    for (int k = 0; k < kEnergySlots; ++k) slot[k].term[t] = k == 0 ? v : Real(0);
  }
  void clear() {
    for (int t = 0; t < kEnergyTerms; ++t) set(t, 0);
  }
};

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

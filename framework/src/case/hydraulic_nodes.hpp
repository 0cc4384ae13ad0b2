// Where and when a condition on the pore liquid acts (porous/hydraulic_condition.hpp),
// for the run's warning of a condition that selects none (solver_setup.cpp) and the check
// of two that overlap (setup_check.cpp). Here, in case/, which sits above both boundary/
// (the lattice) and porous/ (the conditions) in the README's layering.
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree {

/// Where and when a condition acts: the nodes its open surfaces select and those inside its
/// pore-pressure boxes (flat indices, ascending), and the window [from, to) of its time
/// windows' union [s].
struct HydraulicReach {
  std::vector<Index> nodes;
  Real from = 0, to = 0;
};
HydraulicReach hydraulic_reach(const HydraulicCondition& hc, const NodeLattice& grid);

}  // namespace scree

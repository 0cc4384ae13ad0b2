// The grid nodes a condition on the pore liquid acts on (porous/hydraulic_condition.hpp),
// for the run's warning of a condition that selects none (solver_setup.cpp) and the check
// of two that overlap (setup_check.cpp). Here, in case/, which sits above both boundary/
// (the lattice) and porous/ (the conditions) in the README's layering.
#pragma once

#include <vector>

#include "scree/boundary/boundary_condition.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree {

/// The nodes its open surfaces select and those inside its pore-pressure boxes.
std::vector<Index> hydraulic_condition_nodes(const HydraulicCondition& hc, const NodeLattice& grid);

}  // namespace scree

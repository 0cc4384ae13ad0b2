// The registry's retention and permeability plugins as the porous formulation takes them
// (porous/hydraulic_model.hpp: HydraulicModelFactory), for the run and for --check alike.
#pragma once

#include "scree/plugin/registry.hpp"
#include "scree/porous/body_hydraulics.hpp"

namespace scree {

/// The factories of `reg`'s retention and permeability plugins, by the `type` of each
/// model's dictionary (an unknown type is an InputError there, listing the valid ones).
SCREE_API HydraulicModelFactory hydraulic_models(const Registry& reg);

}  // namespace scree

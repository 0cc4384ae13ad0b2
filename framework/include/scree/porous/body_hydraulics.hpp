// A two-phase body's hydraulic models read from its `twoPhase { ... }` block: one reader
// for the run (PorousMedia) and for --check (setup_check), so that the two cannot disagree.
#pragma once

#include <functional>
#include <memory>

#include "scree/core/config.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/porous/hydraulic_model.hpp"

namespace scree {

/// How a two-phase body's `retention { type ...; }` and `permeability { type ...; }` become
/// models: the plugin registry's factories (plugin/hydraulic_models.hpp), handed down (the
/// porous formulation sits below the plugins in the README's layering). Each takes the
/// model's dictionary and throws InputError for a type it does not know.
struct HydraulicModelFactory {
  std::function<std::unique_ptr<RetentionModel>(const Dictionary&)> retention;
  std::function<std::unique_ptr<PermeabilityModel>(const Dictionary&)> permeability;
};

/// A two-phase body's hydraulic models (either may be null: saturated).
struct BodyHydraulics {
  std::unique_ptr<RetentionModel> retention;
  std::unique_ptr<PermeabilityModel> permeability;
};

/// The models of a body's `twoPhase { ... }` block: throws InputError at the entry when a
/// relative permeability comes without a retention curve, or when the two do not fit
/// (PermeabilityModel::incompatible).
SCREE_API BodyHydraulics read_hydraulics(const Dictionary& two_phase, const HydraulicModelFactory& models);

}  // namespace scree

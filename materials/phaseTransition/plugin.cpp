// The phaseTransition material plugin (libphaseTransition.so).
#include "PhaseTransition.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<scree::materials::PhaseTransition>(); }

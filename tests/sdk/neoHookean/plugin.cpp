#include "NeoHookean.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<sdk_example::NeoHookean>(); }

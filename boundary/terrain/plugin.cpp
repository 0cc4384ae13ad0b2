// The terrain boundary-condition plugin (libterrain.so).
#include "Terrain.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::Terrain>(); }

// The simsand material plugin (libsimsand.so).
#include "Simsand.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<scree::materials::Simsand>(); }

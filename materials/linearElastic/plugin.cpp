// The linearElastic material plugin (liblinearElastic.so).
#include "LinearElastic.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<scree::materials::LinearElastic>(); }

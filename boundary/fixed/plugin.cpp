// The fixed boundary-condition plugin (libfixed.so).
#include "Fixed.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::Fixed>(); }

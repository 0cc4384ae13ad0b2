// The inclinedPlane boundary-condition plugin (libinclinedPlane.so).
#include "InclinedPlane.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::InclinedPlane>(); }

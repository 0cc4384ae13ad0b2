// The slip boundary-condition plugin (libslip.so).
#include "Slip.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::Slip>(); }

// The shakingTable boundary-condition plugin (libshakingTable.so).
#include "ShakingTable.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::ShakingTable>(); }

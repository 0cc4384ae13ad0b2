// The friction boundary-condition plugin (libfriction.so).
#include "Friction.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::Friction>(); }

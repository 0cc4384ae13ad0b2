// The rotatingWall boundary-condition plugin (librotatingWall.so).
#include "RotatingWall.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_boundary_condition<scree::boundary::RotatingWall>(); }

#include "SeepageFace.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(r) { r.add_boundary_condition<scree::boundary::SeepageFace>(); }

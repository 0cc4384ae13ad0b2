// The muI material plugin (libmuI.so): one line registers the material; add_material
// checks the material's contract at compile time and instantiates its particle kernels
// for both backends, in 2D and 3D.
#include "MuIRheology.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<mui_example::MuIRheology>(); }

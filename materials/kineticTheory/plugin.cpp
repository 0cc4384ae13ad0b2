// The kineticTheory material plugin (libkineticTheory.so).
#include "KineticTheory.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) { registry.add_material<scree::materials::KineticTheory>(); }

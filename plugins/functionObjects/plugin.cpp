// The function-object plugin (libfunctionObjects.so): run-time post-processing usable by
// any case. See README.md.
#include "Energies.hpp"
#include "LineProfile.hpp"
#include "ParticleProbes.hpp"
#include "RunOut.hpp"
#include "SurfaceProfile.hpp"
#include "WaterBalance.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(registry) {
  registry.add_function_object<scree::fo::RunOut>();
  registry.add_function_object<scree::fo::ParticleProbes>();
  registry.add_function_object<scree::fo::Energies>();
  registry.add_function_object<scree::fo::SurfaceProfile>();
  registry.add_function_object<scree::fo::LineProfile>();
  registry.add_function_object<scree::fo::WaterBalance>();
}

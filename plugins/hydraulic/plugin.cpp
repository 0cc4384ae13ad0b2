#include "HydraulicModels.hpp"
#include "scree/plugin/plugin_api.hpp"

SCREE_PLUGIN(r) {
  r.add_retention<scree::hydraulic::VanGenuchten>();
  r.add_permeability<scree::hydraulic::MualemVanGenuchten>();
  r.add_permeability<scree::hydraulic::PowerLaw>();
}

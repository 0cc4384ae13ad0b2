// Tabulation of the retention and permeability curves for the kernels (hydraulic_model.hpp),
// a body's models read from its twoPhase block (body_hydraulics.hpp), and the key
// functions of the porous formulation's plugin interfaces (their type
// information lives in the core, where the solver's dynamic_cast finds a plugin's
// HydraulicCondition: hydraulic_condition.hpp).
#include "scree/porous/hydraulic_model.hpp"

#include <cmath>
#include <vector>

#include "scree/porous/body_hydraulics.hpp"
#include "scree/porous/hydraulic_condition.hpp"

namespace scree {

RetentionModel::~RetentionModel() = default;
PermeabilityModel::~PermeabilityModel() = default;
HydraulicCondition::~HydraulicCondition() = default;

HydraulicTableStorage::HydraulicTableStorage(const RetentionModel* ret, const PermeabilityModel* perm, Device device) {
  HydraulicTable& t = table_;
  if (!ret) {
    t.saturated = 1;
    t.s_min = 0;
    t.s_max = 1;
    return;
  }
  constexpr int ns = HydraulicTable::kSuction, nk = HydraulicTable::kPermeability;
  std::vector<Real> host(static_cast<std::size_t>(2 * ns + nk));
  t.s_ref = ret->suction_scale();
  t.s_min = ret->s_min();
  t.s_max = ret->s_max();
  // u = ln(1 + s / s_ref) from 0 to ln(1 + 1e6): suctions up to a million times the scale.
  t.du = std::log1p(1e6) / (ns - 1);
  for (int i = 0; i < ns; ++i) {
    const double s = t.s_ref * std::expm1(i * t.du);
    host[i] = ret->saturation(s);
    host[ns + i] = ret->dsaturation(s);
  }
  for (int j = 0; j < nk; ++j) {
    const double se = static_cast<double>(j) / (nk - 1);
    host[2 * ns + j] = perm ? perm->relative(se, *ret) : 1.0;
  }
  data_.resize(host.size(), device);
  data_.copy_from_host(host);
  t.sat = data_.data();
  t.dsat = data_.data() + ns;
  t.krel = data_.data() + 2 * ns;
}

BodyHydraulics read_hydraulics(const Dictionary& tp, const HydraulicModelFactory& models) {
  BodyHydraulics h;
  if (tp.has("retention")) h.retention = models.retention(tp.at("retention").dict());
  if (tp.has("permeability")) h.permeability = models.permeability(tp.at("permeability").dict());
  if (h.permeability && !h.retention)
    throw InputError(tp.at("permeability").where(),
                     "permeability: a relative permeability needs a retention curve (retention { type ...; }); a "
                     "saturated body has k_rel = 1");
  if (h.permeability)
    if (const std::string why = h.permeability->incompatible(*h.retention); !why.empty())
      throw InputError(tp.at("permeability").where(), "permeability: " + why);
  return h;
}

}  // namespace scree

// A host copy of the particle (and optionally grid) data at one output time. Writers and
// function objects read snapshots only, never device memory, so they run on the host
// (on a writer thread) while the solver goes on.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scree/core/config.hpp"
#include "scree/output/energy_ledger.hpp"
#include "scree/output/field_info.hpp"

namespace scree {

/// One named field over the particles of a body: `components` values per particle,
/// interleaved (particle i's values at [i*components, (i+1)*components)).
/// Symmetric tensors have 6 components in Voigt order (xx yy zz xy yz zx).
struct FieldData {
  std::string name;
  int components = 1;
  std::string unit;
  std::string doc;
  std::vector<Real> values;
};

struct BodySnapshot {
  std::string name;       ///< the body's name in constant/bodies
  int body_id = 0;
  std::string material;   ///< the material's entry name in constant/materials
  std::string material_type;
  Index n = 0;
  std::vector<Real> position;      ///< 3 per particle (z = 0 in 2D) [m]
  std::vector<std::int64_t> id;    ///< particle ids (unique over the case, stable)
  std::vector<FieldData> fields;   ///< velocity, displacement, stress, ... and material fields
  /// 1 for a point that has left the grid (its stencil reached past the last node: it is
  /// frozen where it left, mpm/particle_pass.hpp), 0 otherwise; empty where the snapshot does
  /// not say (one made by hand). Function objects leave these points out of what they measure.
  std::vector<std::uint8_t> lost;
  bool is_lost(Index p) const { return !lost.empty() && lost[static_cast<std::size_t>(p)] != 0; }
  /// Per-body scalars at this time: constants a post-processor needs and cumulative
  /// quantities since t = 0. A two-phase body (porous/) gives liquidDensity [kg/m^3],
  /// liquidBulkModulus [Pa], liquidInflowSurface [kg] (the pore liquid's net mass that
  /// entered through the body's surfaces, rain and ponding included) and
  /// liquidInflowPrescribed [kg] (the net mass that prescribed pore pressures added);
  /// masses per metre of thickness in 2D.
  struct Scalar {
    std::string name, unit, doc;
    Real value = 0;
  };
  std::vector<Scalar> scalars;
  const Scalar* scalar(const std::string& nm) const {
    for (auto& s : scalars)
      if (s.name == nm) return &s;
    return nullptr;
  }
  const FieldData* find(const std::string& name) const {
    for (auto& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  }
};

struct GridSnapshot {
  int n[3] = {1, 1, 1};  ///< nodes per axis
  Real origin[3] = {0, 0, 0};
  Real h = 0;
  std::vector<FieldData> fields;  ///< mass, velocity, ... per node
};

struct Snapshot {
  Real time = 0;
  std::int64_t step = 0;
  int dimension = 2;
  EnergyLedger energy;
  std::vector<BodySnapshot> bodies;
  bool has_grid = false;
  GridSnapshot grid;
};

}  // namespace scree

// Must NOT compile: a material without density(). The CTest material_contract_message
// checks that the compiler says so in the words of check_material() (material.hpp).
#include "scree/material/material.hpp"

using namespace scree;

struct MissingDensity {
  static constexpr const char* type_name = "missingDensity";
  struct Params {
    Real K;
  };
  struct State {};
  static ParamSpec spec() { return ParamSpec(type_name, "no density"); }
  static Params read(const ParamReader&) { return {1}; }
  static State initial_state(const Params&, Sym3&) { return {}; }
  SCREE_HD static void update(const Params&, State&, Sym3&, const StrainIncrement&) {}
  SCREE_HD static Real wave_speed(const Params&, const State&, const Sym3&, Real, Real) { return 1; }
  static void describe(OutputFields<MissingDensity>&) {}
};

static_assert(check_material<MissingDensity>());

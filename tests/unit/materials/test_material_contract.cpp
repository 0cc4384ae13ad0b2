// The material contract (scree/material/material.hpp): the concept Material accepts the
// materials of this repository and a minimal conforming one, and rejects a struct that
// misses one piece, piece by piece. Compile-time checks; the tests below only make them
// part of the suite's report. The message a plugin author sees for a missing piece is
// checked by the CTest material_contract_message (contract/missing_density.cpp).
#include <gtest/gtest.h>

#include "kineticTheory/KineticTheory.hpp"
#include "linearElastic/LinearElastic.hpp"
#include "phaseTransition/PhaseTransition.hpp"
#include "scree/material/material.hpp"
#include "simsand/Simsand.hpp"

using namespace scree;

namespace {

/// The smallest conforming material: a linear spring in the trace with one state variable.
struct Toy {
  static constexpr const char* type_name = "toy";
  struct Params {
    Real K, rho;
  };
  struct State {
    Real volumetric;  ///< accumulated tr(deps)
    Sym3 back;        ///< a tensor in the state (rotated by the model)
  };
  static ParamSpec spec() { return ParamSpec(type_name, "toy"); }
  static Params read(const ParamReader&) { return {1e6, 1000}; }
  static Real density(const Params& p) { return p.rho; }
  static State initial_state(const Params&, Sym3&) { return {}; }
  SCREE_HD static void update(const Params& p, State& s, Sym3& sigma, const StrainIncrement& inc) {
    s.volumetric += inc.deps.trace();
    s.back = corotate(s.back, inc.spin);
    for (int i = 0; i < 3; ++i) sigma[i] += p.K * inc.deps.trace();
  }
  SCREE_HD static Real wave_speed(const Params& p, const State&, const Sym3&, Real rho, Real) {
    return sqrt(p.K / rho);
  }
  static void describe(OutputFields<Toy>& out) { out.state("volumetricStrain", &State::volumetric, "-", "tr eps"); }
};

// Toy with one piece missing or wrong each.
struct NoDensity {
  static constexpr const char* type_name = "bad";
  using Params = Toy::Params;
  using State = Toy::State;
  static ParamSpec spec() { return Toy::spec(); }
  static Params read(const ParamReader& r) { return Toy::read(r); }
  static State initial_state(const Params& p, Sym3& s) { return Toy::initial_state(p, s); }
  SCREE_HD static void update(const Params& p, State& s, Sym3& sig, const StrainIncrement& i) { Toy::update(p, s, sig, i); }
  SCREE_HD static Real wave_speed(const Params& p, const State& s, const Sym3& sig, Real r, Real h) {
    return Toy::wave_speed(p, s, sig, r, h);
  }
  static void describe(OutputFields<NoDensity>&) {}
};
struct NoUpdate : Toy {
  static void describe(OutputFields<NoUpdate>&) {}
  static void update() = delete;
};
struct StateWithAnInt : Toy {
  struct State {
    Real x;
    int flag;  // not a Real: the kernels store States as arrays of Reals
  };
  static State initial_state(const Params&, Sym3&) { return {}; }
  SCREE_HD static void update(const Params&, State&, Sym3&, const StrainIncrement&) {}
  SCREE_HD static Real wave_speed(const Params&, const State&, const Sym3&, Real, Real) { return 1; }
  static void describe(OutputFields<StateWithAnInt>&) {}
};
struct NoTypeName : Toy {
  static constexpr int type_name = 3;
  static void describe(OutputFields<NoTypeName>&) {}
};
struct NoDescribe : Toy {
  static void describe(int) {}
};

}  // namespace

static_assert(Material<Toy>);
static_assert(check_material<Toy>());
static_assert(Material<materials::LinearElastic>);
static_assert(Material<materials::Simsand>);
static_assert(Material<materials::KineticTheory>);
static_assert(Material<materials::PhaseTransition>);

static_assert(!Material<NoDensity>);
static_assert(!material_contract::has_density<NoDensity>);
static_assert(material_contract::has_update<NoDensity>);  // only density is missing
static_assert(!Material<NoUpdate>);
static_assert(!material_contract::has_update<NoUpdate>);
static_assert(!Material<StateWithAnInt>);
static_assert(!material_contract::has_state<StateWithAnInt>);
static_assert(!Material<NoTypeName>);
static_assert(!Material<NoDescribe>);
static_assert(!Material<int>);

TEST(MaterialContract, ConformingMaterialsPassAndIncompleteOnesFail) {
  EXPECT_TRUE(Material<Toy>);
  EXPECT_TRUE(Material<materials::PhaseTransition>);
  EXPECT_FALSE(Material<NoDensity>);
  EXPECT_FALSE(Material<StateWithAnInt>);
}

// The toy behaves as a material through the host adapter (what scree-element uses).
TEST(MaterialContract, ToyRunsThroughPointMaterial) {
  PointMaterialOf<Toy> m(Toy::Params{1e6, 1000});
  Sym3 sig = Sym3::zero();
  m.initialise(sig);
  m.update(sig, StrainIncrement{Sym3{{-1e-3, 0, 0, 0, 0, 0}}, Spin3::zero(), 1e-3, 1});
  EXPECT_DOUBLE_EQ(sig[0], -1e3);
  EXPECT_DOUBLE_EQ(m.wave_speed(sig, 0.1), std::sqrt(1e6 / 1000));
  EXPECT_EQ(m.state().size(), 7u);
}

// Replays a fixed set of random stress updates through one version of the material headers
// and writes the bits of every result (stress, state, wave speed, elastic-path result,
// output fields) to stdout as hex: scripts/material-replay.sh compiles it against two trees
// and compares. Params come from read() on dictionaries of the cases' parameter sets, so the
// driver does not depend on how a version builds its Params. Usage: material-replay NAME,
// NAME one of phaseTransition, simsand, kineticTheory.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "kineticTheory/KineticTheory.hpp"
#include "phaseTransition/PhaseTransition.hpp"
#include "simsand/Simsand.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"

using namespace scree;
using namespace scree::materials;

static unsigned long long bits(double x) { unsigned long long u; std::memcpy(&u, &x, 8); return u; }
static void put(double x) { std::printf("%016llx\n", bits(x)); }
static void put(const Sym3& s) { for (int k = 0; k < 6; ++k) put(s[k]); }
template <class S> static void put_state(const S& s) {
  if constexpr (sizeof(S) >= sizeof(double) && !std::is_empty_v<S>) {
    double r[sizeof(S) / sizeof(double)];
    std::memcpy(r, &s, sizeof(S));
    for (double x : r) put(x);
  }
}

template <class M>
void replay(const std::string& text, unsigned seed, int samples, int steps) {
  const Dictionary d = Dictionary::parse(text, "material");
  const ParamSpec spec = M::spec();
  ParamReader r(spec, d);
  const typename M::Params p = M::read(r);
  OutputFields<M> out;
  M::describe(out);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> U(0, 1);
  put(M::density(p));
  for (int i = 0; i < samples; ++i) {
    const double pr = std::pow(10.0, -1 + 6 * U(g));
    Sym3 sig{{-pr * (1 + 0.6 * (U(g) - 0.5)), -pr * (1 + 0.6 * (U(g) - 0.5)), -pr * (1 + 0.6 * (U(g) - 0.5)),
              0.3 * pr * (U(g) - 0.5), 0, 0}};
    if (U(g) < 0.5) { sig[4] = 0.2 * pr * (U(g) - 0.5); sig[5] = 0.2 * pr * (U(g) - 0.5); }
    typename M::State s = M::initial_state(p, sig);
    put(sig); put_state(s);
    const double scale = std::pow(10.0, -7 + 4.5 * U(g));
    const double dt = std::pow(10.0, -6 + 3 * U(g));
    for (int k = 0; k < steps; ++k) {
      StrainIncrement inc;
      for (int c = 0; c < 6; ++c) inc.deps[c] = scale * (U(g) - 0.5);
      if (U(g) < 0.3) inc.deps[2] = inc.deps[4] = inc.deps[5] = 0;
      inc.spin = Spin3{scale * (U(g) - 0.5), 0, 0};
      inc.dt = dt;
      inc.J = 1;
      sig = corotate(sig, inc.spin);
      M::update(p, s, sig, inc);
      put(sig); put_state(s);
      put(M::wave_speed(p, s, sig, M::density(p), 0.01));
      if constexpr (material_has_elastic_path<M>()) {
        typename M::State s2 = s; Sym3 sig2 = sig;
        const bool el = M::update_elastic(p, s2, sig2, inc);
        put(el ? 1.0 : 0.0); put(sig2); put_state(s2);
      }
    }
    // every output field at the end
    double raw[64] = {};
    std::memcpy(raw, &s, sizeof(s));
    for (const auto& f : out.fields()) {
      double v[6] = {};
      f.eval(&p, raw, sig, v);
      for (int c = 0; c < f.components; ++c) put(v[c]);
    }
  }
}

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "";
  const std::string pt = R"(type phaseTransition; particleDensity 2650; diameter 1.25e-3; voidRatioSd 0.62;
    solidFractionM 0.4; restitutionCoefficient 0.6; particleFriction 0.2; initialGranularTemperature 1e-12;
    referenceBulkModulus 120; poissonRatio 0.2; atmosphericPressure 101300; elasticExponent 0.5;
    criticalFrictionAngle 19.8; referenceCriticalVoidRatio 0.977; criticalStateLambda 0.0596; criticalStateXi 0.365;
    dilatancyConstant 0.7; plasticModulusConstant 0.0044; peakStrengthExponent 2.4; phaseTransformationExponent 2.9;
    initialVoidRatio 0.95; integrationTolerance 1e-3;)";
  const std::string pt7 = R"(type phaseTransition; particleDensity 1050; diameter 1e-3; voidRatioSd 0.92;
    solidFractionM 0.4; restitutionCoefficient 0.7; particleFriction 0.1; initialGranularTemperature 1e-12;
    referenceBulkModulus 120; poissonRatio 0.235; atmosphericPressure 101300; elasticExponent 0.5;
    criticalFrictionAngle 23; referenceCriticalVoidRatio 0.910; criticalStateLambda 0.122; criticalStateXi 0.71;
    dilatancyConstant 0.5; plasticModulusConstant 0.001; peakStrengthExponent 1; phaseTransformationExponent 1;
    initialVoidRatio 1.05;)";
  const std::string ss = R"(type simsand; particleDensity 2650; referenceBulkModulus 120; poissonRatio 0.2;
    atmosphericPressure 101300; elasticExponent 0.5; criticalFrictionAngle 19.8; referenceCriticalVoidRatio 0.977;
    criticalStateLambda 0.0596; criticalStateXi 0.365; dilatancyConstant 0.7; plasticModulusConstant 0.0044;
    peakStrengthExponent 2.4; phaseTransformationExponent 2.9; initialVoidRatio 0.95; integrationTolerance 1e-3;)";
  const std::string ss1 = R"(type simsand; particleDensity 2650; referenceBulkModulus 150; poissonRatio 0.22;
    elasticExponent 0.6; criticalFrictionAngle 30; referenceCriticalVoidRatio 0.937; criticalStateLambda 0.022;
    criticalStateXi 0.71; dilatancyConstant 4; plasticModulusConstant 0.001; peakStrengthExponent 1;
    phaseTransformationExponent 1; initialVoidRatio 0.8; lodeDependence none;)";
  const std::string kt = R"(type kineticTheory; particleDensity 1500; diameter 1e-3; solidFractionSd 0.6;
    solidFractionM 0.4; restitutionCoefficient 0.6; particleFriction 0.2; initialGranularTemperature 1e-12;
    initialVoidRatio 0.8;)";
  if (which == "phaseTransition") {  // column collapse (Table 3) and element tests (Figs. 6-7)
    replay<PhaseTransition>(pt, 1, 3000, 30);
    replay<PhaseTransition>(pt7, 2, 2000, 30);
  } else if (which == "simsand") {  // column collapse (Table 3) and Table 1 without Lode dependence
    replay<Simsand>(ss, 3, 3000, 30);
    replay<Simsand>(ss1, 4, 2000, 30);
  } else if (which == "kineticTheory") {  // Table 2 (Fig. 5)
    replay<KineticTheory>(kt, 5, 3000, 30);
  } else {
    std::fprintf(stderr, "usage: material-replay phaseTransition|simsand|kineticTheory\n");
    return 2;
  }
  return 0;
}

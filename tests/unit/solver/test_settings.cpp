// Typed settings of the core dictionaries (case/settings.hpp): every key is read through
// its spec, so a case that leaves a key out gets the default the spec declares (and that
// `scree --list-plugins case` prints), and a case that sets it gets its value.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include "scree_test.hpp"

namespace scree::test {
namespace {

/// The smallest valid case: every optional key of the core dictionaries left out.
void write_minimal(const TempCase& tc, const std::string& schemes = "") {
  tc.write("system/controlDict", "endTime 0.1; deltaT 1e-4; writeInterval 0.05;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1 1); cellSize 0.1;");
  tc.write("system/mpmSchemes", schemes);
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "m { type linearElastic; E 1e6; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "b { material m; region { type rectangle; lower (0 0); upper (0.5 0.5); } }");
}

/// The default a spec declares for `key`, parsed as a number.
double spec_default(const ParamSpec& spec, const char* key) {
  const Param* p = spec.find(key);
  EXPECT_NE(p, nullptr) << key;
  EXPECT_TRUE(p && p->default_text()) << key << " has no default";
  return std::stod(*p->default_text());
}

TEST(Settings, OmittedKeysTakeTheDefaultsTheSpecsDeclare) {
  TempCase tc("settings_defaults");
  write_minimal(tc);
  const Case c = Case::read(tc.dir(), runtime());
  const CaseSettings& s = c.settings();
  const CoreSpecs& cs = CoreSpecs::get();
  EXPECT_EQ(s.control.time.start_time, spec_default(*cs.control, "startTime"));
  EXPECT_EQ(s.control.time.max_co, spec_default(*cs.control, "maxCo"));
  EXPECT_EQ(s.control.progress_interval, spec_default(*cs.control, "progressInterval"));
  EXPECT_FALSE(s.control.time.adjust_time_step);
  EXPECT_EQ(s.control.time.max_delta_t, 1e-4) << "maxDeltaT defaults to deltaT";
  EXPECT_EQ(s.control.write_control, WriteControl::runTime);
  EXPECT_EQ(s.schemes.pic_fraction, spec_default(*cs.schemes, "picFraction"));
  EXPECT_EQ(s.schemes.pic_rate, spec_default(*cs.schemes, "picRate"));
  EXPECT_EQ(s.schemes.mass_tolerance, spec_default(*cs.schemes, "massTolerance"));
  EXPECT_EQ(s.schemes.sort_interval, spec_default(*cs.schemes, "sortInterval"));
  EXPECT_EQ(s.schemes.update_scheme, UpdateScheme::USF);
  EXPECT_EQ(s.schemes.shape, ShapeKind::linear);
  EXPECT_EQ(s.schemes.transfer, Transfer::flip);
  EXPECT_EQ(s.schemes.max_volume_ratio, std::numeric_limits<Real>::infinity()) << "no limit without the key";
  EXPECT_EQ(s.schemes.damping.coefficient, 0);
  EXPECT_EQ(s.grid.ghost_layers, spec_default(*cs.grid, "ghostLayers"));
  EXPECT_EQ(s.grid.cell_size, 0.1);
  ASSERT_EQ(s.gravity.size(), 2u);
  EXPECT_EQ(s.gravity[1], -9.81);
}

TEST(Settings, GivenKeysAreReadAndDampingTakesItsSubSpecsDefaults) {
  TempCase tc("settings_given");
  write_minimal(tc,
                "updateScheme MUSL; shapeFunction bspline2; transfer APIC; picFraction 0.01; sortInterval 50;"
                "maxVolumeRatio 526; massTolerance 1e-5; damping { coefficient 0.1; }");
  const Case c = Case::read(tc.dir(), runtime());
  const SchemeSettings& s = c.settings().schemes;
  EXPECT_EQ(s.update_scheme, UpdateScheme::MUSL);
  EXPECT_EQ(s.shape, ShapeKind::bspline2);
  EXPECT_EQ(s.transfer, Transfer::apic);
  EXPECT_EQ(s.pic_fraction, 0.01);
  EXPECT_EQ(s.sort_interval, 50);
  EXPECT_EQ(s.max_volume_ratio, 526);
  EXPECT_EQ(s.mass_tolerance, 1e-5);
  EXPECT_EQ(s.damping.coefficient, 0.1);
  const ParamSpec& damp = *CoreSpecs::get().schemes->find("damping")->sub();
  EXPECT_EQ(s.damping.start_time, spec_default(damp, "startTime"));
  EXPECT_EQ(s.damping.end_time, spec_default(damp, "endTime"));
}

// sortInterval was documented as "default 0 (never)" while the solver sorted every 200
// steps. Now the spec's default is the one in force, and `scree --list-plugins case`
// prints it.
TEST(Settings, SortIntervalDefaultInForceIsTheDocumentedOne) {
  const double documented = spec_default(*CoreSpecs::get().schemes, "sortInterval");
  EXPECT_EQ(documented, 200);
  TempCase tc("settings_sort");
  write_minimal(tc);
  const Case c = Case::read(tc.dir(), runtime());
  EXPECT_EQ(c.settings().schemes.sort_interval, documented);
  EXPECT_EQ(KernelPolicy{}.sort_interval(c.settings().schemes.sort_interval), documented);
  EXPECT_EQ(KernelPolicy::reference_kernels().sort_interval(c.settings().schemes.sort_interval), 0)
      << "the reference kernels never sort";

  std::string listing;
  {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(SCREE_EXE " --list-plugins case", "r"), pclose);
    ASSERT_TRUE(pipe);
    std::array<char, 4096> buf;
    while (fgets(buf.data(), buf.size(), pipe.get())) listing += buf.data();
  }
  const auto at = listing.find("sortInterval");
  ASSERT_NE(at, std::string::npos) << listing;
  const std::string line = listing.substr(at, listing.find('\n', at) - at);
  EXPECT_NE(line.find("200"), std::string::npos) << line;
}

TEST(Settings, BodySettingsTakeTheBodySpecsDefault) {
  const auto d = Dictionary::parse("b { material m; region { type rectangle; lower (0 0); upper (1 1); } }", "t");
  const BodySettings b = BodySettings::read(d.sub("b"));
  EXPECT_EQ(b.material, "m");
  EXPECT_EQ(b.particles_per_cell, spec_default(*CoreSpecs::get().body, "particlesPerCell"));
}

}  // namespace
}  // namespace scree::test

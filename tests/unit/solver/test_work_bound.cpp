// The bound on a stress update's work (material.hpp, work_bound; SIMSAND's maxSubsteps): the
// updates that reach it are counted per body, over the whole run, and the run's log says how
// many and which bound.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>
#include <string>

#include "scree_test.hpp"

namespace scree::test {
namespace {

/// The log of a 0.05 s collapse of a small SIMSAND column (the column case's sand at its
/// tolerance, 10 mm cells) with `extra` added to its material.
std::string collapse_log(const std::string& extra, int threads) {
  TempCase tc("workbound");
  tc.write("system/controlDict", "endTime 0.05; deltaT 1e-4; adjustTimeStep yes; maxCo 0.5; writeInterval 0.05;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.5 0.15); cellSize 0.01;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties",
           "sand { type simsand; particleDensity 2650; referenceBulkModulus 120; poissonRatio 0.2; "
           "elasticExponent 0.5; criticalFrictionAngle 19.8; referenceCriticalVoidRatio 0.977; "
           "criticalStateLambda 0.0596; criticalStateXi 0.365; dilatancyConstant 0.7; "
           "plasticModulusConstant 0.0044; peakStrengthExponent 2.4; phaseTransformationExponent 2.9; "
           "initialVoidRatio 0.95; integrationTolerance 1e-2; " +
               extra + " }");
  tc.write("constant/bodies",
           "column { material sand; region { type rectangle; lower (0.15 0); upper (0.35 0.1); } particlesPerCell 2; "
           "initialStress { type geostatic; K0 0.5; } }");
  tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; }");
  Case c = Case::read(tc.dir(), runtime());
  RunOptions o = options(threads);
  std::ostringstream log;
  o.log = &log;
  Simulation sim(c, runtime(), o);
  sim.run();
  return log.str();
}

TEST(WorkBound, UpdatesThatReachTheBoundAreCountedInTheLog) {
  const std::regex line(
      "body 'column': (\\d+) stress updates? reached the bound on their work \\(maxSubsteps (\\d+)\\)");
  std::smatch m;
  const std::string dflt = collapse_log("", 1);
  ASSERT_TRUE(std::regex_search(dflt, m, line)) << dflt;
  EXPECT_EQ(m[1].str(), "0") << "no update of this collapse needs a thousand substeps";
  EXPECT_EQ(m[2].str(), "1000");
  for (int threads : {1, 2}) {
    const std::string low = collapse_log("maxSubsteps 2;", threads);
    ASSERT_TRUE(std::regex_search(low, m, line)) << low;
    EXPECT_EQ(m[2].str(), "2");
    // The column's 800 points over at least the 500 steps of 0.05 s at 1e-4 s: the flowing
    // points' plastic updates take more than two substeps at the default tolerance.
    EXPECT_GT(std::stoll(m[1].str()), 100) << low;
    EXPECT_NE(low.find(" of its "), std::string::npos) << "the share of the point-updates: " << low;
  }
}

}  // namespace
}  // namespace scree::test

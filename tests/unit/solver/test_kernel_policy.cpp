// KernelPolicy (exec/kernel_policy.hpp): a register cap is a compile-time launch bound,
// so only the caps the kernels were compiled for exist. Any other value used to run the
// uncapped kernel without a word; now it is an error that names the valid values.
#include <gtest/gtest.h>

#include "scree_test.hpp"

namespace scree::test {
namespace {

TEST(KernelPolicy, TheDefaultsAndEveryCompiledCapAreAccepted) {
  EXPECT_EQ(KernelPolicy{}.check(), "");
  EXPECT_EQ(KernelPolicy::reference_kernels().check(), "");
  for (int cap : KernelPolicy::kStressCaps) {
    KernelPolicy p;
    p.stress_blocks_per_sm = cap;
    EXPECT_EQ(p.check(), "") << cap;
  }
  for (int cap : KernelPolicy::kElasticCaps) {
    KernelPolicy p;
    p.elastic_blocks_per_sm = cap;
    EXPECT_EQ(p.check(), "") << cap;
  }
}

TEST(KernelPolicy, RefillLanesAreTheLanesOfAWarp) {
  for (int lanes : {1, 8, 16, 32}) {
    KernelPolicy p;
    p.refill_lanes = lanes;
    EXPECT_EQ(p.check(), "") << lanes;
  }
  for (int lanes : {0, 33}) {
    KernelPolicy p;
    p.refill_lanes = lanes;
    EXPECT_NE(p.check().find("expected 1 to 32"), std::string::npos) << p.check();
  }
}

TEST(KernelPolicy, AnUncompiledCapIsAnErrorNamingTheValidOnes) {
  KernelPolicy p;
  p.stress_blocks_per_sm = 8;
  EXPECT_NE(p.check().find("valid: 0, 6"), std::string::npos) << p.check();
  KernelPolicy q;
  q.elastic_blocks_per_sm = 7;
  EXPECT_NE(q.check().find("valid: 0, 10"), std::string::npos) << q.check();

  // ... and a run with it does not start.
  TempCase tc("policy");
  tc.write("system/controlDict", "endTime 0.01; deltaT 1e-4; writeInterval 0.01;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (1 1); cellSize 0.1;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "m { type linearElastic; E 1e6; nu 0.3; rho 1000; }");
  tc.write("constant/bodies", "b { material m; region { type rectangle; lower (0 0); upper (0.5 0.5); } }");
  const Case c = Case::read(tc.dir(), runtime());
  RunOptions o = options(1);
  o.kernels = p;
  EXPECT_THROW(Simulation(c, runtime(), o), std::invalid_argument);
}

TEST(KernelPolicy, TheReferenceKernelsNeitherSortNorUseTheSparseGrid) {
  const KernelPolicy r = KernelPolicy::reference_kernels();
  EXPECT_FALSE(r.sparse());
  EXPECT_EQ(r.sort_interval(200), 0);
  KernelPolicy f;
  EXPECT_TRUE(f.sparse());
  EXPECT_EQ(f.sort_interval(200), 200);
}

}  // namespace
}  // namespace scree::test

// The memory estimate (case/memory_estimate.hpp): its bytes per node and per point
// against hand-computed counts of the solver's arrays, its backend total against the
// bytes a small case really allocates (mem::bytes_in_use counts every Buffer), single-
// and two-phase, and check_memory's error at the entry that drives the memory. (scree
// itself: tests/broken/variants/memory_*.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "scree/case/decomposition.hpp"
#include "scree/case/memory_estimate.hpp"
#include "scree/case/setup_check.hpp"
#include "scree/material/material.hpp"
#include "scree/plugin/registry.hpp"
#include "scree_test.hpp"

namespace scree::test {
namespace {

/// A 1 m x 1 m grid of 1 cm cells (105 x 105 nodes with the ghost layers), a block of
/// 0.5 m x 0.5 m at 2 x 2 points per cell (10,000 points), a floor, sorted every step.
void write_block(const TempCase& tc, const std::string& cell = "0.01", const std::string& ppc = "2",
                 const std::string& material = "type linearElastic; E 1e6; nu 0.3; rho 1000;") {
  tc.write("system/controlDict", "endTime 0.01; deltaT 1e-5; writeInterval 0.01;");
  tc.write("system/mpmSchemes", "sortInterval 1;");
  tc.write("system/gridDict", "dimension 2;\nlower (0 0);\nupper (1 1);\ncellSize " + cell + ";");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "sand { " + material + " }");
  tc.write("constant/bodies", "block\n{\n  material sand;\n  region { type rectangle; lower (0.25 0.25); upper (0.75 0.75); }\n"
                              "  particlesPerCell " + ppc + ";\n}\n");
  tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; }");
}

/// The bytes the case's Simulation holds on the CPU backend after setting up and taking
/// a step with a sort (every Buffer: grid, particles, sort buffers, masks).
double allocated(const Case& c) {
  const std::size_t before = mem::bytes_in_use(Device::cpu);
  RunOptions o = options(1);
  o.device = Device::cpu;
  Simulation sim(c, runtime(), o);
  sim.run_steps(2);
  return static_cast<double>(mem::bytes_in_use(Device::cpu) - before);
}

TEST(MemoryEstimate, FreeMemoryIsReadAndTheTestVariableReplacesIt) {
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
  const mem::Available host = mem::available(Device::cpu);
  ASSERT_TRUE(host.known) << "Linux: /proc/meminfo";
  EXPECT_GT(host.bytes, 0u);
  EXPECT_FALSE(host.source.empty());
  ::setenv("SCREE_TEST_FREE_MEMORY", "2e9", 1);
  EXPECT_EQ(mem::available(Device::cpu).bytes, 2000000000u);
  EXPECT_EQ(mem::available(Device::cuda).bytes, 2000000000u);
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
  EXPECT_EQ(mem::format_bytes(152), "152 bytes");
  EXPECT_EQ(mem::format_bytes(2e9), "2.00 GB");
  EXPECT_EQ(mem::format_bytes(43.84e9), "43.8 GB");
  EXPECT_EQ(mem::format_bytes(288e12), "288 TB");
}

TEST(MemoryEstimate, BytesPerNodeAndPointAreTheSolversArrays) {
  TempCase tc("memory_counts");
  write_block(tc);
  const Case c = Case::read(tc.dir(), runtime());
  const MemoryEstimate m = estimate_memory(c, runtime().registry(), Device::cpu, false);
  ASSERT_EQ(m.parts.size(), 2u);
  const MemoryPart& grid = m.parts[0];
  EXPECT_EQ(grid.key, "cellSize");
  EXPECT_EQ(grid.where.str(), "system/gridDict:4:1");
  EXPECT_DOUBLE_EQ(grid.count, 105.0 * 105.0);  // 100 cells + 1 + 2 x 2 ghost layers per axis
  // Two sets of 1 + 4 D = 9 Reals, a uint32 stamp per 128-node tile and set, a wall mask.
  EXPECT_DOUBLE_EQ(grid.backend_each, 2 * 9 * 8 + 2 * 4.0 / 128 + 4);
  EXPECT_DOUBLE_EQ(grid.host_each, 4);  // the WallSet's masks while the walls are built
  const MemoryPart& body = m.parts[1];
  EXPECT_EQ(body.key, "particlesPerCell");
  EXPECT_EQ(body.where.str(), "constant/bodies:5:3");
  EXPECT_DOUBLE_EQ(body.count, 10000);
  // linearElastic in 2D, FLIP: x, v, x0 (2 each), F (4), sigma (4), mass, volume0, id:
  // 17 Reals; the split's list (8), keys and permutation (16), a scratch copy of all 17
  // columns (the block is under 64 MiB).
  EXPECT_DOUBLE_EQ(body.backend_each, 17 * 8 + 8 + 16 + 17 * 8);
  // Host, without output: the setup's copies, positions and volumes at a capacity of
  // 16,384 (push_back), velocities and stresses, the host block.
  EXPECT_DOUBLE_EQ(body.host_each, 16384.0 / 10000 * 3 * 8 + 8 * 8 + 17 * 8);
}

TEST(MemoryEstimate, BackendBytesAreWhatASmallCaseAllocates) {
  TempCase tc("memory_single");
  write_block(tc);
  const Case c = Case::read(tc.dir(), runtime());
  const double estimate = estimate_memory(c, runtime().registry(), Device::cpu, false).backend_bytes();
  const double actual = allocated(c);
  std::cout << "single-phase: estimate " << estimate << " bytes, allocated " << actual << " bytes\n";
  EXPECT_GT(estimate, actual / 1.1);
  EXPECT_LT(estimate, actual * 1.1);
}

TEST(MemoryEstimate, AMaterialWhoseUpdateRunsInTurnsCountsItsHandoff) {
  // SIMSAND's update runs in turns: its body holds the split's Handoff, 8 Reals a point in
  // 2D (the increment's xx, yy and xy strain and its spin, J, the start speed and the energy
  // ledger's two shares), besides its State (twice: the block and the sort's scratch copy).
  const std::string simsand =
      "type simsand; particleDensity 2650; referenceBulkModulus 120; poissonRatio 0.2; elasticExponent 0.5; "
      "criticalFrictionAngle 19.8; referenceCriticalVoidRatio 0.977; criticalStateLambda 0.0596; "
      "criticalStateXi 0.365; dilatancyConstant 0.7; plasticModulusConstant 0.0044; peakStrengthExponent 2.4; "
      "phaseTransformationExponent 2.9; initialVoidRatio 0.95;";
  TempCase elastic("memory_turns_elastic"), sand("memory_turns_sand");
  write_block(elastic);
  write_block(sand, "0.01", "2", simsand);
  const Case ce = Case::read(elastic.dir(), runtime()), cs = Case::read(sand.dir(), runtime());
  const double k = static_cast<double>(
      runtime().registry().make_point_material(cs.materials().sub("sand"))->state().size());
  ASSERT_GT(k, 0);
  const double e = estimate_memory(ce, runtime().registry(), Device::cpu, false).parts[1].backend_each;
  const MemoryEstimate m = estimate_memory(cs, runtime().registry(), Device::cpu, false);
  EXPECT_DOUBLE_EQ(m.parts[1].backend_each - e, 2 * k * 8 + 8 * 8);
  const double estimate = m.backend_bytes();
  const double actual = allocated(cs);
  std::cout << "simsand: estimate " << estimate << " bytes, allocated " << actual << " bytes\n";
  EXPECT_GT(estimate, actual / 1.1);
  EXPECT_LT(estimate, actual * 1.1);
}

TEST(MemoryEstimate, BackendBytesOfATwoPhaseCaseAreWhatItAllocates) {
  TempCase tc("memory_two_phase");
  tc.write("system/controlDict", "endTime 0.01; deltaT 1e-5; writeInterval 0.01;");
  tc.write("system/mpmSchemes", "updateScheme USL; sortInterval 1;");
  tc.write("system/gridDict", "dimension 2; lower (0 0); upper (0.1 1.1); cellSize 0.0125;");
  tc.write("constant/g", "value (0 -9.81);");
  tc.write("constant/materialProperties", "soil { type linearElastic; E 1e7; nu 0.3; rho 2650; }");
  tc.write("constant/bodies",
           "column { material soil; region { type rectangle; lower (0 0); upper (0.1 1.05); } particlesPerCell 2;\n"
           "  twoPhase { porosity 0.33; liquidDensity 1000; liquidBulkModulus 2e8; viscosity 1e-3;\n"
           "             intrinsicPermeability 2e-10; } }");
  tc.write("constant/boundaryConditions",
           "base { type fixed; face yMin; drained yes; }\nleft { type slip; face xMin; }\n"
           "right { type slip; face xMax; }");
  const Case c = Case::read(tc.dir(), runtime());
  const MemoryEstimate m = estimate_memory(c, runtime().registry(), Device::cpu, false);
  // The liquid's two sets of 8 + 4 D Reals, 2 cell counts, a surface flag, 3 + D balance
  // Reals, 1 + 2 D reconstructed cell pressures and its wall masks, besides the grid's.
  EXPECT_DOUBLE_EQ(m.parts[0].backend_each,
                   2 * 9 * 8 + 2 * 4.0 / 128 + 4 + 2 * 16 * 8 + 2 * 8 + 1 + 5 * 8 + 5 * 8 + 4);
  const double estimate = m.backend_bytes();
  const double actual = allocated(c);
  std::cout << "two-phase: estimate " << estimate << " bytes, allocated " << actual << " bytes\n";
  EXPECT_GT(estimate, actual / 1.1);
  EXPECT_LT(estimate, actual * 1.1);
}

/// check_memory with SCREE_TEST_FREE_MEMORY set to `bytes`.
std::vector<InputError> check_with(const Case& c, const char* bytes) {
  ::setenv("SCREE_TEST_FREE_MEMORY", bytes, 1);
  auto e = check_memory(c, runtime().registry(), Device::cpu, true);
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
  return e;
}

TEST(MemoryEstimate, TooManyPointsNameTheBodysParticlesPerCellAndWhatFits) {
  TempCase tc("memory_points");
  write_block(tc, "0.01", "8");  // 160,000 points
  const Case c = Case::read(tc.dir(), runtime());
  const MemoryEstimate m = estimate_memory(c, runtime().registry(), Device::cpu, true);
  EXPECT_TRUE(check_with(c, std::to_string(m.host_bytes() * 1.01).c_str()).empty());
  const auto e = check_with(c, "50e6");
  ASSERT_EQ(e.size(), 1u);
  const std::string what = e[0].what();
  EXPECT_EQ(e[0].where().str(), "constant/bodies:5:3") << what;
  EXPECT_EQ(what.rfind("constant/bodies:5:3: particlesPerCell: the run needs about ", 0), 0u) << what;
  EXPECT_NE(what.find("of host memory, more than the 50.0 MB free (SCREE_TEST_FREE_MEMORY, set for a test)"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("the 160,000 particles of body 'block' (particlesPerCell 8 at constant/bodies:5:3)"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("; particlesPerCell 6 fits (90,000 particles"), std::string::npos) << what;
  // And the run refuses before it allocates anything.
  ::setenv("SCREE_TEST_FREE_MEMORY", "50e6", 1);
  const std::size_t before = mem::bytes_in_use(Device::cpu);
  EXPECT_THROW(Simulation(c, runtime(), options(1)), InputErrors);
  EXPECT_EQ(mem::bytes_in_use(Device::cpu), before);
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
}

// A run over ranks: each rank's backend holds its slab of the grid with the halo (a
// quarter of 1000 cells plus 5 node layers on each side, the widest shape's reach and the
// migration slack) and at most kRebalanceRatio times a quarter of the points before the
// cuts move; so does its host, since each rank makes only the points of its box (and
// writes them as its own piece); the ranks of one machine share that machine's memory. A
// case too big for one process fits on four machines, and not on four ranks of one.
TEST(MemoryEstimate, ARunOverRanksNeedsItsShareOfTheBackendAndOfTheHost) {
  TempCase tc("memory_ranks");
  write_block(tc, "0.001", "1");  // 1,010,025 nodes, 250,000 points
  const Case c = Case::read(tc.dir(), runtime());
  const auto& reg = runtime().registry();
  const MemoryEstimate one = estimate_memory(c, reg, Device::cpu, true);
  const MemoryEstimate four = estimate_memory(c, reg, Device::cpu, true, {4, 1});
  const MemoryEstimate shared = estimate_memory(c, reg, Device::cpu, true, {4, 4});
  EXPECT_NEAR(four.parts[0].backend() / one.parts[0].backend(), 0.25 + 2 * 5 / 1000.0, 1e-12);
  EXPECT_NEAR(four.parts[1].backend() / one.parts[1].backend(), kRebalanceRatio / 4, 1e-12);
  EXPECT_NEAR(four.parts[1].host() / one.parts[1].host(), kRebalanceRatio / 4, 1e-12);
  EXPECT_DOUBLE_EQ(shared.host_bytes(), 4 * four.host_bytes());
  EXPECT_LT(four.host_bytes(), one.host_bytes());

  const std::string free = std::to_string(0.5 * (one.host_bytes() + four.host_bytes()));
  ::setenv("SCREE_TEST_FREE_MEMORY", free.c_str(), 1);
  const auto refused = check_memory(c, reg, Device::cpu, true);
  const auto fits = check_memory(c, reg, Device::cpu, true, {4, 1});
  const auto crowded = check_memory(c, reg, Device::cpu, true, {4, 4});
  ::unsetenv("SCREE_TEST_FREE_MEMORY");
  EXPECT_EQ(refused.size(), 1u);
  EXPECT_TRUE(fits.empty()) << fits.front().what();
  ASSERT_EQ(crowded.size(), 1u);
  EXPECT_NE(std::string(crowded[0].what()).find("of host memory on each machine (its 4 rank(s) of 4, each making its "
                                                "own points)"),
            std::string::npos)
      << crowded[0].what();
}

// A function object that does not reduce over ranks computes on the whole case, which the
// first rank gathers when it is due: its host holds the whole case's output copy besides
// its own share; the other ranks of its machine only their shares. Those that reduce
// (every shipped one) add nothing.
TEST(MemoryEstimate, TheFirstRankGathersTheWholeCaseForFunctionObjects) {
  register_whole_case();
  TempCase tc("memory_gather");
  write_block(tc, "0.001", "1");
  tc.write("system/controlDict", "endTime 0.01; deltaT 1e-5; writeInterval 0.01; functions { e { type energies; } }");
  const auto& reg = runtime().registry();
  {
    const Case c = Case::read(tc.dir(), runtime());
    EXPECT_EQ(estimate_memory(c, reg, Device::cuda, true, {4, 1}).parts[1].host_root_each, 0);
  }
  tc.write("system/controlDict",
           "endTime 0.01; deltaT 1e-5; writeInterval 0.01; functions { e { type energies; } w { type testWholeCase; } }");
  const Case c = Case::read(tc.dir(), runtime());
  const MemoryPart one = estimate_memory(c, reg, Device::cuda, true).parts[1];
  const MemoryPart four = estimate_memory(c, reg, Device::cuda, true, {4, 1}).parts[1];
  EXPECT_EQ(one.host_root_each, 0);  // one rank: its own points are the whole case
  EXPECT_GT(four.host_root_each, 0);
  EXPECT_DOUBLE_EQ(four.host(), four.count * (four.rank_share * four.host_each + four.host_root_each));
  EXPECT_GT(four.host(), four.count * four.host_root_each);
  EXPECT_DOUBLE_EQ(four.node_host(4) - four.node_host(1), 3 * four.count * four.rank_share * four.host_each);
}

TEST(MemoryEstimate, ALargeGridNamesCellSizeAndTheSmallestThatFits) {
  TempCase tc("memory_grid");
  write_block(tc, "0.001", "1");  // 1,010,025 nodes, 250,000 points
  const Case c = Case::read(tc.dir(), runtime());
  const auto e = check_with(c, "100e6");
  ASSERT_EQ(e.size(), 1u);
  const std::string what = e[0].what();
  EXPECT_EQ(what.rfind("system/gridDict:4:1: cellSize: the run needs about ", 0), 0u) << what;
  EXPECT_NE(what.find("the grid's 1,010,025 nodes (cellSize 0.001 m at system/gridDict:4:1)"), std::string::npos)
      << what;
  const std::string fits = "; a cellSize of at least ";
  const auto at = what.find(fits);
  ASSERT_NE(at, std::string::npos) << what;
  const double h = std::stod(what.substr(at + fits.size()));
  EXPECT_GT(h, 0.001);
  // That cell size fits, and one 2% smaller does not.
  auto with_cell = [&](double cell) {
    TempCase t("memory_grid_fit");
    write_block(t, std::to_string(cell), "1");
    return check_with(Case::read(t.dir(), runtime()), "100e6").empty();
  };
  EXPECT_TRUE(with_cell(h)) << what;
  EXPECT_FALSE(with_cell(h * 0.98)) << what;
}

TEST(MemoryEstimate, AnAllocationThatFailsNamesItsEntryAndSize) {
  // Unchecked (check_setup off), a grid of 4e12 nodes: its fields (288 TB) exceed any
  // address space, so the allocation fails on every machine and whatever its overcommit.
  TempCase tc("memory_alloc");
  write_block(tc, "5e-5", "1");
  tc.write("system/gridDict", "dimension 2;\nlower (0 0);\nupper (100 100);\ncellSize 5e-5;");
  const Case c = Case::read(tc.dir(), runtime());
  RunOptions o = options(1);
  o.device = Device::cpu;
  o.check_setup = false;
  std::string what;
  try {
    Simulation sim(c, runtime(), o);
  } catch (const InputError& e) {
    what = e.what();
  }
  EXPECT_EQ(what.rfind("system/gridDict:4:1: cellSize: the grid's 4000020000025 nodes need about ", 0), 0u) << what;
  EXPECT_NE(what.find(" of host memory, and an allocation for them failed (out of host memory: 288 TB ("),
            std::string::npos)
      << what;
}

}  // namespace
}  // namespace scree::test

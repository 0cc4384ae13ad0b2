// End to end: a small case (an elastic column under gravity) written into a temporary
// directory and run with the `scree` executable of the build tree, with the vtk writer
// and the function objects. Checks that the .pvd series lists every write time, that
// every .vtp it lists opens with VTK's reader with the right particle count and arrays,
// that no temporary file is left, and that the CSV files have one row per execution.
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cstdlib>

#include "scree_test.hpp"
#include "test_util.hpp"

using namespace scree_test;

namespace {

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

/// Writes each (path relative to `dir`, text) of `files`.
void write_files(const fs::path& dir, std::initializer_list<std::pair<const char*, std::string>> files) {
  for (const auto& [rel, text] : files) write_file(dir / rel, text);
}

const char* const kSoil = "soil { type linearElastic; E 1e6; nu 0.3; rho 1000; }\n";

/// 4 x 20 cells of 0.05 m with 2 x 2 particles per cell: 320 particles.
void write_case(const fs::path& dir) {
  write_files(dir, {{"constant/materialProperties", kSoil},
                    {"constant/g", "value (0 -9.81);\n"},
                    {"constant/boundaryConditions",
                     "floor { type fixed; face yMin; }\nleft { type slip; face xMin; }\nright { type slip; face xMax; }\n"},
                    {"constant/bodies",
                     "column { material soil; region { type rectangle; lower (0 0); upper (0.2 1.0); } "
                     "particlesPerCell 2; }\n"},
                    {"system/gridDict", "dimension 2;\nlower (0 0);\nupper (0.2 1.0);\ncellSize 0.05;\n"},
                    {"system/mpmSchemes", "updateScheme USF;\n"},
                    {"system/controlDict",
                     "FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }\n"
                     "endTime 0.02;\ndeltaT 1e-4;\nwriteControl adjustableRunTime;\nwriteInterval 0.005;\n"
                     "writers { vtk { type vtk; fields (velocity stress pressure); } }\n"
                     "functions {\n"
                     "  front { type runOut; origin (0 0); }\n"
                     "  probes { type particleProbes; points ((0.1 0.9)); names (top); fields (pressure); "
                     "executeControl timeStep; executeInterval 50; }\n"
                     "}\n"}});
}

}  // namespace

TEST(EndToEnd, ElasticColumnWritesReadableSeries) {
  TempDir dir;
  write_case(dir.path());
  const ScreeRun run = run_scree(dir.path(), " --threads 2", dir.path() / "log.scree");
  ASSERT_EQ(run.rc, 0) << run.out;

  const fs::path vtk = dir.path() / "VTK";
  const auto series = read_pvd(vtk / "vtk.pvd");
  ASSERT_EQ(series.size(), 5u) << run.out;  // t = 0, 0.005, ..., 0.02
  for (std::size_t i = 0; i < series.size(); ++i) {
    EXPECT_NEAR(series[i].time, 0.005 * static_cast<double>(i), 1e-9);
    EXPECT_EQ(series[i].file, "vtk_" + std::to_string(i) + ".vtp");
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName((vtk / series[i].file).c_str());
    r->Update();
    ASSERT_EQ(r->GetErrorCode(), 0u) << series[i].file;
    vtkPolyData* pd = r->GetOutput();
    EXPECT_EQ(pd->GetNumberOfPoints(), 320) << series[i].file;
    EXPECT_EQ(pd->GetNumberOfVerts(), 320) << series[i].file;
    vtkPointData* pt = pd->GetPointData();
    EXPECT_EQ(pt->GetNumberOfArrays(), 5);
    for (const char* name : {"particleId", "bodyId", "velocity", "stress", "pressure"})
      EXPECT_NE(pt->GetArray(name), nullptr) << series[i].file << ": " << name;
    EXPECT_EQ(pt->GetArray("velocity")->GetNumberOfComponents(), 3);
    EXPECT_EQ(pt->GetArray("stress")->GetNumberOfComponents(), 6);
    EXPECT_NEAR(pd->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), series[i].time, 1e-12);
  }
  // Compressed appended binary by default.
  std::ifstream vf(vtk / "vtk_1.vtp", std::ios::binary);
  std::string head(400, '\0');
  vf.read(head.data(), static_cast<std::streamsize>(head.size()));
  EXPECT_NE(head.find("vtkZLibDataCompressor"), std::string::npos);
  EXPECT_TRUE(temporaries(vtk).empty());

  // Function objects: one row per write time (runOut), per 50 steps (probes).
  const fs::path pp = dir.path() / "postProcessing";
  const Csv front = read_csv(pp / "front" / "runOut.csv");
  ASSERT_EQ(front.rows.size(), 5u);
  EXPECT_EQ(front.num(0, "particles [-]"), 320);
  EXPECT_NEAR(front.num(0, "runout [m]"), 0.1875, 1e-12);  // centres of the last column of particles
  EXPECT_NEAR(front.num(0, "kinetic_energy [J/m]"), 0.0, 1e-12);
  EXPECT_GT(front.num(4, "kinetic_energy [J/m]"), 0.0);
  const Csv top = read_csv(pp / "probes" / "top.csv");
  EXPECT_EQ(top.rows.size(), 5u);
  const std::vector<std::string> header = {"time [s]", "x [m]", "y [m]", "pressure [Pa]"};
  EXPECT_EQ(top.header, header);
  EXPECT_TRUE(temporaries(pp / "probes").empty());
}

// The shipped template case, cases/elasticColumn, run as a user would (copied to a
// temporary directory): its .pvd series opens with VTK's reader, every listed file has
// the 1280 particles and the standard fields, and the last one holds the settled column
// (sigma_yy at the bottom row within 2% of rho g H: the case's own claim). The copy is
// made without the results scripts/setup.sh leaves in the source tree (copy_case), so the
// run needs no --overwrite: results carried along would stop it with status 4.
TEST(EndToEnd, ShippedElasticColumnCase) {
  TempDir dir;
  scree::test::copy_case(fs::path(SCREE_SOURCE_DIR) / "cases" / "elasticColumn", dir.path());
  ASSERT_EQ(run_scree(dir.path(), " --device cpu --threads 2", dir.path() / "log.scree").rc, 0);
  const fs::path vtk = dir.path() / "VTK";
  const auto series = read_pvd(vtk / "particles.pvd");
  ASSERT_EQ(series.size(), 13u);  // t = 0, 0.25, ..., 3
  vtkPolyData* last = nullptr;
  vtkNew<vtkXMLPolyDataReader> readers[13];
  for (std::size_t i = 0; i < series.size(); ++i) {
    readers[i]->SetFileName((vtk / series[i].file).c_str());
    readers[i]->Update();
    ASSERT_EQ(readers[i]->GetErrorCode(), 0u) << series[i].file;
    vtkPolyData* pd = readers[i]->GetOutput();
    ASSERT_EQ(pd->GetNumberOfPoints(), 1280) << series[i].file;
    for (const char* name : {"particleId", "bodyId", "velocity", "displacement", "stress", "pressure",
                             "deviatoricStress", "volume", "mass", "density"})
      ASSERT_NE(pd->GetPointData()->GetArray(name), nullptr) << series[i].file << ": " << name;
    last = pd;
  }
  const double rho = 1800, g = 9.81, H = 1.0;
  vtkDataArray* s = last->GetPointData()->GetArray("stress");
  double sum = 0;
  int n = 0;
  for (vtkIdType p = 0; p < last->GetNumberOfPoints(); ++p)
    if (last->GetPoint(p)[1] < 0.025) {  // the bottom cell row
      sum += s->GetComponent(p, 1);
      ++n;
    }
  ASSERT_GT(n, 0);
  EXPECT_NEAR(sum / n, -rho * g * (H - 0.0125), 0.02 * rho * g * H);
}

// A run in which points leave the grid: a block thrown at 5 m/s towards
// the grid's right edge, beside one at rest. The run-out front is that of the points still
// on the grid, not the edge the lost ones stick at, and lostPoints.csv counts the lost ones
// (the solver warns of them too).
TEST(EndToEnd, PointsThatLeaveTheGridAreLeftOutAndCounted) {
  TempDir dir;
  const fs::path d = dir.path();
  write_files(d, {{"constant/materialProperties", kSoil},
                  {"constant/g", "value (0 0);\n"},
                  {"constant/bodies",
                   "rest { material soil; region { type rectangle; lower (0.1 0.4); upper (0.3 0.6); } "
                   "particlesPerCell 2; }\n"
                   "thrown { material soil; region { type rectangle; lower (0.6 0.4); upper (0.8 0.6); } "
                   "particlesPerCell 2; velocity (5 0); }\n"},
                  {"system/gridDict", "dimension 2;\nlower (0 0);\nupper (1 1);\ncellSize 0.1;\n"},
                  {"system/controlDict",
                   "endTime 0.2;\ndeltaT 1e-4;\nwriteControl adjustableRunTime;\nwriteInterval 0.1;\n"
                   "maxLostFraction 1;\nwriters {}\nfunctions { front { type runOut; origin (0 0); } }\n"}});
  const ScreeRun run = run_scree(d, " --device cpu --threads 2", d / "log.scree");
  ASSERT_EQ(run.rc, 0) << run.out;
  const fs::path pp = d / "postProcessing" / "front";
  const Csv front = read_csv(pp / "runOut.csv");
  ASSERT_EQ(front.rows.size(), 3u);  // t = 0, 0.1, 0.2
  EXPECT_EQ(front.num(0, "particles [-]"), 32);  // 2 x 2 cells of 2 x 2 points each, both blocks
  EXPECT_EQ(front.num(2, "particles [-]"), 16) << "the thrown block has left the grid (and its ghost nodes) by 0.2 s";
  EXPECT_LT(front.num(2, "runout [m]"), 0.3) << "the front of the block at rest, not the grid's edge";
  const Csv lost = read_csv(pp / "lostPoints.csv");
  ASSERT_FALSE(lost.rows.empty());
  EXPECT_EQ(lost.num(lost.rows.size() - 1, "time [s]"), 0.2);
  EXPECT_EQ(lost.num(lost.rows.size() - 1, "lost points [-]"), 16);
}

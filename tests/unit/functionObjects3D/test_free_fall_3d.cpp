// A 3D elastic block in free fall, run with the scree executable (CPU) with the vtk writer
// and the function objects. Nothing touches the block, so every particle moves with
// v = -g t: the kinetic energy is M g^2 t^2 / 2 (M = rho V = 8 kg), in J; the total
// (kinetic + potential) stays at M g z_c(0) but for the explicit integration's O(dt)
// error (|drift| <= M g^2 t dt); the horizontal positions do not change, so runOut along
// the diagonal (1 1 0) keeps the far corner's centre; the height field at t = 0 is the
// block's top within half a particle spacing; the .vtp files carry velocity (0 0 -g t)
// with 3 components and a stress of 6 components, zero in free fall.
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <cstdlib>

#include "test_util.hpp"

using namespace scree_test;

namespace {

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

constexpr double kG = 9.81, kDt = 1e-4, kRho = 1000;
constexpr double kMass = kRho * 0.2 * 0.2 * 0.2;  // the block [0.1, 0.3]^2 x [0.4, 0.6]

/// Cells of 0.1 m, 2 particles per cell and axis (spacing 0.05): 2 x 2 x 2 cells, 64
/// particles, far from the grid's faces over 0.05 s (a fall of 12 mm). No walls.
void write_case(const fs::path& dir) {
  write_file(dir / "constant" / "materialProperties", "soil { type linearElastic; E 1e6; nu 0.3; rho 1000; }\n");
  write_file(dir / "constant" / "g", "value (0 0 -9.81);\n");
  write_file(dir / "constant" / "bodies",
             "block { material soil; region { type box; lower (0.1 0.1 0.4); upper (0.3 0.3 0.6); } "
             "particlesPerCell 2; }\n");
  write_file(dir / "system" / "gridDict", "dimension 3;\nlower (0 0 0);\nupper (0.4 0.4 0.8);\ncellSize 0.1;\n");
  write_file(dir / "system" / "mpmSchemes", "updateScheme USF;\n");
  write_file(dir / "system" / "controlDict",
             "endTime 0.05;\ndeltaT 1e-4;\nwriteControl adjustableRunTime;\nwriteInterval 0.025;\n"
             "writers { vtk { type vtk; fields (velocity stress); } }\n"
             "functions {\n"
             "  energy { type energies; executeControl timeStep; executeInterval 100; }\n"
             "  front { type runOut; direction (1 1 0); }\n"
             "  profile { type surfaceProfile; binWidth 0.05; }\n"
             "}\n");
}

}  // namespace

TEST(FreeFall3D, EnergiesRunOutHeightFieldAndVtk) {
  TempDir dir;
  write_case(dir.path());
  const fs::path log = dir.path() / "log.scree";
  const ScreeRun run = run_scree(dir.path(), " --device cpu --threads 1", log);
  ASSERT_EQ(run.rc, 0) << run.out;
  const fs::path pp = dir.path() / "postProcessing";

  // energies: J in 3D; KE = M g^2 t^2 / 2; PE(0) = M g z_c with z_c = 0.5.
  const Csv e = read_csv(pp / "energy" / "energies.csv");
  const std::vector<std::string> header = {"time [s]", "kinetic [J]", "potential [J]", "total [J]"};
  EXPECT_EQ(e.header, header);
  ASSERT_EQ(e.rows.size(), 6u) << run.out;  // steps 0, 100, ..., 500
  EXPECT_NEAR(e.num(0, "potential [J]"), kMass * kG * 0.5, 1e-9);
  const double total0 = e.num(0, "total [J]");
  for (std::size_t r = 0; r < e.rows.size(); ++r) {
    const double t = e.num(r, "time [s]");
    EXPECT_NEAR(t, 0.01 * static_cast<double>(r), 1e-12);
    const double ke = 0.5 * kMass * kG * kG * t * t;
    EXPECT_NEAR(e.num(r, "kinetic [J]"), ke, 1e-9 * (1 + ke)) << "t = " << t;
    EXPECT_LE(std::fabs(e.num(r, "total [J]") - total0), kMass * kG * kG * t * kDt + 1e-9) << "t = " << t;
  }

  // runOut along (1 1 0)/sqrt2 from the origin: the far corner's centre (0.275 0.275).
  const Csv f = read_csv(pp / "front" / "runOut.csv");
  ASSERT_EQ(f.rows.size(), 3u);  // the write times 0, 0.025, 0.05
  for (std::size_t r = 0; r < f.rows.size(); ++r) {
    const double t = f.num(r, "time [s]");
    EXPECT_NEAR(f.num(r, "runout [m]"), 0.55 / std::sqrt(2.0), 1e-12) << "t = " << t;
    EXPECT_NEAR(f.num(r, "mass [kg]"), kMass, 1e-9);
    EXPECT_EQ(f.num(r, "particles [-]"), 64);
    // The top centre 0.575 falls g t^2 / 2, up to the integration's O(dt) g t dt.
    EXPECT_NEAR(f.num(r, "height [m]"), 0.575 - 0.5 * kG * t * t, kG * t * kDt + 1e-12) << "t = " << t;
    EXPECT_NEAR(f.num(r, "mean_velocity_z [m/s]"), -kG * t, 1e-9) << "t = " << t;
  }

  // The height field at t = 0: 4 x 4 bins of 0.05 over [0.1, 0.3]^2, each the top 0.6
  // within half the spacing (0.025), with its column of 4 particles.
  const Csv h = read_csv(pp / "profile" / "0.csv");
  const std::vector<std::string> hh = {"x [m]", "y [m]", "height [m]", "particles [-]"};
  EXPECT_EQ(h.header, hh);
  ASSERT_EQ(h.rows.size(), 16u);
  for (std::size_t r = 0; r < h.rows.size(); ++r) {
    EXPECT_NEAR(h.num(r, "x [m]"), 0.125 + 0.05 * static_cast<double>(r % 4), 1e-12);
    EXPECT_NEAR(h.num(r, "y [m]"), 0.125 + 0.05 * static_cast<double>(r / 4), 1e-12);
    EXPECT_LE(std::fabs(h.num(r, "height [m]") - 0.6), 0.025 + 1e-12) << r;
    EXPECT_EQ(h.num(r, "particles [-]"), 4) << r;
  }

  // The last .vtp: velocity (0 0 -g t) at every particle, stress of 6 components (zero).
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir.path() / "VTK" / "vtk_2.vtp").c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorCode(), 0u);
  vtkPolyData* pd = reader->GetOutput();
  ASSERT_EQ(pd->GetNumberOfPoints(), 64);
  vtkDataArray* v = pd->GetPointData()->GetArray("velocity");
  vtkDataArray* s = pd->GetPointData()->GetArray("stress");
  ASSERT_NE(v, nullptr);
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(v->GetNumberOfComponents(), 3);
  ASSERT_EQ(s->GetNumberOfComponents(), 6);
  EXPECT_STREQ(s->GetComponentName(4), "YZ");
  for (vtkIdType p = 0; p < pd->GetNumberOfPoints(); ++p) {
    EXPECT_NEAR(v->GetComponent(p, 0), 0.0, 1e-12);
    EXPECT_NEAR(v->GetComponent(p, 1), 0.0, 1e-12);
    EXPECT_NEAR(v->GetComponent(p, 2), -kG * 0.05, 1e-9);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(s->GetComponent(p, c), 0.0, 1e-6) << c;  // |stress| << rho g L = 2000 Pa
  }
}

// A user error in a function object constructed after the vtk writer and another
// function object (a 2-number direction in a 3D radial front): scree stops with a
// non-zero status naming the file, line and key, and the case is left as it was (no
// VTK/, no postProcessing/: the plugins constructed before it write nothing until the
// first output).
TEST(FreeFall3D, UserErrorStopsBeforeAnythingIsWritten) {
  TempDir dir;
  write_case(dir.path());
  write_file(dir.path() / "system" / "controlDict",
             "endTime 0.05;\ndeltaT 1e-4;\nwriteControl adjustableRunTime;\nwriteInterval 0.025;\n"
             "writers { vtk { type vtk; } }\n"
             "functions {\n"
             "  energy { type energies; }\n"
             "  front { type runOut; radial { centre (0.2 0.2 0); directions ((1 0 0) (0 1)); } }\n"
             "}\n");
  const fs::path log = dir.path() / ".." / (dir.path().filename().string() + ".log");
  for (const char* mode : {" --check", " --device cpu --threads 1"}) {
    const ScreeRun run = run_scree(dir.path(), mode, log);
    fs::remove(log);
    EXPECT_NE(run.rc, 0) << mode << ": " << run.out;
    EXPECT_NE(run.out.find("system/controlDict:8:"), std::string::npos) << mode << ": " << run.out;
    EXPECT_NE(run.out.find("radial.directions: element 2 must be a direction of 3 numbers"), std::string::npos)
        << mode << ": " << run.out;
    EXPECT_FALSE(fs::exists(dir.path() / "VTK")) << mode;
    EXPECT_FALSE(fs::exists(dir.path() / "postProcessing")) << mode;
  }
  // An error only the constructor can see (the default axis comes from gravity, +z here:
  // a direction along it): the run stops the same way, and the vtk writer and energies,
  // built before, have written nothing.
  write_file(dir.path() / "system" / "controlDict",
             "endTime 0.05;\ndeltaT 1e-4;\nwriteControl adjustableRunTime;\nwriteInterval 0.025;\n"
             "writers { vtk { type vtk; } }\n"
             "functions {\n"
             "  energy { type energies; }\n"
             "  front { type runOut; radial { centre (0.2 0.2 0); directions ((1 0 0) (0 0 1)); } }\n"
             "}\n");
  const ScreeRun run = run_scree(dir.path(), " --device cpu --threads 1", log);
  fs::remove(log);
  EXPECT_NE(run.rc, 0) << run.out;
  EXPECT_NE(run.out.find("system/controlDict:8:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("element 2 (0 0 1) is zero or parallel to the axis"), std::string::npos) << run.out;
  EXPECT_FALSE(fs::exists(dir.path() / "VTK"));
  EXPECT_FALSE(fs::exists(dir.path() / "postProcessing"));
}

// Case validation: every error of a case is reported together, each with
// file:line and what was expected, with a non-zero exit, before anything is written.
#include <cstdio>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>
#include <sstream>
#include <string>
#include <vector>

#include "scree_test.hpp"

namespace scree::test {
namespace {

struct Result {
  int status;
  std::string out, err;
};

Result run_scree(const std::string& args) {
  // Named after this process: test runs of other build trees may run beside this one.
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid());
  const auto out = dir / ("scree_test_stdout_" + tag + ".txt"), err = dir / ("scree_test_stderr_" + tag + ".txt");
  const std::string cmd = std::string(SCREE_BINARY_DIR) + "/bin/scree " + args + " >" + out.string() + " 2>" + err.string();
  const int rc = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  Result r{WEXITSTATUS(rc), slurp(out), slurp(err)};
  std::error_code ec;
  std::filesystem::remove(out, ec);
  std::filesystem::remove(err, ec);
  return r;
}

void write_valid_case(const TempCase& tc) {
  tc.write("system/controlDict",
           "FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }\n"
           "endTime 0.01;\ndeltaT 1e-3;\nwriteInterval 0.005;\n");
  tc.write("system/gridDict", "dimension 2;\nlower (0 0);\nupper (1 1);\ncellSize 0.1;\n");
  tc.write("constant/g", "value (0 -9.81);\n");
  tc.write("constant/materialProperties", "soil\n{\n    type linearElastic;\n    E 1e6;\n    nu 0.3;\n    rho 1000;\n}\n");
  tc.write("constant/bodies", "block\n{\n    material soil;\n    region { type rectangle; lower (0 0); upper (0.5 0.5); }\n}\n");
  tc.write("constant/boundaryConditions", "floor { type fixed; face yMin; }\n");
}

TEST(CaseErrors, ValidCaseChecksClean) {
  TempCase tc("valid");
  write_valid_case(tc);
  const Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 0) << r.err;
}

// A geostatic `surface` is one level for the body; `overburden all` is the material above
// each point: asking for both is an error at the surface's line, and an unknown overburden
// names the valid ones.
TEST(CaseErrors, GeostaticSurfaceWithOverburdenAllAndAnUnknownOverburden) {
  TempCase tc("overburden");
  write_valid_case(tc);
  tc.write("constant/bodies",
           "block\n{\n    material soil;\n    region { type rectangle; lower (0 0); upper (0.5 0.5); }\n"
           "    initialStress { type geostatic;\n        overburden all;\n        surface 0.6; }\n}\n"
           "top\n{\n    material soil;\n    region { type rectangle; lower (0 0.5); upper (0.5 0.7); }\n"
           "    initialStress { type geostatic; overburden crest; }\n}\n");
  const Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("constant/bodies:7:9: surface: a given level replaces the overburden"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("constant/bodies:13:37: overburden: 'crest' is not valid"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("expected one of: all, body"), std::string::npos) << r.err;
}

TEST(CaseErrors, MisspelledKeyOutOfRangeAndUnknownTypeAllReportedBeforeAnyOutput) {
  TempCase tc("broken");
  write_valid_case(tc);
  // line 2: unknown key (typo), line 3: out of range, and an unknown material type.
  tc.write("constant/materialProperties",
           "soil\n{\n    type linearElastic;\n    E 1e6;\n    nuu 0.3;\n    rho -1000;\n}\n"
           "clay\n{\n    type linearElastik;\n}\n");
  tc.write("constant/bodies", "block\n{\n    material soil;\n    region { type rectangle; lower (0 0); upper (0.5 0.5); }\n}\n");
  tc.write("system/controlDict",
           "endTime 0.01;\ndeltaT 1e-3;\nwriteInterval 0.005;\n"
           "writers { vtk { type vtk; } }\nfunctions { }\n");
  const Result r = run_scree("--case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  const std::string& e = r.err;
  EXPECT_NE(e.find("constant/materialProperties:5:5: unknown entry 'nuu'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'nu'?"), std::string::npos) << e;
  EXPECT_NE(e.find("constant/materialProperties:6:5: rho: expected a number > 0"), std::string::npos) << e;
  EXPECT_NE(e.find("constant/materialProperties:10:5: unknown material type 'linearElastik'; did you mean "
                   "'linearElastic'?"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("missing required entry 'nu'"), std::string::npos) << e;
  // Nothing was written.
  EXPECT_FALSE(std::filesystem::exists(tc.dir() / "VTK"));
  EXPECT_FALSE(std::filesystem::exists(tc.dir() / "postProcessing"));
}

TEST(CaseErrors, SyntaxErrorsOfSeveralFilesReportedTogether) {
  TempCase tc("syntax");
  write_valid_case(tc);
  tc.write("system/controlDict", "endTime 0.01\ndeltaT 1e-3;\nwriteInterval 0.005;\n");
  tc.write("system/gridDict", "dimension 2;\nlower (0 0;\n");
  const Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("system/gridDict:"), std::string::npos) << r.err;
}

TEST(CaseErrors, MissingCaseFilesAndBadCommandLine) {
  TempCase tc("empty");
  Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict: missing case file"), std::string::npos) << r.err;
  r = run_scree("--device gpu --case " + tc.dir().string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("expected cpu or cuda"), std::string::npos) << r.err;
}

TEST(CaseErrors, UnknownOutputFieldIsAnErrorWithItsLine) {
  TempCase tc("fields");
  write_valid_case(tc);
  tc.write("system/controlDict",
           "endTime 0.01;\ndeltaT 1e-3;\nwriteInterval 0.005;\n"
           "writers\n{\n    vtk { type vtk; fields (velocity presure stress); }\n}\n");
  const Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict:6:38: fields: no body of this case has a field 'presure'; did you mean "
                       "'pressure'?"),
            std::string::npos)
      << r.err;
}

/// The lines of `text` that report an error (file:line: ... or file: ...), without the
/// summary line.
std::vector<std::string> error_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l.rfind("scree:", 0) != 0) lines.push_back(l);
  return lines;
}

// A missing or unreadable constant/materialProperties also gave "constant/bodies:
// material 'soil' is not defined ... Defined: " (with an empty list) for every body. The
// cause is reported once.
TEST(CaseErrors, AMissingOrBrokenMaterialPropertiesIsReportedOnce) {
  TempCase tc("materials");
  write_valid_case(tc);
  std::filesystem::remove(tc.dir() / "constant/materialProperties");
  Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(error_lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("constant/materialProperties: missing case file"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("is not defined"), std::string::npos) << r.err;

  tc.write("constant/materialProperties", "soil\n{\n    type linearElastic;\n    E 1e6\n    nu 0.3;\n}\n");
  r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(error_lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("constant/materialProperties:4:10: expected ';' after the value of 'E'"), std::string::npos)
      << r.err;

  // A material entry that is not a dictionary is one error, not two.
  tc.write("constant/materialProperties", "soil 5;\n");
  r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(error_lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("constant/materialProperties:1:1: 'soil': expected a dictionary"), std::string::npos) << r.err;

  // A material that is really not defined is still reported, with the defined ones.
  tc.write("constant/materialProperties", "sand { type linearElastic; E 1e6; nu 0.3; rho 1000; }\n");
  r = run_scree("--check --case " + tc.dir().string());
  EXPECT_NE(r.err.find("constant/bodies:3:5: material: 'soil' is not defined in constant/materialProperties; "
                       "defined: sand"),
            std::string::npos)
      << r.err;
}

// Without a readable gridDict the dimension is unknown: a 3D case's vectors are not
// reported as "expected 2 components" one by one.
TEST(CaseErrors, AMissingGridDictIsReportedOnce) {
  TempCase tc("grid");
  write_valid_case(tc);
  tc.write("constant/g", "value (0 0 -9.81);\n");
  std::filesystem::remove(tc.dir() / "system/gridDict");
  const Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(error_lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("system/gridDict: missing case file"), std::string::npos) << r.err;
}

// writeControl timeStep with writeInterval 0.4 silently became "every step".
TEST(CaseErrors, AnIntervalInStepsMustBeAWholeNumber) {
  TempCase tc("steps");
  write_valid_case(tc);
  tc.write("system/controlDict",
           "endTime 0.01;\ndeltaT 1e-3;\nwriteControl timeStep;\nwriteInterval 0.4;\n"
           "writers { vtk { type vtk; } }\n"
           "functions\n{\n    e { type energies; executeControl timeStep; executeInterval 2.5; }\n"
           "    f { type energies; executeControl runTime; executeInterval 2.5e-3; }\n}\n");
  const Result r = run_scree("--case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict:4:1: writeInterval: with writeControl timeStep it counts steps: expected a "
                       "whole number of steps, at least 1, found 0.4"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("system/controlDict:8:49: executeInterval: with executeControl timeStep it counts steps"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(error_lines(r.err).size(), 2u) << r.err;  // runTime counts seconds: 2.5e-3 is fine
  EXPECT_FALSE(std::filesystem::exists(tc.dir() / "VTK"));
  tc.write("system/controlDict", "endTime 0.01;\ndeltaT 1e-3;\nwriteControl timeStep;\nwriteInterval 4;\n");
  EXPECT_EQ(run_scree("--check --case " + tc.dir().string()).status, 0);
}

// deltaT 1e-30 ran forever: the clock cannot add it to endTime.
TEST(CaseErrors, ATimeStepThatCannotEndTheRunIsAnError) {
  TempCase tc("deltaT");
  write_valid_case(tc);
  tc.write("system/controlDict", "endTime 3;\ndeltaT 1e-30;\nwriteInterval 0.5;\n");
  Result r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict:2:1: deltaT: a step of 1e-30 s cannot advance the clock"),
            std::string::npos)
      << r.err;
  tc.write("system/controlDict", "endTime 3;\ndeltaT 1e-4;\nadjustTimeStep yes;\nmaxDeltaT 1e-14;\nwriteInterval 0.5;\n");
  r = run_scree("--check --case " + tc.dir().string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("system/controlDict:4:1: maxDeltaT: a step of 1e-14 s needs 3e+14 steps"), std::string::npos)
      << r.err;
}

TEST(CaseErrors, ListPluginsDocumentsParameters) {
  const Result r = run_scree("--list-plugins material");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("linearElastic"), std::string::npos);
  EXPECT_NE(r.out.find("Young's modulus"), std::string::npos);
  EXPECT_NE(r.out.find("[Pa]"), std::string::npos);
}

}  // namespace
}  // namespace scree::test

// Functions of time (params/function_table.hpp, time/function_of_time.hpp): each form a
// dictionary may write, its units, a CSV file, the interpolations and what holds outside
// the table, against values worked out by hand; the running integral against the exact
// integral of the interpolant; and the errors a user can meet, each naming file and line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "scree/params/spec.hpp"
#include "scree/time/function_of_time.hpp"

namespace scree {
namespace {

ParamSpec rain_spec() {
  ParamSpec s("rain", "a rain");
  s.function("intensity", "m/s", "rain intensity").non_negative();
  s.function("velocity", "m/s", "a wall's velocity").size(-1).optional();
  return s;
}

FunctionTable read(const std::string& text, const std::filesystem::path& dir = {}, const FunctionDefaults& d = {},
                   const char* key = "intensity", int components = 1) {
  static ParamSpec spec = rain_spec();
  Dictionary dict = Dictionary::parse(text, "constant/boundaryConditions");
  return read_function_table(*spec.find(key), dict.at(key), components, dir, d);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string error_of(const std::string& text, const std::filesystem::path& dir = {}) {
  try {
    read(text, dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FunctionOfTime, AConstantIsTheSameAtEveryTime) {
  for (const char* text : {"intensity 2e-4;", "intensity constant 2e-4;", "intensity { type constant; value 2e-4; }"}) {
    const FunctionOfTime f(read(text));
    EXPECT_TRUE(f.is_constant()) << text;
    for (double t : {-5.0, 0.0, 3.0, 1e6}) EXPECT_EQ(f(t), 2e-4) << text;
    EXPECT_DOUBLE_EQ(f.integral(10), 2e-3) << text;  // from time 0
  }
}

TEST(FunctionOfTime, UnitsConvertToTheParametersSIUnit) {
  // 36 mm/h = 1e-5 m/s; hours of the table in seconds.
  const FunctionTable f = read("intensity { type table; values ((0 36) (2 72)); unit mm/h; timeUnit h; }");
  ASSERT_EQ(f.times.size(), 2u);
  EXPECT_DOUBLE_EQ(f.times[1], 7200);
  EXPECT_DOUBLE_EQ(f.values[0], 1e-5);
  EXPECT_DOUBLE_EQ(f.values[1], 2e-5);
  // The reader's default unit (rainfall's `unit` entry) applies when the entry names none.
  EXPECT_DOUBLE_EQ(read("intensity 3.6;", {}, {"mm/h"}).values[0], 1e-6);
}

TEST(FunctionOfTime, LinearAndStepInterpolationAndTheEnds) {
  const char* rows = "((1 10) (3 30) (4 0))";
  const FunctionOfTime lin(read(std::string("intensity table ") + rows + ";"));
  EXPECT_DOUBLE_EQ(lin(2), 20);    // halfway between 10 and 30
  EXPECT_DOUBLE_EQ(lin(3.5), 15);  // halfway between 30 and 0
  EXPECT_DOUBLE_EQ(lin(3), 30);    // on a row
  EXPECT_DOUBLE_EQ(lin(0), 10);    // clamped before the first row
  EXPECT_DOUBLE_EQ(lin(9), 0);     // and after the last
  const FunctionOfTime step(read(std::string("intensity { type table; values ") + rows +
                                 "; interpolation step; outOfBounds zero; }"));
  EXPECT_EQ(step(2.99), 10);  // the last row at or before t
  EXPECT_EQ(step(3), 30);
  EXPECT_EQ(step(0.5), 0);  // zero outside the table
  EXPECT_EQ(step(4.5), 0);
  const FunctionOfTime rep(read(std::string("intensity { type table; values ") + rows + "; outOfBounds repeat; }"));
  EXPECT_DOUBLE_EQ(rep(2 + 3), 20);   // one period (3 s) later
  EXPECT_DOUBLE_EQ(rep(2 - 6), 20);   // two periods earlier
}

TEST(FunctionOfTime, TheIntegralIsExactForTheInterpolant) {
  // v(t) = 10 + 10 (t - 1) on [1, 3], 30 - 30 (t - 3) on [3, 4]: the integral from 1 is
  // 10 (t-1) + 5 (t-1)^2 on [1, 3] (40 at 3) and 40 + 30 (t-3) - 15 (t-3)^2 beyond (55 at 4).
  const FunctionOfTime f(read("intensity table ((1 10) (3 30) (4 0));"));
  EXPECT_NEAR(f.integral(2), 15, 1e-12);
  EXPECT_NEAR(f.integral(3), 40, 1e-12);
  EXPECT_NEAR(f.integral(3.5), 40 + 15 - 3.75, 1e-12);
  EXPECT_NEAR(f.integral(4), 55, 1e-12);
  EXPECT_NEAR(f.integral(5), 55, 1e-12);  // clamped at 0 after the last row
  EXPECT_NEAR(f.integral(0), -10, 1e-12);  // clamped at 10 before the first
  const FunctionOfTime z(read("intensity { type table; values ((1 10) (3 30) (4 0)); outOfBounds zero; }"));
  EXPECT_EQ(z.integral(0.5), 0);
  const FunctionOfTime s(read("intensity { type table; values ((1 10) (3 30) (4 0)); interpolation step; }"));
  EXPECT_NEAR(s.integral(3.5), 20 + 15, 1e-12);  // 10 over [1, 3), 30 over [3, 3.5)
  const FunctionOfTime r(read("intensity { type table; values ((1 10) (3 30) (4 0)); outOfBounds repeat; }"));
  EXPECT_NEAR(r.integral(2 + 6), 2 * 55 + 15, 1e-12);  // two whole periods and 1 s
}

TEST(FunctionOfTime, AVectorFunctionHasOneValuePerComponent) {
  const FunctionOfTime f(read("velocity table ((0 (0 0)) (2 (0.2 -0.1)));", {}, {}, "velocity", 2));
  EXPECT_EQ(f.components(), 2);
  EXPECT_DOUBLE_EQ(f(1, 0), 0.1);
  EXPECT_DOUBLE_EQ(f(1, 1), -0.05);
}

struct TempDir {
  std::filesystem::path dir;
  TempDir() {
    dir = std::filesystem::temp_directory_path() / ("scree_fot_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir / "constant");
  }
  ~TempDir() { std::filesystem::remove_all(dir); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir / name) << text; }
};

TEST(FunctionOfTime, ACsvFileWithAHeaderAndComments) {
  TempDir d;
  d.write("constant/rain.csv",
          "# a hyetograph\n"
          "time_h, gauge, intensity_mm_per_h\n"
          "0, 7, 0\n"
          "1, 7, 36\n"
          "\n"
          "2, 7, 0\n");
  const FunctionTable f = read(
      "intensity { type csvFile; file \"constant/rain.csv\"; columns (time_h intensity_mm_per_h); timeUnit h; "
      "unit mm/h; }",
      d.dir);
  ASSERT_EQ(f.times.size(), 3u);
  EXPECT_DOUBLE_EQ(f.times[2], 7200);
  EXPECT_DOUBLE_EQ(FunctionOfTime(f)(1800), 0.5e-5);  // half of 36 mm/h, in m/s
  // Columns by index, whitespace-separated, no header.
  d.write("constant/rain.txt", "0 1 2\n10 11 12\n");
  const FunctionTable g =
      read("intensity { type csvFile; file \"constant/rain.txt\"; columns (0 2); separator \" \"; }", d.dir);
  EXPECT_DOUBLE_EQ(FunctionOfTime(g)(5), 7);
}

TEST(FunctionOfTime, ErrorsNameFileLineAndWhatIsValid) {
  // The dictionary's own errors, each at its line.
  EXPECT_PRED2(contains, error_of("\nintensity table ((0 1) (0 2));"), ("constant/boundaryConditions:2"));
  EXPECT_PRED2(contains, error_of("intensity table ((0 1) (0 2));"), ("times must increase strictly"));
  EXPECT_PRED2(contains, error_of("intensity table ((0 1) (1 -2));"), ("row 2"));
  EXPECT_PRED2(contains, error_of("intensity table ((0 1) (1 -2));"), (">= 0"));
  EXPECT_PRED2(contains, error_of("intensity { type table; values ((0 1)); unit mm/hr; }"), ("did you mean 'mm/h'"));
  EXPECT_PRED2(contains, error_of("intensity { type table; values ((0 1)); unit kg; }"), ("mm/h"));
  EXPECT_PRED2(contains, error_of("intensity { type tables; values ((0 1)); }"), ("did you mean 'table'"));
  EXPECT_PRED2(contains, error_of("intensity { type table; valuess ((0 1)); }"), ("did you mean 'values'"));
  EXPECT_PRED2(contains, error_of("intensity { type table; values ((0 1)); interpolation cubic; }"), ("linear, step"));
  EXPECT_PRED2(contains, error_of("intensity ten;"), ("expected a function of time"));
  EXPECT_PRED2(contains, error_of("intensity table ((0 (1 2)));"), ("expected a number as a row's value"));
  // A CSV file's errors name the file and its line.
  TempDir d;
  d.write("constant/bad.csv", "t,v\n0,1\n1,x\n");
  EXPECT_PRED2(contains, error_of("intensity { type csvFile; file \"constant/bad.csv\"; }", d.dir), ("constant/bad.csv:3"));
  EXPECT_PRED2(contains, error_of("intensity { type csvFile; file \"constant/bad.csv\"; columns (t value); }", d.dir),
              ("'t' 'v'"));
  EXPECT_PRED2(contains, error_of("intensity { type csvFile; file \"constant/none.csv\"; }", d.dir), ("cannot read"));
  // Whole-case validation finds the same errors through the spec (the file is read at setup).
  std::vector<InputError> errors;
  validate(rain_spec(), Dictionary::parse("intensity table ((1 1) (0 2));", "b"), errors, 2);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_PRED2(contains, std::string(errors[0].what()), ("b:1"));
  errors.clear();
  validate(rain_spec(), Dictionary::parse("intensity 1; velocity table ((0 (1 2 3)));", "b"), errors, 2);
  ASSERT_EQ(errors.size(), 1u);  // a vector of the case's dimension
  EXPECT_PRED2(contains, std::string(errors[0].what()), ("a vector of 2 numbers"));
}

TEST(FunctionOfTime, ListedWithItsFormsAndUnits) {
  const std::string doc = rain_spec().describe();
  EXPECT_PRED2(contains, doc, ("function of time"));
  EXPECT_PRED2(contains, doc, ("csvFile"));
  EXPECT_PRED2(contains, doc, ("mm/h"));
}

}  // namespace
}  // namespace scree

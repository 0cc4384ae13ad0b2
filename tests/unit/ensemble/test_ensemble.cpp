// Ensembles: the dictionary, the members' values and cases, the statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "scree/ensemble/ensemble.hpp"

namespace fs = std::filesystem;
using namespace scree;

namespace {

fs::path fresh_case(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("scree_test_ensemble_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "system");
  fs::create_directories(d / "constant");
  std::ofstream(d / "constant/materialProperties") << "sand\n{\n    type linearElastic;\n    E 1e6;  // [Pa]\n    nu 0.3;\n    rho 2000;\n}\n";
  std::ofstream(d / "constant/bodies") << "column { material sand; region { type rectangle; lower (0 0); upper (0.2 0.1); } }\n";
  std::ofstream(d / "system/controlDict") << "endTime 1;\n";
  std::ofstream(d / "constant/column.xy") << "0 0\n0.1 0\n";  // a data file: copied as it is
  return d;
}

void write(const fs::path& f, const std::string& text) { std::ofstream(f) << text; }

std::string slurp(const fs::path& f) {
  std::ifstream in(f);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// The errors of reading the case's ensembleDict, one per line.
std::string errors_of(const fs::path& d) {
  try {
    EnsembleSpec::read(d);
  } catch (const InputErrors& e) {
    return e.what();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

EnsembleParameter law(EnsembleParameter::Law l, double mean, double sd, double lower, double upper) {
  EnsembleParameter p;
  p.kind = EnsembleParameter::Kind::distribution;
  p.law = l;
  p.mean = mean;
  p.sd = sd;
  p.lower = lower;
  p.upper = upper;
  return p;
}

}  // namespace

// The inverse distribution function is the normal's to double precision: Phi(x(p)) = p.
TEST(Ensemble, NormalQuantileInvertsTheDistributionFunction) {
  const EnsembleParameter p = law(EnsembleParameter::Law::normal, 0, 1, -1e300, 1e300);
  for (double u : {1e-12, 1e-6, 0.01, 0.02425, 0.2, 0.5, 0.8, 0.97575, 0.999, 1 - 1e-9}) {
    const double x = p.quantile(u);
    EXPECT_NEAR(0.5 * std::erfc(-x / std::sqrt(2.0)), u, 4e-16 + 1e-13 * u) << "u = " << u;
  }
  EXPECT_NEAR(p.quantile(0.975), 1.959963984540054, 1e-13);  // the tabulated 97.5% point
}

// Draws of the members of an ensemble: their mean and standard deviation against the
// distributions' own (truncated normal: the closed-form moments), within four standard
// errors of the sample (a failure by chance has a probability below 1e-4).
TEST(Ensemble, DrawsHaveTheirDistributionsMoments) {
  const fs::path d = fresh_case("moments");
  write(d / "system/ensembleDict",
        "seed 11; samples 20000;\n"
        "parameters {\n"
        "  E  { file constant/materialProperties; entry sand/E; distribution { type lognormal; mean 2e6; standardDeviation 5e5; } }\n"
        "  nu { file constant/materialProperties; entry sand/nu; distribution { type normal; mean 0.3; standardDeviation 0.05; lower 0.25; upper 0.4; } }\n"
        "  rho { file constant/materialProperties; entry sand/rho; distribution { type uniform; lower 1800; upper 2200; } }\n"
        "}\n");
  const EnsembleSpec s = EnsembleSpec::read(d);
  ASSERT_EQ(s.members(), 20000);
  std::vector<std::vector<double>> x(3);
  for (std::int64_t k = 0; k < s.members(); ++k) {
    const auto v = s.member_values(k);
    for (int i = 0; i < 3; ++i) x[i].push_back(std::stod(v[i]));
  }
  auto phi = [](double z) { return std::exp(-z * z / 2) / std::sqrt(2 * M_PI); };
  auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  // truncated normal on [a, b] (standardised alpha, beta): mean mu + sd (phi(a) - phi(b)) / Z,
  // variance sd^2 (1 + (a phi(a) - b phi(b)) / Z - ((phi(a) - phi(b)) / Z)^2)
  const double a = (0.25 - 0.3) / 0.05, b = (0.4 - 0.3) / 0.05, Z = Phi(b) - Phi(a);
  const double tn_mean = 0.3 + 0.05 * (phi(a) - phi(b)) / Z;
  const double tn_sd = 0.05 * std::sqrt(1 + (a * phi(a) - b * phi(b)) / Z - std::pow((phi(a) - phi(b)) / Z, 2));
  const double want_mean[] = {2e6, tn_mean, 2000}, want_sd[] = {5e5, tn_sd, 400 / std::sqrt(12.0)};
  for (int i = 0; i < 3; ++i) {
    const SampleStats st = sample_stats(x[i]);
    const double se = want_sd[i] / std::sqrt(static_cast<double>(st.n));
    EXPECT_NEAR(st.mean, want_mean[i], 4 * se) << "parameter " << i;
    // the standard deviation's standard error, sd sqrt((kurtosis - 1) / (4 n)): the normal's
    // kurtosis is 3, the uniform's 1.8, the lognormal's 3 + e^(4s^2) + 2 e^(3s^2) + 3 e^(2s^2) - 6
    // (s^2 = ln(1 + (sd/mean)^2)); the truncated normal's, below 3, taken as 3
    const double s2 = std::log1p(0.25 * 0.25);
    const double kurtosis[] = {std::exp(4 * s2) + 2 * std::exp(3 * s2) + 3 * std::exp(2 * s2) - 3, 3, 1.8};
    EXPECT_NEAR(st.sd, want_sd[i], 4 * want_sd[i] * std::sqrt((kurtosis[i] - 1) / (4.0 * static_cast<double>(st.n))))
        << "parameter " << i;
  }
  EXPECT_GE(sample_stats(x[1]).min, 0.25);
  EXPECT_LE(sample_stats(x[1]).max, 0.4);
  EXPECT_GT(sample_stats(x[0]).min, 0);
  fs::remove_all(d);
}

// Listed values make every combination, the last parameter fastest, times the samples; a
// member's draw depends on the seed, the parameter and the member only.
TEST(Ensemble, MembersAreTheCombinationsTimesTheSamples) {
  const fs::path d = fresh_case("members");
  write(d / "system/ensembleDict",
        "seed 3; samples 2;\n"
        "parameters {\n"
        "  E  { file constant/materialProperties; entry sand/E; values (1e6 2e6 3e6); }\n"
        "  nu { file constant/materialProperties; entry sand/nu; range { from 0.2; to 0.3; count 2; } }\n"
        "  rho { file constant/materialProperties; entry sand/rho; distribution { type uniform; lower 1; upper 2; } }\n"
        "}\n");
  const EnsembleSpec s = EnsembleSpec::read(d);
  ASSERT_EQ(s.members(), 12);
  EXPECT_EQ(s.member_values(0)[0], "1e6");
  EXPECT_EQ(s.member_values(0)[1], "0.2");
  EXPECT_EQ(s.member_values(1)[1], "0.2");  // the second sample of the same combination
  EXPECT_EQ(s.member_values(2)[1], "0.3");
  EXPECT_EQ(s.member_values(4)[0], "2e6");
  EXPECT_EQ(s.member_values(11)[0], "3e6");
  EXPECT_EQ(s.member_values(11)[1], "0.3");
  EXPECT_NE(s.member_values(0)[2], s.member_values(1)[2]);
  write(d / "system/ensembleDict",
        "seed 3; samples 2;\n"
        "parameters {\n"
        "  rho { file constant/materialProperties; entry sand/rho; distribution { type uniform; lower 1; upper 2; } }\n"
        "}\n");
  EXPECT_EQ(EnsembleSpec::read(d).member_values(1)[0], s.member_values(1)[2]);
  fs::remove_all(d);
}

// Every mistake in ensembleDict is named at its line, with what is valid.
TEST(Ensemble, DictionaryErrorsNameTheirLines) {
  const fs::path d = fresh_case("errors");
  auto check = [&](const std::string& text, const std::string& where, const std::string& what) {
    write(d / "system/ensembleDict", text);
    const std::string e = errors_of(d);
    EXPECT_NE(e.find(where), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  check("parameters { E { file constant/materialProperties; entry sand/E; values (1 2); } }\nmembers 5;\n",
        "system/ensembleDict:2:1", "unknown entry 'members' in system/ensembleDict (valid: seed, samples");
  check("parameters\n{\n  E { file constant/nothing; entry sand/E; values (1 2); }\n}\n", "system/ensembleDict:3:",
        "file constant/nothing is not a file of the case");
  check("parameters\n{\n  E { file constant/materialProperties; entry clay/E; values (1 2); }\n}\n",
        "system/ensembleDict:3:", "has no dictionary 'clay' (its dictionaries there: sand)");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand; values (1 2); }\n}\n",
        "system/ensembleDict:3:", "entry sand is a dictionary");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand/E;\n distribution { type weibull; } }\n}\n",
        "system/ensembleDict:4:", "unknown distribution type 'weibull' (valid: uniform, normal, lognormal)");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand/E;\n distribution { type normal; mean 1; standardDeviation 0; } }\n}\n",
        "system/ensembleDict:4:", "standardDeviation must be > 0");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand/E; values (1); range { from 1; to 2; count 3; } }\n}\n",
        "system/ensembleDict:3:", "give exactly one of values");
  check("samples 4;\nparameters { E { file constant/materialProperties; entry sand/E; values (1 2); } }\n",
        "system/ensembleDict:1:", "no parameter has one");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand/E; values (1 2); }\n"
        "  F { file constant/materialProperties; entry sand/E; values (3 4); }\n}\n",
        "system/ensembleDict:4:", "another parameter sets constant/materialProperties sand/E");
  check("parameters { E { file constant/materialProperties; entry sand/E; values (1 2); } }\n"
        "summary\n{\n  r { file postProcessing/front/runOut.csv; column runout; at last; }\n}\n",
        "system/ensembleDict:4:", "at: expected end, max, min or a time in seconds, found 'last'");
  check("parameters\n{\n  E { file constant/materialProperties; entry sand/E; values (1 2); }\n}\n"
        "summary\n{\n  E { file postProcessing/front/runOut.csv; column runout; }\n}\n",
        "system/ensembleDict:7:", "summary quantity 'E' has the name of a parameter");
  write(d / "constant/materialProperties", "_E 1e6;\nsand { type linearElastic; E $_E; nu 0.3; rho 2000; }\n");
  check("parameters\n{\n  E { file constant/materialProperties; entry _E; values (1 2); }\n}\n", "system/ensembleDict:3:",
        "_E is used as $_E in constant/materialProperties:2");
  fs::remove_all(d);
}

// A member's case: its dictionaries written out whole, the value set and nothing else
// changed (each file reads back as the base's dictionary with that one entry replaced),
// data files copied byte for byte, the ensemble's own dictionary left out.
TEST(Ensemble, AMemberCaseIsTheBaseWithItsValues) {
  const fs::path d = fresh_case("member");
  write(d / "system/ensembleDict",
        "parameters {\n"
        "  E   { file constant/materialProperties; entry sand/E; values (5e6 7.5e6); }\n"
        "  top { file constant/bodies; entry column/region/upper; values ((0.2 0.1) (0.2 0.3)); }\n"
        "}\n");
  const EnsembleSpec s = EnsembleSpec::read(d);
  const fs::path m = d / "member";
  write_member_case(d, s, 3, m);
  const Dictionary mat = Dictionary::read_file(m / "constant/materialProperties");
  EXPECT_EQ(mat.sub("sand").at("E").value_string(), "7.5e6");
  EXPECT_EQ(mat.sub("sand").get_scalar("nu"), 0.3);
  EXPECT_EQ(mat.sub("sand").get_word("type"), "linearElastic");
  const Dictionary bodies = Dictionary::read_file(m / "constant/bodies");
  EXPECT_EQ(bodies.sub("column").sub("region").at("upper").value_string(), "(0.2 0.3)");
  EXPECT_EQ(bodies.sub("column").sub("region").at("lower").value_string(), "(0 0)");
  EXPECT_EQ(Dictionary::read_file(m / "system/controlDict").to_string(),
            Dictionary::read_file(d / "system/controlDict").to_string());
  EXPECT_EQ(slurp(m / "constant/column.xy"), slurp(d / "constant/column.xy"));
  EXPECT_FALSE(fs::exists(m / "system/ensembleDict"));
  // writers no: the members' controlDict without its writers, the rest as it was
  write(d / "system/controlDict", "endTime 1;\nwriters { particles { type vtk; } }\nfunctions { f { type runOut; } }\n");
  write(d / "system/ensembleDict",
        "writers no;\nparameters { E { file constant/materialProperties; entry sand/E; values (5e6); } }\n");
  write_member_case(d, EnsembleSpec::read(d), 0, m);
  const Dictionary control = Dictionary::read_file(m / "system/controlDict");
  EXPECT_EQ(control.sub("writers").entries().size(), 0u);
  EXPECT_EQ(control.sub("functions").sub("f").get_word("type"), "runOut");
  EXPECT_EQ(control.get_scalar("endTime"), 1);
  fs::remove_all(d);
}

// The summary's percentiles are numpy's default (linear between order statistics).
TEST(Ensemble, SampleStatisticsAsNumpyGivesThem) {
  const SampleStats s = sample_stats({4, 1, 3, 2, 10});
  EXPECT_EQ(s.n, 5u);
  EXPECT_DOUBLE_EQ(s.mean, 4);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt(12.5));  // numpy.std(x, ddof=1)
  EXPECT_DOUBLE_EQ(s.p50, 3);
  EXPECT_DOUBLE_EQ(s.p25, 2);
  EXPECT_DOUBLE_EQ(s.p75, 4);
  EXPECT_DOUBLE_EQ(s.p05, 1.2);   // numpy.percentile(x, 5)
  EXPECT_DOUBLE_EQ(s.p95, 8.8);
}

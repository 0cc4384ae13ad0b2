// The parameter specs of the granular materials: the
// paper's parameter sets pass them, every documented range refuses a value outside it with
// the entry's file:line, and the listing (`scree --list-plugins`) gives typical values.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "kineticTheory/KineticTheory.hpp"
#include "phaseTransition/PhaseTransition.hpp"
#include "scree/io/dictionary.hpp"
#include "scree/params/spec.hpp"
#include "simsand/Simsand.hpp"

using namespace scree;
using namespace scree::materials;

namespace {

struct Set {
  const char* name;
  ParamSpec spec;
  std::vector<std::pair<std::string, std::string>> entries;  // one per line, in order
};

std::string text_of(const Set& s) {
  std::string t;
  for (const auto& [k, v] : s.entries) t += k + " " + v + ";\n";
  return t;
}

std::vector<InputError> errors_of(const ParamSpec& spec, const std::string& text) {
  const Dictionary d = Dictionary::parse(text, "materialProperties");
  std::vector<InputError> errors;
  validate(spec, d, errors);
  return errors;
}

using Entries = std::vector<std::pair<std::string, std::string>>;
// The frictional part of the paper's Table 3 columns and of Table 1 (Fig. 4).
const Entries kElementF = {{"referenceBulkModulus", "120"}, {"poissonRatio", "0.235"}, {"elasticExponent", "0.5"},
                           {"criticalFrictionAngle", "23"}, {"referenceCriticalVoidRatio", "0.910"},
                           {"criticalStateLambda", "0.122"}, {"criticalStateXi", "0.71"}, {"dilatancyConstant", "0.5"},
                           {"plasticModulusConstant", "0.001"}, {"peakStrengthExponent", "1"},
                           {"phaseTransformationExponent", "1"}, {"initialVoidRatio", "1.05"}};
const Entries kCollapseF = {{"referenceBulkModulus", "120"}, {"poissonRatio", "0.2"}, {"elasticExponent", "0.5"},
                            {"atmosphericPressure", "101300"}, {"criticalFrictionAngle", "19.8"},
                            {"referenceCriticalVoidRatio", "0.977"}, {"criticalStateLambda", "0.0596"},
                            {"criticalStateXi", "0.365"}, {"dilatancyConstant", "0.7"},
                            {"plasticModulusConstant", "0.0044"}, {"peakStrengthExponent", "2.4"},
                            {"phaseTransformationExponent", "2.9"}, {"initialVoidRatio", "0.95"},
                            {"integrationTolerance", "1e-2"}, {"minPressure", "1"}, {"lodeDependence", "sheng"}};
const Entries kFlumeF = {{"referenceBulkModulus", "130"}, {"poissonRatio", "0.2"}, {"elasticExponent", "0.5"},
                         {"criticalFrictionAngle", "38"}, {"referenceCriticalVoidRatio", "0.977"},
                         {"criticalStateLambda", "0.0596"}, {"criticalStateXi", "0.365"}, {"dilatancyConstant", "0.4"},
                         {"plasticModulusConstant", "0.0044"}, {"peakStrengthExponent", "2.4"},
                         {"phaseTransformationExponent", "2.9"}, {"initialVoidRatio", "0.90"}};
const Entries kTable1 = {{"referenceBulkModulus", "150"}, {"poissonRatio", "0.22"}, {"elasticExponent", "0.6"},
                         {"criticalFrictionAngle", "30"}, {"referenceCriticalVoidRatio", "0.937"},
                         {"criticalStateLambda", "0.022"}, {"criticalStateXi", "0.71"}, {"dilatancyConstant", "4"},
                         {"plasticModulusConstant", "0.001"}, {"peakStrengthExponent", "1"},
                         {"phaseTransformationExponent", "1"}, {"initialVoidRatio", "0.80"}};

Entries with(Entries a, const Entries& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::vector<Set> paper_sets() {
  return {
      {"simsand, Table 3 element test", Simsand::spec(), with({{"particleDensity", "1050"}}, kElementF)},
      {"simsand, Table 3 column collapse", Simsand::spec(), with({{"particleDensity", "2650"}}, kCollapseF)},
      {"simsand, Table 3 flume", Simsand::spec(), with({{"particleDensity", "2500"}}, kFlumeF)},
      {"simsand, Table 1", Simsand::spec(), with({{"particleDensity", "2650"}}, kTable1)},
      {"phaseTransition, Table 3 element test", PhaseTransition::spec(),
       with({{"particleDensity", "1050"}, {"diameter", "1e-3"}, {"voidRatioSd", "0.92"}, {"solidFractionM", "0.4"},
             {"restitutionCoefficient", "0.7"}, {"particleFriction", "0.1"}},
            kElementF)},
      {"phaseTransition, Table 3 column collapse", PhaseTransition::spec(),
       with({{"particleDensity", "2650"}, {"diameter", "1.25e-3"}, {"voidRatioSd", "0.62"}, {"solidFractionM", "0.4"},
             {"restitutionCoefficient", "0.6"}, {"particleFriction", "0.2"}, {"initialGranularTemperature", "1e-12"}},
            kCollapseF)},
      {"phaseTransition, Table 3 flume", PhaseTransition::spec(),
       with({{"particleDensity", "2500"}, {"diameter", "1e-3"}, {"voidRatioSd", "0.60"}, {"solidFractionM", "0.4"},
             {"restitutionCoefficient", "0.6"}, {"particleFriction", "0.2"}},
            kFlumeF)},
      {"kineticTheory, Table 2", KineticTheory::spec(),
       {{"particleDensity", "1500"}, {"diameter", "1e-3"}, {"solidFractionSd", "0.6"}, {"solidFractionM", "0.4"},
        {"restitutionCoefficient", "0.6"}, {"particleFriction", "0.2"}, {"initialVoidRatio", "0.8"}}},
  };
}

TEST(MaterialSpecs, PaperParameterSetsPass) {
  for (const Set& s : paper_sets()) {
    const std::vector<InputError> errors = errors_of(s.spec, text_of(s));
    EXPECT_TRUE(errors.empty()) << s.name << ": " << (errors.empty() ? "" : errors.front().what());
  }
}

// Every bounded number of every set, replaced by a value just outside its range, is refused
// once, at its own line, naming the entry and the range.
TEST(MaterialSpecs, OutOfRangeValuesAreRefusedAtTheirLine) {
  int refused = 0;
  for (const Set& s : paper_sets()) {
    for (std::size_t i = 0; i < s.entries.size(); ++i) {
      const Param* p = s.spec.find(s.entries[i].first);
      ASSERT_NE(p, nullptr) << s.entries[i].first;
      if (p->type() != ParamType::scalar || !(p->lower() || p->upper())) continue;
      for (const double bad : {p->lower() ? *p->lower() - 1 - std::abs(*p->lower()) : 0.0,
                               p->upper() ? *p->upper() * 2 + 1 : 0.0}) {
        if (bad == 0.0) continue;
        Set t = s;
        t.entries[i].second = std::to_string(bad);
        const std::vector<InputError> errors = errors_of(t.spec, text_of(t));
        ASSERT_EQ(errors.size(), 1u) << s.name << ", " << p->name() << " " << bad;
        const std::string what = errors.front().what();
        EXPECT_EQ(what.rfind("materialProperties:" + std::to_string(i + 1) + ":", 0), 0u) << what;
        EXPECT_NE(what.find(p->name() + ": expected " + p->expectation()), std::string::npos) << what;
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 150);
}

// The listing a user reads first says what values to expect for each parameter of the model.
TEST(MaterialSpecs, ListingGivesTypicalValues) {
  for (const ParamSpec& spec : {Simsand::spec(), PhaseTransition::spec()}) {
    for (const char* key :
         {"referenceBulkModulus", "poissonRatio", "elasticExponent", "criticalFrictionAngle",
          "referenceCriticalVoidRatio", "criticalStateLambda", "criticalStateXi", "dilatancyConstant",
          "plasticModulusConstant", "peakStrengthExponent", "phaseTransformationExponent", "initialVoidRatio",
          "particleDensity", "integrationTolerance"}) {
      const Param* p = spec.find(key);
      ASSERT_NE(p, nullptr) << key;
      EXPECT_NE(p->doc().find("typical"), std::string::npos) << spec.name() << " " << key;
      EXPECT_TRUE(p->lower() || p->upper()) << spec.name() << " " << key;
    }
    EXPECT_NE(spec.describe().find("typical 100-200 for sands"), std::string::npos);
  }
  for (const char* key : {"diameter", "voidRatioSd", "solidFractionSd", "solidFractionM", "restitutionCoefficient",
                          "particleFriction"})
    EXPECT_NE(PhaseTransition::spec().find(key)->doc().find("typical"), std::string::npos) << key;
}

}  // namespace

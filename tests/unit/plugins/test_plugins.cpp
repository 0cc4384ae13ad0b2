// The plugin runtime: loading, ABI check, errors, and kernels of the same template in
// two plugins each running their own body (on the CPU, and on the GPU with --device=cuda).
#include <boost/dll/shared_library.hpp>

#include "scree_test.hpp"

namespace scree::test {
namespace {

const std::string kTestLibs = SCREE_TEST_PLUGIN_DIR;

TEST(PluginRuntime, DefaultPluginsProvideEveryKind) {
  PluginRuntime& rt = runtime();
  EXPECT_NE(rt.registry().find(PluginKind::material, "linearElastic"), nullptr);
  EXPECT_NE(rt.registry().find(PluginKind::boundaryCondition, "fixed"), nullptr);
  EXPECT_NE(rt.registry().find(PluginKind::boundaryCondition, "slip"), nullptr);
}

TEST(PluginRuntime, UnknownTypeListsValidNamesAndNearMiss) {
  try {
    runtime().registry().get(PluginKind::material, "linearElastik", SourceLocation{std::make_shared<std::string>("f"), 3, 7});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("f:3:7"), std::string::npos) << w;
    EXPECT_NE(w.find("did you mean 'linearElastic'"), std::string::npos) << w;
    EXPECT_NE(w.find("Valid types:"), std::string::npos) << w;
  }
}

TEST(PluginRuntime, RefusesAnotherAbiVersionWithAClearMessage) {
  PluginRuntime rt;
  try {
    rt.load(kTestLibs + "/libscree_test_bad_abi.so", SourceLocation{std::make_shared<std::string>("system/controlDict"), 4, 6});
    FAIL() << "loaded a plugin of another ABI";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("system/controlDict:4:6"), std::string::npos) << w;
    EXPECT_NE(w.find("ABI version 999"), std::string::npos) << w;
    EXPECT_NE(w.find("ABI version " + std::to_string(kPluginAbiVersion)), std::string::npos) << w;
  }
}

TEST(PluginRuntime, RefusesALibraryThatIsNotAPlugin) {
  PluginRuntime rt;
  EXPECT_THROW(rt.load(kTestLibs + "/libscree_test_not_a_plugin.so"), InputError);
  EXPECT_THROW(rt.load("libdoes_not_exist.so"), InputError);
}

// A file named like a plugin that is not a shared object (a text file): the dynamic
// loader's reason, once, without the errno text that Boost.DLL's exception appends (it
// ended with ": Bad file descriptor").
TEST(PluginRuntime, AFileThatIsNotASharedObjectGetsTheLoadersReason) {
  TempCase tc("not_a_shared_object");
  const std::filesystem::path lib = tc.dir() / "libtext.so";
  std::ofstream(lib) << "not a shared object\n";
  PluginRuntime rt;
  try {
    rt.load(lib.string(), SourceLocation{std::make_shared<std::string>("system/controlDict"), 2, 7});
    FAIL() << "loaded a text file";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("system/controlDict:2:7: cannot load plugin library '" + lib.string() + "'"), std::string::npos)
        << w;
    EXPECT_NE(w.find("not a shared object"), std::string::npos) << w;
    EXPECT_EQ(w.find("Bad file descriptor"), std::string::npos) << w;
    EXPECT_EQ(w.find("boost"), std::string::npos) << w;
  }
}

TEST(PluginRuntime, SameKernelTemplateInTwoLibrariesRunsEachOwnBody) {
  const Device dev = test_device();
  boost::dll::shared_library a(kTestLibs + "/libscree_test_fill_a.so");
  boost::dll::shared_library b(kTestLibs + "/libscree_test_fill_b.so");
  auto fa = a.get<void(int, double*, long long)>("scree_test_fill");
  auto fb = b.get<void(int, double*, long long)>("scree_test_fill");
  const long long n = 1000;
  Buffer<double> buf(n, dev);
  for (int round = 0; round < 2; ++round) {  // alternate, in both orders
    fa(dev == Device::cuda, buf.data(), n);
    for (double x : buf.to_host()) ASSERT_EQ(x, 1.0) << "library A ran the wrong kernel";
    fb(dev == Device::cuda, buf.data(), n);
    for (double x : buf.to_host()) ASSERT_EQ(x, 2.0) << "library B ran the wrong kernel";
  }
}

}  // namespace
}  // namespace scree::test

SCREE_TEST_MAIN()

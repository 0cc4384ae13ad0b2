// A library that looks like a plugin but was "built for" another ABI version.
#include <boost/config.hpp>
namespace scree { class Registry; }
extern "C" BOOST_SYMBOL_EXPORT int scree_plugin_abi_v1() { return 999; }
extern "C" BOOST_SYMBOL_EXPORT void scree_register_v1(scree::Registry&) {}

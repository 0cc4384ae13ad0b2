// A shared library without Scree's entry points.
#include <boost/config.hpp>
extern "C" BOOST_SYMBOL_EXPORT int something_else() { return 1; }

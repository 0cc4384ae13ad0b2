#include <boost/config.hpp>
#define SCREE_TEST_FILL_VALUE 2.0
#include "same_kernel.hpp"

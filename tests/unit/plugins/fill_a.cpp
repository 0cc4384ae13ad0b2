#include <boost/config.hpp>
#define SCREE_TEST_FILL_VALUE 1.0
#include "same_kernel.hpp"

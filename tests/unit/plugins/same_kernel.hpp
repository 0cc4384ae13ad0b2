// A kernel template that two test plugins instantiate with DIFFERENT bodies (the macro
// SCREE_TEST_FILL_VALUE differs). Without hidden visibility the dynamic linker (or the
// CUDA runtime's kernel registration) may bind both libraries to one instantiation, and
// one library would silently run the other's kernel (../shared/gpu/README.md).
#pragma once

#include "scree/exec/parallel.hpp"

namespace scree_test {

template <int N>
struct Fill {
  double* out;
  SCREE_HD void operator()(scree::Index i) const { out[i] = SCREE_TEST_FILL_VALUE + 0 * N; }
};

}  // namespace scree_test

/// Exported entry: fill n doubles in `out` (memory of device d) with this library's value.
extern "C" BOOST_SYMBOL_EXPORT void scree_test_fill(int device, double* out, long long n) {
  scree::Exec ex;
  ex.device = device ? scree::Device::cuda : scree::Device::cpu;
  scree::parallel_for(ex, n, scree_test::Fill<1>{out});
  scree::mem::synchronize(ex.device);
}

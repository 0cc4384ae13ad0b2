// One source, two backends: parallel loops over particles or grid nodes.
//
//   parallel_for(exec, n, f)   calls f(i) for i in [0, n):
//     Device::cuda -> a CUDA kernel launch on exec.stream (only from code compiled by
//                     nvcc; kernels are templates, instantiated in the plugin or core
//                     translation unit that launches them);
//     Device::cpu  -> an OpenMP loop with exec.threads threads.
//
// f is a functor (or an extended lambda) whose operator() is SCREE_HD. Nothing
// virtual is called inside f: materials are template parameters of the functors.
#pragma once

#include <stdexcept>
#include <string>

#include "scree/core/config.hpp"
#include "scree/exec/memory.hpp"

#if defined(__CUDACC__)
#include <cuda_runtime.h>
#endif

namespace scree {

/// Where and how a kernel runs. `stream` is a cudaStream_t (nullptr: default stream).
struct Exec {
  Device device = Device::cpu;
  void* stream = nullptr;
  int threads = 1;  ///< CPU threads (OpenMP); ignored on CUDA
};

/// Throw a std::runtime_error naming `what` if the last CUDA call or launch failed.
SCREE_API void check_cuda_launch(const char* what);

#if defined(__CUDACC__)
namespace detail {
template <class F>
__global__ void for_each_kernel(Index n, F f) {
  const Index i = Index(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}
}  // namespace detail
#endif

inline constexpr int kCudaBlockSize = 256;

template <class F>
void parallel_for(const Exec& ex, Index n, const F& f) {
  if (n <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    const Index blocks = (n + kCudaBlockSize - 1) / kCudaBlockSize;
    detail::for_each_kernel<<<static_cast<unsigned>(blocks), kCudaBlockSize, 0,
                              static_cast<cudaStream_t>(ex.stream)>>>(n, f);
    check_cuda_launch("parallel_for");
#else
    throw std::logic_error(
        "parallel_for: a CUDA launch was requested from a translation unit compiled "
        "without CUDA (compile this source with the CUDA language)");
#endif
  } else {
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(ex.threads > 0 ? ex.threads : 1)
#endif
    for (Index i = 0; i < n; ++i) f(i);
  }
}

/// Atomic a += v on either backend. On the CPU it is a plain add when the loop runs on
/// one thread (`serial`), so single-threaded runs pay nothing for atomics.
SCREE_INLINE void atomic_add(Real* a, Real v, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  atomicAdd(a, v);
#else
  if (serial) {
    *a += v;
  } else {
#pragma omp atomic
    *a += v;
  }
#endif
}

/// Atomic ++a on a counter.
SCREE_INLINE void atomic_increment(unsigned long long* a, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  atomicAdd(a, 1ull);
#else
  if (serial) ++*a;
  else __atomic_fetch_add(a, 1ull, __ATOMIC_RELAXED);
#endif
}

/// Atomic a = max(a, v) for non-negative doubles (their bit patterns order like
/// unsigned integers), used for the largest wave speed of a step.
SCREE_INLINE void atomic_max_nonneg(Real* a, Real v, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  atomicMax(reinterpret_cast<unsigned long long*>(a), __double_as_longlong(v));
#else
  if (serial) {
    if (v > *a) *a = v;
  } else {
    // CAS loop on the bit pattern; a plain load when v is not larger (the common case).
    auto* bits = reinterpret_cast<unsigned long long*>(a);
    unsigned long long cur = __atomic_load_n(bits, __ATOMIC_RELAXED);
    unsigned long long want;
    __builtin_memcpy(&want, &v, sizeof want);
    while (want > cur &&
           !__atomic_compare_exchange_n(bits, &cur, want, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
    }
  }
#endif
}

}  // namespace scree

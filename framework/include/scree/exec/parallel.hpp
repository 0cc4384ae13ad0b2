// One source, two backends: parallel loops over particles or grid nodes.
//
//   parallel_for(exec, n, f[, block])    calls f(i) for i in [0, n):
//     Device::cuda -> a CUDA kernel launch on exec.stream, `block` threads per block (only
//                     from code compiled by nvcc; kernels are templates, instantiated in
//                     the plugin or core translation unit that launches them);
//     Device::cpu  -> an OpenMP loop with exec.threads threads.
//   parallel_for_warps(exec, n, f, block) calls f(i, valid) for whole warps: on CUDA every
//     thread of the launch calls it, with valid = i < n, so that f may use warp-collective
//     operations (WarpSegment below); on the CPU f(i, true) for i in [0, n).
//
// f is a functor (or an extended lambda) whose operator() is SCREE_HD. Nothing
// virtual is called inside f: materials are template parameters of the functors.
#pragma once

#include <algorithm>
#include <cstdint>
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
/// Every thread calls f, so that whole warps reach f's warp-collective operations.
template <class F>
__global__ void for_each_warp_kernel(Index n, F f) {
  const Index i = Index(blockIdx.x) * blockDim.x + threadIdx.x;
  f(i < n ? i : n - 1, i < n);
}
/// The same with launch bounds: at most Block threads, at least MinBlocks blocks per SM
/// (which caps the registers per thread at 65536 / (Block MinBlocks)).
template <int Block, int MinBlocks, class F>
__global__ void __launch_bounds__(Block, MinBlocks) for_each_warp_kernel_bounded(Index n, F f) {
  const Index i = Index(blockIdx.x) * blockDim.x + threadIdx.x;
  f(i < n ? i : n - 1, i < n);
}
/// Blocks of `kernel` (`block` threads each) that the current device holds at once: one wave.
template <class K>
int resident_blocks(K kernel, int block) {
  int per_sm = 0, device = 0, sms = 0;
  cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, kernel, block, 0);
  cudaGetDevice(&device);
  cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device);
  return std::max(1, per_sm * sms);
}
/// Whole warps over the first *count entries of `list` (count read on the device, so the
/// launch needs no host round trip): f(list[j], j < *count), grid-stride. One thread then
/// zeroes *reset (see parallel_for_listed_warps).
template <int Block, int MinBlocks, class F>
__global__ void __launch_bounds__(Block, MinBlocks)
    for_listed_warp_kernel(const Index* list, const unsigned* count, unsigned* reset, F f) {
  const Index n = *count;
  if (reset && blockIdx.x == 0 && threadIdx.x == 0) *reset = 0;
  const Index stride = Index(gridDim.x) * blockDim.x;
  for (Index base = Index(blockIdx.x) * blockDim.x + (threadIdx.x & ~31u); base < n; base += stride) {
    const Index j = base + (threadIdx.x & 31u);
    f(list[j < n ? j : base], j < n);
  }
}
/// Persistent warps (parallel_for_queue): every thread of one wave calls f.drain().
template <int Block, int MinBlocks, class F>
__global__ void __launch_bounds__(Block, MinBlocks) drain_kernel(F f) {
  if (blockIdx.x == 0 && threadIdx.x == 0) f.reset();
  f.drain();
}
}  // namespace detail
#endif

inline constexpr int kCudaBlockSize = 256;

/// CPU loops shorter than this run on the calling thread alone. A parallel region costs
/// a fork and a barrier (microseconds when the team is hot), and a barrier waits for a
/// whole scheduler time slice (milliseconds) whenever one of its threads has been
/// descheduled -- which happens on every step when other processes share the cores. A
/// loop of a few hundred particles or nodes does less work than one such wait.
inline constexpr Index kCpuParallelMinItems = 2048;
/// The same for loops whose items are each a whole stress update with substepping
/// (parallel_for_listed_warps): tens of microseconds each, so a few dozen fill a thread.
inline constexpr Index kCpuParallelMinCostlyItems = 64;

template <class F>
void parallel_for(const Exec& ex, Index n, const F& f, int block = kCudaBlockSize) {
  if (n <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    const Index blocks = (n + block - 1) / block;
    detail::for_each_kernel<<<static_cast<unsigned>(blocks), block, 0, static_cast<cudaStream_t>(ex.stream)>>>(n, f);
    check_cuda_launch("parallel_for");
#else
    throw std::logic_error(
        "parallel_for: a CUDA launch was requested from a translation unit compiled "
        "without CUDA (compile this source with the CUDA language)");
#endif
  } else {
    (void)block;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n >= kCpuParallelMinItems) \
    num_threads(ex.threads > 0 ? ex.threads : 1)
#endif
    for (Index i = 0; i < n; ++i) f(i);
  }
}

/// parallel_for for warp-collective functors f(i, valid); `block` must be a multiple of 32.
/// Threads past the end get valid = false and the index of the last item (never to be
/// written through).
template <class F>
void parallel_for_warps(const Exec& ex, Index n, const F& f, int block = kCudaBlockSize) {
  if (n <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    const Index blocks = (n + block - 1) / block;
    detail::for_each_warp_kernel<<<static_cast<unsigned>(blocks), block, 0, static_cast<cudaStream_t>(ex.stream)>>>(
        n, f);
    check_cuda_launch("parallel_for_warps");
#else
    throw std::logic_error("parallel_for_warps: a CUDA launch from a translation unit compiled without CUDA");
#endif
  } else {
    (void)block;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n >= kCpuParallelMinItems) \
    num_threads(ex.threads > 0 ? ex.threads : 1)
#endif
    for (Index i = 0; i < n; ++i) f(i, true);
  }
}

/// parallel_for_warps with a register cap from launch bounds (see above); the CPU ignores
/// the bounds.
template <int Block, int MinBlocks, class F>
void parallel_for_warps_bounded(const Exec& ex, Index n, const F& f) {
  if (n <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    const Index blocks = (n + Block - 1) / Block;
    detail::for_each_warp_kernel_bounded<Block, MinBlocks>
        <<<static_cast<unsigned>(blocks), Block, 0, static_cast<cudaStream_t>(ex.stream)>>>(n, f);
    check_cuda_launch("parallel_for_warps_bounded");
#else
    throw std::logic_error("parallel_for_warps_bounded: a CUDA launch from a translation unit compiled without CUDA");
#endif
  } else {
    parallel_for_warps(ex, n, f);
  }
}

/// parallel_for_warps over the items list[0 .. *count) that an earlier kernel collected
/// (push_index below), with launch bounds as parallel_for_warps_bounded. `count` lives on
/// the device; the CUDA launch has `max_blocks` blocks (0: one wave of the device, as the
/// occupancy calculator gives it for the first device this runs on; at most ceil(n_max /
/// Block)) and loops over the list. `reset`, if not null, is set to zero by the kernel: the counter
/// the next collecting kernel will use (a kernel cannot clear its own counter while other
/// blocks still read it).
template <int Block, int MinBlocks, class F>
void parallel_for_listed_warps(const Exec& ex, const Index* list, const unsigned* count, unsigned* reset,
                               Index n_max, int max_blocks, const F& f) {
  if (n_max <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    static const int wave = detail::resident_blocks(detail::for_listed_warp_kernel<Block, MinBlocks, F>, Block);
    const Index blocks = std::min<Index>((n_max + Block - 1) / Block, max_blocks > 0 ? max_blocks : wave);
    detail::for_listed_warp_kernel<Block, MinBlocks>
        <<<static_cast<unsigned>(blocks), Block, 0, static_cast<cudaStream_t>(ex.stream)>>>(list, count, reset, f);
    check_cuda_launch("parallel_for_listed_warps");
#else
    throw std::logic_error("parallel_for_listed_warps: a CUDA launch from a translation unit compiled without CUDA");
#endif
  } else {
    const Index n = *count;
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, 16) if (n >= kCpuParallelMinCostlyItems) \
    num_threads(ex.threads > 0 ? ex.threads : 1)
#endif
    for (Index j = 0; j < n; ++j) f(list[j], true);
    if (reset) *reset = 0;
  }
}

/// Items that a functor takes from a queue of its own (f.size() of them, a count the device
/// holds): on CUDA persistent warps, one wave of `Block`-thread blocks (at most
/// ceil(n_max / Block)), every thread calling f.drain(), which takes items until the queue is
/// empty, so that a lane whose item is done can take the next while the other lanes of its
/// warp still work; one thread calls f.reset() (the counters of the queue's next use: a
/// kernel cannot clear its own while other blocks still read them). On the CPU f.item(j) for
/// j in [0, f.size()) (OpenMP, dynamic, as parallel_for_listed_warps), then f.reset().
template <int Block, int MinBlocks, class F>
void parallel_for_queue(const Exec& ex, Index n_max, const F& f) {
  if (n_max <= 0) return;
  if (ex.device == Device::cuda) {
#if defined(__CUDACC__)
    static const int wave = detail::resident_blocks(detail::drain_kernel<Block, MinBlocks, F>, Block);
    const Index blocks = std::min<Index>((n_max + Block - 1) / Block, wave);
    detail::drain_kernel<Block, MinBlocks><<<static_cast<unsigned>(blocks), Block, 0, static_cast<cudaStream_t>(ex.stream)>>>(f);
    check_cuda_launch("parallel_for_queue");
#else
    throw std::logic_error("parallel_for_queue: a CUDA launch from a translation unit compiled without CUDA");
#endif
  } else {
    const Index n = f.size();
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, 16) if (n >= kCpuParallelMinCostlyItems) \
    num_threads(ex.threads > 0 ? ex.threads : 1)
#endif
    for (Index j = 0; j < n; ++j) f.item(j);
    f.reset();
  }
}

/// CUDA, warp-collective: the lanes in `lanes` (a ballot every lane of the warp computed
/// alike) take consecutive values of *counter, one atomic for the warp: each lane of `lanes`
/// gets its own; `end`, in every lane, is the value after the last one taken.
#if defined(__CUDACC__)
__device__ inline unsigned warp_take(unsigned* counter, unsigned lanes, unsigned& end) {
  const unsigned lane = threadIdx.x & 31u;
  unsigned base = 0;
  if (lane == 0) base = atomicAdd(counter, static_cast<unsigned>(__popc(lanes)));
  base = __shfl_sync(0xffffffffu, base, 0);
  end = base + static_cast<unsigned>(__popc(lanes));
  return base + static_cast<unsigned>(__popc(lanes & ((1u << lane) - 1u)));
}
#endif

/// Append i to list (counter *count): one atomic per warp on CUDA for the lanes that push.
/// Every lane of the warp must call it (warp-collective), with push saying whether it adds.
SCREE_INLINE void push_index(Index* list, unsigned* count, Index i, bool push, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  const unsigned lanes = __ballot_sync(0xffffffffu, push);
  if (lanes == 0) return;
  const unsigned lane = threadIdx.x & 31u;
  const int leader = __ffs(lanes) - 1;
  unsigned base = 0;
  if (static_cast<int>(lane) == leader) base = atomicAdd(count, static_cast<unsigned>(__popc(lanes)));
  base = __shfl_sync(0xffffffffu, base, leader);
  if (push) list[base + __popc(lanes & ((1u << lane) - 1u))] = i;
#else
  if (!push) return;
  const unsigned j = serial ? (*count)++ : __atomic_fetch_add(count, 1u, __ATOMIC_RELAXED);
  list[j] = i;
#endif
}

/// *count += the number of lanes of the warp with `flag` set: one atomic per warp on CUDA,
/// none where no lane has it. Every lane of the warp must call it (warp-collective).
SCREE_INLINE void warp_count(unsigned long long* count, bool flag, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  const unsigned lanes = __ballot_sync(0xffffffffu, flag);
  if (lanes != 0 && static_cast<int>(threadIdx.x & 31u) == __ffs(lanes) - 1)
    atomicAdd(count, static_cast<unsigned long long>(__popc(lanes)));
#else
  if (!flag) return;
  if (serial) ++*count;
  else __atomic_fetch_add(count, 1ull, __ATOMIC_RELAXED);
#endif
}

/// *count += the sum of n over the warp: one atomic per warp on CUDA, none where it is 0.
/// Every lane of the warp must call it (warp-collective).
SCREE_INLINE void warp_add(unsigned long long* count, unsigned n, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  const unsigned sum = __reduce_add_sync(0xffffffffu, n);
  if (sum != 0 && (threadIdx.x & 31u) == 0) atomicAdd(count, static_cast<unsigned long long>(sum));
#else
  if (n == 0) return;
  if (serial) *count += n;
  else __atomic_fetch_add(count, static_cast<unsigned long long>(n), __ATOMIC_RELAXED);
#endif
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

/// The sum of v over the warp, valid in every lane (CUDA: warp-collective, every lane of the
/// warp calls it); v itself on the CPU. Sums that many threads add to one place go through it
/// first, one atomic per warp instead of one per thread: atomics on one address serialise.
SCREE_INLINE Real warp_sum(Real v) {
#if defined(__CUDA_ARCH__)
  for (int off = 16; off > 0; off >>= 1) v += __shfl_xor_sync(0xffffffffu, v, off);
#endif
  return v;
}

/// The index of this thread's warp in the launch (CUDA), or 0 (CPU).
SCREE_INLINE unsigned warp_index() {
#if defined(__CUDA_ARCH__)
  return (blockIdx.x * blockDim.x + threadIdx.x) >> 5;
#else
  return 0;
#endif
}

/// Whether this thread is the first lane of its warp (CUDA), or always (CPU).
SCREE_INLINE bool first_lane_of_warp() {
#if defined(__CUDA_ARCH__)
  return (threadIdx.x & 31u) == 0;
#else
  return true;
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

/// Atomic ++a on a counter, returning the value before (the one thread that sees 0 is first).
SCREE_INLINE unsigned long long atomic_fetch_increment(unsigned long long* a, bool serial) {
#if defined(__CUDA_ARCH__)
  (void)serial;
  return atomicAdd(a, 1ull);
#else
  if (serial) return (*a)++;
  return __atomic_fetch_add(a, 1ull, __ATOMIC_RELAXED);
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

/// Store v into *a when it differs (a flag or stamp that several threads may set to the
/// same value at once: relaxed atomic stores, and no store when it is already there).
SCREE_INLINE void store_if_changed(std::uint32_t* a, std::uint32_t v) {
#if defined(__CUDA_ARCH__)
  if (*reinterpret_cast<volatile std::uint32_t*>(a) != v) *reinterpret_cast<volatile std::uint32_t*>(a) = v;
#else
  if (__atomic_load_n(a, __ATOMIC_RELAXED) != v) __atomic_store_n(a, v, __ATOMIC_RELAXED);
#endif
}

/// Runs of equal keys among consecutive lanes of a warp (particles sorted by cell share
/// their stencil's nodes): sum() adds a value over each run, so that one lane (the run's
/// head) makes the atomic add to global memory for all of them. Every lane of the warp
/// must construct it and call sum() the same number of times (warp-collective, CUDA).
/// On the CPU every particle is its own run.
struct WarpSegment {
#if defined(__CUDA_ARCH__)
  int span;      ///< lanes after this one in its run
  int max_span;  ///< the largest span in the warp: the number of doubling steps needed
  bool head;     ///< first lane of its run: makes the atomic add
  __device__ explicit WarpSegment(long long key) {
    const unsigned lane = threadIdx.x & 31u;
    const long long prev = __shfl_up_sync(0xffffffffu, key, 1);
    head = lane == 0 || prev != key;
    const unsigned heads = __ballot_sync(0xffffffffu, head);
    const unsigned later = lane == 31 ? 0u : heads >> (lane + 1);  // bit j: a run starts at lane + 1 + j
    span = later ? __ffs(later) - 1 : static_cast<int>(31 - lane);
#if __CUDA_ARCH__ >= 800
    max_span = static_cast<int>(__reduce_max_sync(0xffffffffu, static_cast<unsigned>(span)));
#else
    max_span = span;
    for (int off = 16; off > 0; off >>= 1) max_span = max(max_span, __shfl_xor_sync(0xffffffffu, max_span, off));
#endif
  }
  /// The sum of v over this lane and the following lanes of its run (the run's total at
  /// its head): a segmented suffix scan by doubling.
  __device__ Real sum(Real v) const {
    for (int off = 1; off <= max_span; off <<= 1) {
      const Real o = __shfl_down_sync(0xffffffffu, v, off);
      if (off <= span) v += o;
    }
    return v;
  }
#else
  bool head = true;
  explicit WarpSegment(long long) {}
  Real sum(Real v) const { return v; }
#endif
};

/// The largest of v over the warp, valid in every lane (CUDA); v itself on the CPU.
SCREE_INLINE Real warp_max(Real v) {
#if defined(__CUDA_ARCH__)
  for (int off = 16; off > 0; off >>= 1) v = fmax(v, __shfl_xor_sync(0xffffffffu, v, off));
#endif
  return v;
}

}  // namespace scree

// ParticleSorter<D>: reorder a body's particles by the grid cell they are in, so that a
// warp's stencils overlap (its P2G adds combine before the atomics) and the gathers hit
// the cache. Ids move with the particles.
//
// Key: the flat index of the cell holding the particle (x fastest), 32 bits; a stable sort
// of the keys (CUB radix sort on the GPU) gives the permutation, through which every
// column is gathered, a few columns at a time via a scratch block. All of it is queued on
// the body's stream after the passes before it: no host round trip. The buffers are kept
// for the next sort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "scree/exec/parallel.hpp"
#include "scree/mpm/grid.hpp"
#include "scree/mpm/particle_storage.hpp"

#if defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>
#endif

namespace scree {

template <int D>
class ParticleSorter {
 public:
  void sort(ParticleStorage<D>& storage, const Exec& exec, const GridGeometry<D>& g) {
    const Index n = storage.size();
    if (n < 2) return;
    const int columns = storage.columns();
    const std::size_t un = static_cast<std::size_t>(n);
    if (keys_.size() != 2 * un) {
      keys_.resize(2 * un, exec.device);
      perm_.resize(2 * un, exec.device);
      // Small bodies gather every column in one kernel; large ones 4 at a time (memory).
      chunk_ = un * columns * sizeof(Real) <= (std::size_t(64) << 20) ? columns : std::min(columns, 4);
      scratch_.resize(static_cast<std::size_t>(chunk_) * un, exec.device);
#if defined(__CUDACC__)
      if (exec.device == Device::cuda) {
        cub::DoubleBuffer<std::uint32_t> k(keys_.data(), keys_.data() + un), v(perm_.data(), perm_.data() + un);
        std::size_t bytes = 0;
        cub::DeviceRadixSort::SortPairs(nullptr, bytes, k, v, static_cast<int>(n), 0, 32);
        temp_.resize(bytes, exec.device);
      }
#endif
      mem::synchronize(exec.device);  // the buffers' zero fill ran on the default stream
    }
    std::uint32_t* kp = keys_.data();
    std::uint32_t* pp = perm_.data();
    ParticleArrays<D> a = storage.arrays();
    const GridGeometry<D> geo = g;
    std::uint64_t cells = 1;
    for (int d = 0; d < D; ++d) cells *= static_cast<std::uint64_t>(g.n[d]);
    parallel_for(exec, n, [=] SCREE_HD(Index p) {
      std::uint32_t key = 0, s = 1;
      for (int d = 0; d < D; ++d) {
        int c = static_cast<int>(floor((a.x[d][p] - geo.origin[d]) / geo.h));
        c = c < 0 ? 0 : (c >= geo.n[d] ? geo.n[d] - 1 : c);
        key += static_cast<std::uint32_t>(c) * s;
        s *= static_cast<std::uint32_t>(geo.n[d]);
      }
      kp[p] = key;
      pp[p] = static_cast<std::uint32_t>(p);
    });
    const std::uint32_t* order = pp;
    if (exec.device == Device::cuda) {
#if defined(__CUDACC__)
      int bits = 1;
      while (bits < 32 && (std::uint64_t(1) << bits) < cells) ++bits;
      cub::DoubleBuffer<std::uint32_t> k(kp, kp + un), v(pp, pp + un);
      std::size_t bytes = temp_.size();
      cub::DeviceRadixSort::SortPairs(temp_.data(), bytes, k, v, static_cast<int>(n), 0, bits,
                                      static_cast<cudaStream_t>(exec.stream));
      check_cuda_launch("sort_by_cell: radix sort");
      order = v.Current();
#else
      throw std::logic_error("sort_by_cell: CUDA bodies need their material compiled as CUDA");
#endif
    } else {
      std::stable_sort(pp, pp + n, [kp](std::uint32_t i, std::uint32_t j) { return kp[i] < kp[j]; });
    }
    // column[i] <- column[order[i]] for every column, chunk_ columns per kernel.
    Real* base = storage.data().data();
    Real* tmp = scratch_.data();
    for (int c0 = 0; c0 < columns; c0 += chunk_) {
      const int nc = std::min(chunk_, columns - c0);
      Real* first = base + static_cast<std::size_t>(c0) * un;
      parallel_for(exec, n * nc, [=] SCREE_HD(Index j) {
        const Index c = j / n, i = j - c * n;
        tmp[j] = first[c * n + order[i]];
      });
      mem::copy_async(first, exec.device, tmp, exec.device, static_cast<std::size_t>(n * nc) * sizeof(Real),
                      exec.stream);
    }
  }

 private:
  // keys and permutation (double-buffered for the radix sort), CUB's temporary storage,
  // and a scratch block of chunk_ columns
  Buffer<std::uint32_t> keys_, perm_;
  Buffer<char> temp_;
  Buffer<Real> scratch_;
  int chunk_ = 0;
};

}  // namespace scree

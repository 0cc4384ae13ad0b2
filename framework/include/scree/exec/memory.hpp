// Memory spaces and typed buffers for the two backends.
//
// A Buffer<T> owns n elements in one memory space: host memory (CPU backend) or CUDA
// device memory (CUDA backend). Kernels get raw pointers (data()); the core's
// allocation functions below are the only place that calls cudaMalloc/cudaFree, so
// plugins and the core share one allocator and one CUDA runtime (see DESIGN.md).
#pragma once

#include <cstddef>
#include <cstring>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "scree/core/config.hpp"

namespace scree {

/// Where a run executes and where its data live.
enum class Device { cpu, cuda };

SCREE_API const char* to_string(Device d);

namespace mem {
/// An allocation that failed for want of memory: its size and memory space are in what()
/// ("out of host memory: 12.0 GB (12000000000 bytes) could not be allocated").
class SCREE_API OutOfMemory : public std::bad_alloc {
 public:
  OutOfMemory(std::size_t bytes, Device d);
  const char* what() const noexcept override { return what_.c_str(); }
  std::size_t bytes() const noexcept { return bytes_; }
  Device device() const noexcept { return device_; }

 private:
  std::size_t bytes_;
  Device device_;
  std::string what_;
};

/// Memory a run may still take in the space of `d`: bytes, and where the figure comes
/// from (for messages). Host: MemAvailable of /proc/meminfo, or less where the cgroup's
/// memory.max (cgroup v2) leaves less; device: cudaMemGetInfo's free memory of the
/// current GPU. The environment variable SCREE_TEST_FREE_MEMORY (bytes), for tests only,
/// replaces both, so that a test can exceed it without allocating anything.
struct Available {
  std::size_t bytes = 0;
  std::string source;  ///< "MemAvailable in /proc/meminfo", "memory.max of the cgroup", ...
  bool known = false;  ///< false: nothing could be read (no limit is applied)
};
SCREE_API Available available(Device d);
/// "1.5 GB", "312 MB", "64 kB" (decimal units, 3 significant digits).
SCREE_API std::string format_bytes(double bytes);

/// Allocate/free/copy raw bytes in the memory of `d`. Throw OutOfMemory when the memory is
/// not there, std::runtime_error on another failure (with the CUDA error string), or when
/// the CUDA backend is not compiled in.
SCREE_API void* allocate(std::size_t bytes, Device d);
SCREE_API void deallocate(void* p, Device d) noexcept;
SCREE_API void copy(void* dst, Device dst_space, const void* src, Device src_space, std::size_t bytes);
/// `height` rows of `width` bytes, each `src_pitch` apart in src and `dst_pitch` in dst.
SCREE_API void copy_2d(void* dst, std::size_t dst_pitch, Device dst_space, const void* src, std::size_t src_pitch,
                       Device src_space, std::size_t width, std::size_t height);
/// The same, ordered on `stream` (a cudaStream_t) after the work already queued there and
/// asynchronous to the host; a plain memcpy between host buffers. Host memory must stay
/// valid (and, for true overlap, be pinned: allocate_pinned) until the stream reaches it.
SCREE_API void copy_async(void* dst, Device dst_space, const void* src, Device src_space, std::size_t bytes,
                          void* stream);
/// Page-locked host memory (CUDA builds; plain host memory otherwise), for asynchronous
/// copies from the device.
SCREE_API void* allocate_pinned(std::size_t bytes);
SCREE_API void deallocate_pinned(void* p) noexcept;
SCREE_API void fill_zero(void* p, std::size_t bytes, Device d);
/// Whether this build has the CUDA backend and at least one usable GPU.
SCREE_API bool cuda_compiled();
SCREE_API bool cuda_available();
/// The CUDA devices this process sees (0 without any, or without the CUDA backend).
SCREE_API int cuda_device_count();
/// Make device i this process's (before anything is allocated): one GPU per rank.
SCREE_API void select_cuda_device(int i);
/// Block until all work queued on the device has finished (no-op for the CPU).
SCREE_API void synchronize(Device d);
/// Bytes currently allocated through this module on `d` and their peak (for benchmarks).
SCREE_API std::size_t bytes_in_use(Device d);
SCREE_API std::size_t peak_bytes(Device d);
SCREE_API void reset_peak(Device d);
}  // namespace mem

template <class T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(std::size_t n, Device d) : device_(d) { resize(n); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& o) noexcept { swap(o); }
  Buffer& operator=(Buffer&& o) noexcept {
    swap(o);
    return *this;
  }
  ~Buffer() { release(); }

  void swap(Buffer& o) noexcept {
    std::swap(ptr_, o.ptr_);
    std::swap(n_, o.n_);
    std::swap(device_, o.device_);
  }
  /// Reallocate to n elements (contents are not preserved; new memory is zeroed).
  void resize(std::size_t n) {
    release();
    if (n) {
      ptr_ = static_cast<T*>(mem::allocate(n * sizeof(T), device_));
      mem::fill_zero(ptr_, n * sizeof(T), device_);
    }
    n_ = n;
  }
  void resize(std::size_t n, Device d) {
    release();
    device_ = d;
    resize(n);
  }
  void zero() {
    if (n_) mem::fill_zero(ptr_, n_ * sizeof(T), device_);
  }
  T* data() { return ptr_; }
  const T* data() const { return ptr_; }
  std::size_t size() const { return n_; }
  Device device() const { return device_; }

  void copy_from_host(const T* src, std::size_t n) {
    if (n != n_) resize(n);
    if (n) mem::copy(ptr_, device_, src, Device::cpu, n * sizeof(T));
  }
  void copy_from_host(const std::vector<T>& v) { copy_from_host(v.data(), v.size()); }
  void copy_to_host(T* dst) const {
    if (n_) mem::copy(dst, Device::cpu, ptr_, device_, n_ * sizeof(T));
  }
  std::vector<T> to_host() const {
    std::vector<T> v(n_);
    copy_to_host(v.data());
    return v;
  }

 private:
  void release() noexcept {
    if (ptr_) mem::deallocate(ptr_, device_);
    ptr_ = nullptr;
    n_ = 0;
  }
  T* ptr_ = nullptr;
  std::size_t n_ = 0;
  Device device_ = Device::cpu;
};

}  // namespace scree

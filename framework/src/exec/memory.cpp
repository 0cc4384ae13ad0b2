// Allocation and copies for both memory spaces. The only place that calls the CUDA
// runtime's allocator, so every buffer of the core and of plugins goes through one
// runtime (DESIGN.md: shared cudart, one primary context).
#include "scree/exec/memory.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <new>
#include <stdexcept>
#include <sstream>
#include <string>
#include <unordered_map>

#include "scree/exec/parallel.hpp"

#if defined(SCREE_HAVE_CUDA)
#include <cuda_runtime_api.h>
#endif

namespace scree {

const char* to_string(Device d) { return d == Device::cuda ? "cuda" : "cpu"; }

namespace {
struct Usage {
  std::mutex m;
  std::unordered_map<void*, std::size_t> sizes;
  std::size_t in_use = 0, peak = 0;
};
Usage& usage(Device d) {
  static Usage u[2];
  return u[d == Device::cuda ? 1 : 0];
}
void track_alloc(Device d, void* p, std::size_t bytes) {
  auto& u = usage(d);
  std::lock_guard lock(u.m);
  u.sizes[p] = bytes;
  u.in_use += bytes;
  if (u.in_use > u.peak) u.peak = u.in_use;
}
void track_free(Device d, void* p) {
  auto& u = usage(d);
  std::lock_guard lock(u.m);
  auto it = u.sizes.find(p);
  if (it != u.sizes.end()) {
    u.in_use -= it->second;
    u.sizes.erase(it);
  }
}
/// The number after `key` at the start of a line of file `path` ("MemAvailable: 123 kB" of
/// /proc/meminfo), times `unit`; or, key null, the file's first word as a number ("max"
/// and a missing file or key: false).
bool read_number(const char* path, const char* key, double unit, double& out) {
  std::ifstream f(path);
  if (!f) return false;
  std::string line;
  while (std::getline(f, line)) {
    if (key && line.rfind(key, 0) != 0) continue;
    std::istringstream in(key ? line.substr(std::strlen(key)) : line);
    double v = 0;
    if (!(in >> v)) return false;
    out = v * unit;
    return true;
  }
  return false;
}
#if defined(SCREE_HAVE_CUDA)
void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(e));
}
#endif
[[noreturn]] void no_cuda() {
  throw std::runtime_error("this build of Scree has no CUDA backend (rebuild with -DSCREE_WITH_CUDA=ON)");
}
}  // namespace

void check_cuda_launch(const char* what) {
#if defined(SCREE_HAVE_CUDA)
  check(cudaGetLastError(), what);
#else
  (void)what;
#endif
}

namespace mem {

OutOfMemory::OutOfMemory(std::size_t bytes, Device d)
    : bytes_(bytes),
      device_(d),
      what_(std::string("out of ") + (d == Device::cuda ? "device (GPU)" : "host") + " memory: " +
            format_bytes(static_cast<double>(bytes)) + " (" + std::to_string(bytes) + " bytes) could not be allocated") {}

std::string format_bytes(double bytes) {
  static const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 999.5 && u < 6) {
    bytes /= 1000;
    ++u;
  }
  char buf[32];
  if (u == 0) std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  else std::snprintf(buf, sizeof buf, bytes < 9.995 ? "%.2f %s" : (bytes < 99.95 ? "%.1f %s" : "%.0f %s"), bytes, units[u]);
  return buf;
}

Available available(Device d) {
  Available a;
  if (const char* t = std::getenv("SCREE_TEST_FREE_MEMORY"); t && *t) {  // tests only (memory.hpp)
    a.bytes = static_cast<std::size_t>(std::strtod(t, nullptr));
    a.source = "SCREE_TEST_FREE_MEMORY, set for a test";
    a.known = true;
    return a;
  }
  if (d == Device::cuda) {
#if defined(SCREE_HAVE_CUDA)
    std::size_t free = 0, total = 0;
    if (cudaMemGetInfo(&free, &total) == cudaSuccess) {
      a.bytes = free;
      a.source = "free memory of the GPU (cudaMemGetInfo)";
      a.known = true;
    } else {
      cudaGetLastError();  // no device: no limit known
    }
#endif
    return a;
  }
  double v = 0;
  if (read_number("/proc/meminfo", "MemAvailable:", 1024, v)) {
    a.bytes = static_cast<std::size_t>(v);
    a.source = "MemAvailable in /proc/meminfo";
    a.known = true;
  }
  // cgroup v2: the group's limit less what it uses ("max": no limit), its inactive page
  // cache aside (reclaimed before the limit is hit, as MemAvailable counts it).
  double limit = 0, used = 0, cache = 0;
  if (read_number("/sys/fs/cgroup/memory.max", nullptr, 1, limit) &&
      read_number("/sys/fs/cgroup/memory.current", nullptr, 1, used)) {
    read_number("/sys/fs/cgroup/memory.stat", "inactive_file ", 1, cache);
    const double left = std::max(0.0, limit - std::max(0.0, used - cache));
    if (!a.known || left < static_cast<double>(a.bytes)) {
      a.bytes = static_cast<std::size_t>(left);
      a.source = "memory.max less memory.current of the cgroup (/sys/fs/cgroup)";
      a.known = true;
    }
  }
  return a;
}

void* allocate(std::size_t bytes, Device d) {
  if (bytes == 0) return nullptr;
  void* p = nullptr;
  if (d == Device::cpu) {
    // 64-byte alignment: whole cache lines, and SIMD-friendly.
    p = std::aligned_alloc(64, (bytes + 63) / 64 * 64);
    if (!p) throw OutOfMemory(bytes, d);
  } else {
#if defined(SCREE_HAVE_CUDA)
    if (const cudaError_t e = cudaMalloc(&p, bytes); e == cudaErrorMemoryAllocation) {
      cudaGetLastError();  // clear it: the run may report and go on
      throw OutOfMemory(bytes, d);
    } else {
      check(e, "cudaMalloc");
    }
#else
    no_cuda();
#endif
  }
  track_alloc(d, p, bytes);
  return p;
}

void deallocate(void* p, Device d) noexcept {
  if (!p) return;
  track_free(d, p);
  if (d == Device::cpu) {
    std::free(p);
  } else {
#if defined(SCREE_HAVE_CUDA)
    cudaFree(p);
#endif
  }
}

void copy(void* dst, Device dst_space, const void* src, Device src_space, std::size_t bytes) {
  if (bytes == 0) return;
  if (dst_space == Device::cpu && src_space == Device::cpu) {
    std::memcpy(dst, src, bytes);
    return;
  }
#if defined(SCREE_HAVE_CUDA)
  check(cudaMemcpy(dst, src, bytes, cudaMemcpyDefault), "cudaMemcpy");
#else
  no_cuda();
#endif
}

void copy_2d(void* dst, std::size_t dst_pitch, Device dst_space, const void* src, std::size_t src_pitch,
             Device src_space, std::size_t width, std::size_t height) {
  if (width == 0 || height == 0) return;
  if (dst_space == Device::cpu && src_space == Device::cpu) {
    for (std::size_t r = 0; r < height; ++r)
      std::memcpy(static_cast<char*>(dst) + r * dst_pitch, static_cast<const char*>(src) + r * src_pitch, width);
    return;
  }
#if defined(SCREE_HAVE_CUDA)
  check(cudaMemcpy2D(dst, dst_pitch, src, src_pitch, width, height, cudaMemcpyDefault), "cudaMemcpy2D");
#else
  no_cuda();
#endif
}

void copy_async(void* dst, Device dst_space, const void* src, Device src_space, std::size_t bytes, void* stream) {
  if (bytes == 0) return;
  if (dst_space == Device::cpu && src_space == Device::cpu) {
    std::memcpy(dst, src, bytes);
    return;
  }
#if defined(SCREE_HAVE_CUDA)
  check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDefault, static_cast<cudaStream_t>(stream)), "cudaMemcpyAsync");
#else
  (void)stream;
  no_cuda();
#endif
}

void* allocate_pinned(std::size_t bytes) {
  if (bytes == 0) return nullptr;
#if defined(SCREE_HAVE_CUDA)
  if (cuda_available()) {
    void* p = nullptr;
    check(cudaMallocHost(&p, bytes), "cudaMallocHost");
    return p;
  }
#endif
  void* p = std::aligned_alloc(64, (bytes + 63) / 64 * 64);
  if (!p) throw OutOfMemory(bytes, Device::cpu);
  return p;
}

void deallocate_pinned(void* p) noexcept {
  if (!p) return;
#if defined(SCREE_HAVE_CUDA)
  cudaPointerAttributes a{};
  if (cudaPointerGetAttributes(&a, p) == cudaSuccess && a.type == cudaMemoryTypeHost) {
    cudaFreeHost(p);
    return;
  }
  cudaGetLastError();  // a plain host pointer: clear the error it may leave
#endif
  std::free(p);
}

void fill_zero(void* p, std::size_t bytes, Device d) {
  if (bytes == 0) return;
  if (d == Device::cpu) {
    std::memset(p, 0, bytes);
    return;
  }
#if defined(SCREE_HAVE_CUDA)
  check(cudaMemset(p, 0, bytes), "cudaMemset");
#else
  no_cuda();
#endif
}

bool cuda_compiled() {
#if defined(SCREE_HAVE_CUDA)
  return true;
#else
  return false;
#endif
}

int cuda_device_count() {
#if defined(SCREE_HAVE_CUDA)
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return n;
#else
  return 0;
#endif
}

void select_cuda_device(int i) {
#if defined(SCREE_HAVE_CUDA)
  check(cudaSetDevice(i), "cudaSetDevice");
#else
  (void)i;
  no_cuda();
#endif
}

bool cuda_available() {
#if defined(SCREE_HAVE_CUDA)
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();  // clear the sticky "no device" error
    return false;
  }
  return n > 0;
#else
  return false;
#endif
}

void synchronize(Device d) {
#if defined(SCREE_HAVE_CUDA)
  if (d == Device::cuda) check(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
#else
  (void)d;
#endif
}

std::size_t bytes_in_use(Device d) {
  auto& u = usage(d);
  std::lock_guard lock(u.m);
  return u.in_use;
}
std::size_t peak_bytes(Device d) {
  auto& u = usage(d);
  std::lock_guard lock(u.m);
  return u.peak;
}
void reset_peak(Device d) {
  auto& u = usage(d);
  std::lock_guard lock(u.m);
  u.peak = u.in_use;
}

}  // namespace mem
}  // namespace scree

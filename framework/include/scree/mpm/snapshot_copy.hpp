// SnapshotCopy: a copy of a particle block to the host that does not stop the run.
//
// The block is copied on the device first (microseconds, ordered after the queued passes
// on the compute stream), so the next steps may overwrite it at once; the copy to pinned
// host memory then runs on a copy stream beside them, and only the thread that waits for
// it (the output thread) waits. Pinned buffers are reused: page-locking memory costs
// milliseconds, and would stop the run at every snapshot.
#pragma once

#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "scree/exec/memory.hpp"

namespace scree {

#if defined(__CUDACC__)
namespace detail {
inline void cuda_ok(cudaError_t e) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error: ") + cudaGetErrorString(e));
}
}  // namespace detail
#endif

class SnapshotCopy {
 public:
  SnapshotCopy() = default;
  SnapshotCopy(const SnapshotCopy&) = delete;
  SnapshotCopy& operator=(const SnapshotCopy&) = delete;
  ~SnapshotCopy() {
#if defined(__CUDACC__)
    if (stage_free_) cudaEventDestroy(static_cast<cudaEvent_t>(stage_free_));
#endif
    for (Real* p : pinned_free_) mem::deallocate_pinned(p);
  }

#if defined(__CUDACC__)
  /// Queue the copy of the device block `data` (on `compute`, then `copy`). Returns a
  /// function that waits for the copy and calls use(host block), then recycles the buffer.
  std::function<void(const std::function<void(const Real*)>&)> start(const Buffer<Real>& data, void* compute_stream,
                                                                     void* copy_stream, Device device) {
    const std::size_t bytes = data.size() * sizeof(Real);
    auto compute = static_cast<cudaStream_t>(compute_stream), copy = static_cast<cudaStream_t>(copy_stream);
    if (stage_.size() != data.size()) {
      stage_.resize(data.size(), device);
      mem::synchronize(device);
    }
    if (stage_free_) detail::cuda_ok(cudaStreamWaitEvent(compute, static_cast<cudaEvent_t>(stage_free_), 0));
    else detail::cuda_ok(cudaEventCreateWithFlags(reinterpret_cast<cudaEvent_t*>(&stage_free_), cudaEventDisableTiming));
    detail::cuda_ok(cudaMemcpyAsync(stage_.data(), data.data(), bytes, cudaMemcpyDeviceToDevice, compute));
    cudaEvent_t staged, copied;
    detail::cuda_ok(cudaEventCreateWithFlags(&staged, cudaEventDisableTiming));
    detail::cuda_ok(cudaEventCreateWithFlags(&copied, cudaEventDisableTiming));
    detail::cuda_ok(cudaEventRecord(staged, compute));
    detail::cuda_ok(cudaStreamWaitEvent(copy, staged, 0));
    Real* host = acquire_pinned(bytes);
    detail::cuda_ok(cudaMemcpyAsync(host, stage_.data(), bytes, cudaMemcpyDeviceToHost, copy));
    detail::cuda_ok(cudaEventRecord(copied, copy));
    detail::cuda_ok(cudaEventRecord(static_cast<cudaEvent_t>(stage_free_), copy));
    cudaEventDestroy(staged);  // released once it has completed
    return [this, host, copied](const std::function<void(const Real*)>& use) {
      cudaEventSynchronize(copied);
      cudaEventDestroy(copied);
      use(host);
      release_pinned(host);
    };
  }
#endif

 private:
  Real* acquire_pinned(std::size_t bytes) {
    {
      std::lock_guard lock(pinned_mutex_);
      if (!pinned_free_.empty()) {
        Real* p = pinned_free_.back();
        pinned_free_.pop_back();
        return p;
      }
    }
    return static_cast<Real*>(mem::allocate_pinned(bytes));
  }
  void release_pinned(Real* p) {
    std::lock_guard lock(pinned_mutex_);
    pinned_free_.push_back(p);
  }

  // the device copy of the particle block, and the event after which the copy stream has
  // read it (the next snapshot's device copy waits for it)
  Buffer<Real> stage_;
  void* stage_free_ = nullptr;
  std::mutex pinned_mutex_;
  std::vector<Real*> pinned_free_;
};

}  // namespace scree

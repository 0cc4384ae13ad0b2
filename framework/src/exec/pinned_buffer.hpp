// Page-locked host memory that grows to the largest size asked of it: the host side of
// copies between the device and MPI (a halo slab), which the driver moves at the bus's
// speed instead of through its own staging buffer as for pageable memory.
#pragma once

#include <cstddef>
#include <utility>

#include "scree/exec/memory.hpp"

namespace scree {

template <class T>
class PinnedBuffer {
 public:
  PinnedBuffer() = default;
  PinnedBuffer(const PinnedBuffer&) = delete;
  PinnedBuffer& operator=(const PinnedBuffer&) = delete;
  ~PinnedBuffer() { mem::deallocate_pinned(ptr_); }

  /// At least n elements (contents are not preserved when it grows).
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    mem::deallocate_pinned(ptr_);
    ptr_ = nullptr;
    capacity_ = 0;
    ptr_ = static_cast<T*>(mem::allocate_pinned(n * sizeof(T)));
    capacity_ = n;
  }
  T* data() noexcept { return ptr_; }

 private:
  T* ptr_ = nullptr;
  std::size_t capacity_ = 0;
};

}  // namespace scree

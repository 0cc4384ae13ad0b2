// StepGraphs: CUDA graphs of two time steps, one for each starting parity, captured the
// first time they are needed and replayed after that: a replayed kernel node costs a
// fraction of a launch from the host, which small cases' steps are made of
// (docs/performance.md, the cost model). Captured again after clear() (when the
// kernels a step launches change, e.g. the stress split switched).
#pragma once

#include <functional>

namespace scree {

class StepGraphs {
 public:
  explicit StepGraphs(void* stream);  ///< a cudaStream_t (null: no graphs, no CUDA)
  ~StepGraphs();
  StepGraphs(const StepGraphs&) = delete;
  StepGraphs& operator=(const StepGraphs&) = delete;

  /// Replay the graph of parity p on the stream; the first time, capture it from
  /// `record`, which queues the two steps' work on the stream (and runs nothing).
  void replay(int p, const std::function<void()>& record);
  /// Forget the captured graphs.
  void clear();

 private:
  void* stream_;
  void* graphs_[2] = {nullptr, nullptr};
};

}  // namespace scree

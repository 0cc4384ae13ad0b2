// StepGraphs (see step_graphs.hpp).
#include "step_graphs.hpp"

#include <stdexcept>
#include <string>

#if defined(SCREE_HAVE_CUDA)
#include <cuda_runtime_api.h>
#endif

namespace scree {

#if defined(SCREE_HAVE_CUDA)
namespace {
void cuda_check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(e));
}
}  // namespace
#endif

StepGraphs::StepGraphs(void* stream) : stream_(stream) {}

StepGraphs::~StepGraphs() { clear(); }

void StepGraphs::replay(int p, const std::function<void()>& record) {
#if defined(SCREE_HAVE_CUDA)
  auto stream = static_cast<cudaStream_t>(stream_);
  if (!graphs_[p]) {
    cudaGraph_t graph;
    cuda_check(cudaStreamBeginCapture(stream, cudaStreamCaptureModeThreadLocal), "cudaStreamBeginCapture");
    record();
    cuda_check(cudaStreamEndCapture(stream, &graph), "cudaStreamEndCapture");
    cudaGraphExec_t exec;
    cuda_check(cudaGraphInstantiate(&exec, graph, 0), "cudaGraphInstantiate");
    cudaGraphDestroy(graph);
    graphs_[p] = exec;
  }
  cuda_check(cudaGraphLaunch(static_cast<cudaGraphExec_t>(graphs_[p]), stream), "cudaGraphLaunch");
#else
  (void)p;
  (void)record;
  throw std::logic_error("StepGraphs: this build has no CUDA backend");
#endif
}

void StepGraphs::clear() {
#if defined(SCREE_HAVE_CUDA)
  for (auto& g : graphs_)
    if (g) {
      cudaGraphExecDestroy(static_cast<cudaGraphExec_t>(g));
      g = nullptr;
    }
#endif
}

}  // namespace scree

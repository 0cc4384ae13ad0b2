// Diagnostics of GPU diagnostic builds only (CMake option SCREE_REPORT_CYCLES = C; off and
// empty otherwise): where a slow particle pass spends its clock cycles.
//
// A material's stress update may note what it did for its thread (report_work()): how many
// rate evaluations (substeps) it took and which of its paths it took. The particle pass
// (particle_pass.hpp) reads the notes of its warp's lanes back and prints one line for every
// warp whose pass takes more than C clock cycles: the cycles, the lanes that had work, the
// sum and the largest of their substeps and the lanes per path. Cycles that follow the largest
// count mean one slow update; cycles that follow the sum mean the lanes' paths diverged and
// ran one after another. Printing happens after the pass is timed, once per slow warp; the
// notes cost a store per update.
#pragma once

#include "scree/core/config.hpp"

#if defined(SCREE_REPORT_CYCLES) && defined(__CUDACC__)
#include <cstdio>

namespace scree::diag {

inline constexpr unsigned kReportSlots = 1u << 20;  ///< threads of one launch noted (wraps beyond)
/// One note per thread of the running launch (a copy per translation unit: the pass and the
/// material it instantiates share one).
static __device__ unsigned report_substeps[kReportSlots];
static __device__ unsigned report_paths[kReportSlots];

/// This thread's slot.
__device__ __forceinline__ unsigned report_slot() { return (blockIdx.x * blockDim.x + threadIdx.x) % kReportSlots; }

/// Clears this thread's note (the pass, before the update).
__device__ __forceinline__ void report_clear() {
  report_substeps[report_slot()] = 0;
  report_paths[report_slot()] = 0;
}

}  // namespace scree::diag
#endif

namespace scree::diag {
/// A stress update's note (no-op outside diagnostic device code): `substeps` rate
/// evaluations, `paths` a bit mask of the material's own paths.
SCREE_INLINE void report_work(unsigned substeps, unsigned paths) {
#if defined(SCREE_REPORT_CYCLES) && defined(__CUDA_ARCH__)
  report_substeps[report_slot()] = substeps;
  report_paths[report_slot()] = paths;
#else
  (void)substeps;
  (void)paths;
#endif
}
}  // namespace scree::diag

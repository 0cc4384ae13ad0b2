// The 2D phaseTransition stress kernels (linear shape functions), alone in one unit:
// what measure/ptx-line-counts.sh compiles for ptxas statistics and PTX line counts, in a
// minute instead of the whole plugin's five (docs/gpu.md, "Speed").
#include "../../materials/phaseTransition/PhaseTransition.hpp"
#include "scree/exec/parallel.hpp"
#include "scree/mpm/particle_pass.hpp"

using namespace scree;
using PT = materials::PhaseTransition;
using ElasticOnly = ParticlePass<2, ShapeLinear, PT, kAllPhases, true>;
using Whole = ParticlePass<2, ShapeLinear, PT, kAllPhases, false>;
using Deferred = DeferredStress<2, ShapeLinear, PT, false>;
using Scatter = ParticlePass<2, ShapeLinear, PT, kAnyScatter, false>;
// material_body.hpp: the split's elastic-only kernel (10 blocks of 64 per SM), the deferred
// points' kernels (the whole pass over them, or their updates in turns and their scatter) and
// the unsplit whole pass (6 blocks of 64)
template __global__ void detail::for_each_warp_kernel_bounded<64, 10, ElasticOnly>(Index, ElasticOnly);
template __global__ void detail::for_listed_warp_kernel<64, 6, Whole>(const Index*, const unsigned*, unsigned*, Whole);
template __global__ void detail::for_each_warp_kernel_bounded<64, 6, Whole>(Index, Whole);
template __global__ void detail::drain_kernel<64, 6, Deferred>(Deferred);
template __global__ void detail::for_listed_warp_kernel<256, 1, Scatter>(const Index*, const unsigned*, unsigned*, Scatter);

// Scree: compile-time configuration shared by the core, plugins and kernels.
//
// SCREE_HD marks functions that run on both backends (CUDA device and CPU host).
// SCREE_API marks symbols the core library exports to plugins (everything else is
// hidden: plugins and the core are built with -fvisibility=hidden, see DESIGN.md).
#pragma once

#include <cstdint>

#if defined(__CUDACC__)
#define SCREE_HD __host__ __device__
#define SCREE_DEVICE __device__
#define SCREE_INLINE __host__ __device__ __forceinline__
#else
#define SCREE_HD
#define SCREE_DEVICE
#define SCREE_INLINE inline
#endif

// SCREE_UNROLL: unroll the next loop (nvcc's `#pragma unroll`; GCC's own spelling on the
// CPU, where the plain pragma is unknown).
#if defined(__CUDACC__)
#define SCREE_UNROLL _Pragma("unroll")
#elif defined(__GNUC__) && !defined(__clang__)
#define SCREE_UNROLL _Pragma("GCC unroll 32")
#else
#define SCREE_UNROLL
#endif

#if defined(_WIN32)
#define SCREE_API __declspec(dllexport)
#else
#define SCREE_API __attribute__((visibility("default")))
#endif

namespace scree {

/// Floating-point type of all physical quantities (double precision by default).
using Real = double;
/// Particle and node indices. 64-bit so that 10^7..10^9 particles never overflow.
using Index = std::int64_t;

/// Version of the binary interface between the core and plugins. A plugin built
/// against another version is refused on load with a message naming both.
inline constexpr int kPluginAbiVersion = 7;  // 2: Body::save_state, restore_state (checkpoints); 3: Body::replace_state (migration); 4: PassParams split, EnergyLedger by term; 5: PluginEntry::output_fields as FieldInfo (units), compact dictionary Item and Entry (accessors, 12-byte SourcePos); 6: Writer pieces (begin_frame, write_piece, end_frame); 7: BodySetup::ids

}  // namespace scree

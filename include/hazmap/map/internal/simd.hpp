#pragma once
// Internal to the library's SIMD kernels (src/map, and src/stereo's c2f matcher): no public
// header includes it.
// The one place that says how the per-point loops (the map's, c2f's) use SIMD: the wider
// instruction set they target, how the CPU is asked for it, and the vector types they are
// written in.
//
// One target, x86-64-v3 (AVX2, FMA, POPCNT, ...) over the x86-64 baseline, reached in
// one of two ways:
//   HAZMAP_KERNEL        a loop written plainly or in the vector types below. With GCC on
//                        x86-64 it is compiled twice (target_clones), for x86-64-v3 and for
//                        the baseline, and the loader picks the one the CPU runs.
//   HAZMAP_AVX2_KERNEL   a kernel in AVX2 intrinsics (shuffles and masks the compiler does
//                        not find on its own), next to a portable version; the caller picks
//                        with simd::has_avx2(), which asks the CPU once.
// Either way one portable binary, and full SIMD width where the CPU has it.

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HAZMAP_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define HAZMAP_KERNEL
#endif

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
/// Defined where the AVX2 intrinsic kernels are compiled (GCC / Clang on x86-64).
#define HAZMAP_HAVE_AVX2 1
#define HAZMAP_AVX2_KERNEL __attribute__((target("avx2,fma,popcnt")))
#endif

namespace hazmap {
namespace simd {

/// Whether the CPU runs the HAZMAP_AVX2_KERNEL kernels (AVX2, FMA and POPCNT); asked once.
inline bool has_avx2() {
#ifdef HAZMAP_HAVE_AVX2
  static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                          __builtin_cpu_supports("popcnt");
  return yes;
#else
  return false;
#endif
}

// GCC / Clang vector extensions: SSE on x86-64, NEON on ARM, AVX2 in a HAZMAP_KERNEL's
// x86-64-v3 clone. The kernels' lane counts (kRunPointLanes, kRunLanes)
// are static_asserted against these where they are used.
typedef float Vec4 __attribute__((vector_size(16)));  ///< four float lanes
typedef int Mask4 __attribute__((vector_size(16)));   ///< a compare result of Vec4
typedef float Vec8 __attribute__((vector_size(32)));  ///< eight float lanes
typedef int Int8 __attribute__((vector_size(32)));    ///< eight int lanes: slots, masks, lane numbers

}  // namespace simd
}  // namespace hazmap

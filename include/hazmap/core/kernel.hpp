#pragma once
// HAZMAP_KERNEL marks the few per-point loops of the map. With GCC on x86-64 each is
// compiled twice, for AVX2 + FMA (x86-64-v3) and for the baseline, and the loader picks
// the one the CPU runs: one portable binary, and full SIMD width where it exists.

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HAZMAP_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define HAZMAP_KERNEL
#endif
